// Numbers as text in messages, reports and tables: the one formatter of
// Gonio. (File formats with their own number syntax keep their writers:
// io/photometric/ies.h format_ies_number, the EULUMDAT writer's fields.)
#pragma once

#include <cstdint>
#include <string>

namespace gonio {

// At most `significant_digits` significant digits, the shorter of fixed and
// exponent notation, no trailing zeros: printf's "%.*g" ("0.1", "29919.9",
// "1e+07", "nan", "inf"). The default 6 is printf's "%g".
std::string format_number(double v, int significant_digits = 6);

// Exactly `decimals` decimals: printf's "%.*f", except that a value that
// rounds to zero prints without a minus sign ("0.0", not "-0.0").
std::string format_fixed(double v, int decimals);

// A moment as UTC text: strftime's `format` ("%Y-%m-%d", "%H:%M:%S UTC",
// "%Y-%m-%dT%H:%M:%SZ", ...) of `unix_seconds` (seconds since 1970, UTC),
// at most 63 bytes. The one way Gonio writes dates and times.
// (GCC and clang check `format` at each call, as strftime's.)
__attribute__((format(strftime, 2, 0))) std::string format_utc(std::int64_t unix_seconds, const char* format);

// Now, in seconds since 1970 (UTC), for the dates Gonio writes into files
// (GLDF creation times and ZIP entries, the simulated file's issue date):
// $SOURCE_DATE_EPOCH when it holds a whole number of seconds ≥ 0 (the
// reproducible-builds.org convention: the same inputs give the same bytes),
// else the clock.
std::int64_t now_unix();

}  // namespace gonio
