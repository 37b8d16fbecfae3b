#include "photometry/diagnostics.h"
#include "photometry/error_at.h"

#include <algorithm>

namespace gonio {

std::string to_string(const SourceLoc& loc) {
  std::string out = loc.file.empty() ? std::string("<input>") : loc.file;
  if (loc.line > 0) {
    out += ':' + std::to_string(loc.line);
    if (loc.column > 0) out += ':' + std::to_string(loc.column);
  }
  return out;
}

std::string to_string(const Error& error) {
  return to_string(error.where) + ": " + error.message;
}

Error make_error(std::string message) {
  Error e;
  e.message = std::move(message);
  return e;
}

Error make_error(const std::string& file, std::string message) {
  Error e;
  e.where.file = file;
  e.message = std::move(message);
  return e;
}

Error make_error(const std::string& file, int line, std::string message) {
  Error e = make_error(file, std::move(message));
  e.where.line = line;
  return e;
}

const char* to_string(Severity severity) {
  switch (severity) {
    case Severity::Info: return "info";
    case Severity::Warning: return "warning";
    case Severity::Error: return "error";
  }
  return "?";
}

Severity worst(const std::vector<Finding>& findings) {
  Severity w = Severity::Info;
  for (const Finding& f : findings) w = std::max(w, f.severity);
  return w;
}

void check_failed(const char* condition, const char* file, int line, const char* message) {
  std::fprintf(stderr, "gonio: internal error: %s:%d: check failed: %s%s%s\n", file, line,
               condition, message ? ": " : "", message ? message : "");
  std::abort();
}

}  // namespace gonio
