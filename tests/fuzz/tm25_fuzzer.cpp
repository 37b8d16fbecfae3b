// libFuzzer harness: the IES TM-25 ray-file reader (io::parse_tm25) on
// arbitrary bytes, and, for what it accepts, the rays' sums and the TM-25
// writer, whose output must parse again to the same rays and, written once
// more, give the same bytes. A crash, a sanitizer report or a broken round
// trip is a finding (scripts/fuzz.sh).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "io/photometric/tm25.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace gonio;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  Result<io::Tm25RaySet> r = io::parse_tm25(bytes, "fuzz.tm25ray");
  if (!r.ok()) return 0;
  const io::Tm25RaySet& s = *r;
  for (std::size_t i = 0; i < s.ray_count(); ++i)
    if (std::abs(length(s.direction(i)) - 1.0) > 1e-5) fuzz::finding("parse_tm25 returned a direction that is not unit");
  (void)s.total_radiant_flux_w();
  (void)s.total_luminous_flux_lm();
  Result<std::string> written = io::write_tm25(s);
  if (!written.ok()) fuzz::finding("write_tm25 refused what parse_tm25 read: " + to_string(written.error()));
  Result<io::Tm25RaySet> again = io::parse_tm25(*written, "fuzz-written.tm25ray");
  if (!again.ok()) fuzz::finding("write_tm25 wrote a file parse_tm25 refuses: " + to_string(again.error()));
  if (again->items != s.items) fuzz::finding("write_tm25 -> parse_tm25 changed the rays");
  Result<std::string> twice = io::write_tm25(*again);
  if (!twice.ok() || *twice != *written) fuzz::finding("write_tm25 -> parse_tm25 -> write_tm25 changed the file");
  return 0;
}
