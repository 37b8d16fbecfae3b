// The inclusive bounds of the application's numeric options, shared by the
// command line's parser (tools/cli/cli.h) and the application's own checks
// of the plain option structs (tools/run/simulate.h, preview_output.h), so
// that a front end without argv meets the same limits and the same words.
#pragma once

#include <string>

#include "photometry/diagnostics.h"

namespace gonio::app {

template <typename T>
struct Bounds {
  T min, max;
};

// "--NAME must be between MIN and MAX, got VALUE" where it is not (the
// command line parser's wording).
Status check_range(const std::string& name, long long value, Bounds<long long> bounds);
Status check_range(const std::string& name, double value, Bounds<double> bounds);

}  // namespace gonio::app
