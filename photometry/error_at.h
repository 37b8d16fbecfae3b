// An error at a line of an input file: the one helper for readers that know
// the line (design files, model sidecars, optimize's variables). Kept out of
// photometry/diagnostics.h, which nearly every file includes, so that adding
// it rebuilt only its users.
#pragma once

#include <string>

#include "photometry/diagnostics.h"

namespace gonio {

// Printed "FILE:LINE: message" (to_string(Error)); LINE 0: the whole file, as
// make_error(file, message). Out of line, as make_error is, for GCC 12's false
// maybe-uninitialized warnings about Error temporaries built inline.
Error make_error(const std::string& file, int line, std::string message);

}  // namespace gonio
