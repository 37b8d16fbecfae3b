#include "tools/run/console.h"

#include <unistd.h>

#include <cstdio>

#include "gonio/version.h"

namespace gonio::cli {

void print_error(const std::string& message) {
  std::fprintf(stderr, "%s: %s\n", kProgramName, message.c_str());
}

void print_error(const Error& error) { print_error(to_string(error)); }

void print_warning(const std::string& message) {
  std::fprintf(stderr, "%s: warning: %s\n", kProgramName, message.c_str());
}

std::string format_finding(const Finding& finding) {
  std::string out = to_string(finding.where) + ": " + to_string(finding.severity) + ": " +
                    finding.message;
  if (!finding.code.empty()) out += " [" + finding.code + "]";
  return out;
}

void print_finding(const Finding& finding) { print_error(format_finding(finding)); }

bool stderr_is_terminal() { return ::isatty(STDERR_FILENO) == 1; }

std::string format_rate(double per_s) {
  char buf[32];
  if (per_s >= 1e6) {
    std::snprintf(buf, sizeof buf, "%.2f M", per_s / 1e6);
  } else if (per_s >= 1e3) {
    std::snprintf(buf, sizeof buf, "%.1f k", per_s / 1e3);
  } else {
    std::snprintf(buf, sizeof buf, "%.0f ", per_s);
  }
  return buf;
}

}  // namespace gonio::cli
