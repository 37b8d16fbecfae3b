#include "tools/run/option_bounds.h"

#include "photometry/format.h"

namespace gonio::app {

Status check_range(const std::string& name, long long value, Bounds<long long> bounds) {
  if (value >= bounds.min && value <= bounds.max) return Ok{};
  return make_error("--" + name + " must be between " + std::to_string(bounds.min) + " and " +
                    std::to_string(bounds.max) + ", got " + std::to_string(value));
}

Status check_range(const std::string& name, double value, Bounds<double> bounds) {
  if (value >= bounds.min && value <= bounds.max) return Ok{};
  return make_error("--" + name + " must be between " + format_number(bounds.min) + " and " +
                    format_number(bounds.max) + ", got " + format_number(value));
}

}  // namespace gonio::app
