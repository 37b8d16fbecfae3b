// Diagnostics shared by every Gonio module: where in an input something was
// found, errors returned as values, findings with severities, and the check
// macro for broken invariants.
//
// Bad input is an expected outcome and travels as `Error` inside `Result<T>`.
// A broken invariant is a bug and stops the program through GONIO_CHECK.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace gonio {

// A place in an input file. `line` and `column` are 1-based; 0 means unknown.
struct SourceLoc {
  std::string file;
  int line = 0;
  int column = 0;
};

// "file:line:column", "file:line" or "file", whichever parts are known.
std::string to_string(const SourceLoc& loc);

struct Error {
  SourceLoc where;
  std::string message;
};

// "file:line: message" (the form the command line prints after "gonio: ").
std::string to_string(const Error& error);

// The one Error factory: an error with no place, or about a whole file
// (a reader that knows the line builds SourceLoc itself). Out of line, so
// that callers do not meet GCC 12's false maybe-uninitialized warnings about
// Error temporaries built inline.
Error make_error(std::string message);
Error make_error(const std::string& file, std::string message);

// A value or the error that prevented it. Small and explicit on purpose:
// callers test `ok()` and read `value()` or `error()`.
template <class T>
class [[nodiscard]] Result {
 public:
  Result(T value) : state_(std::in_place_index<0>, std::move(value)) {}  // NOLINT: implicit by design
  Result(Error error) : state_(std::in_place_index<1>, std::move(error)) {}  // NOLINT

  bool ok() const { return state_.index() == 0; }
  explicit operator bool() const { return ok(); }

  T& value() & { return std::get<0>(state_); }
  const T& value() const& { return std::get<0>(state_); }
  T&& value() && { return std::get<0>(std::move(state_)); }
  const Error& error() const { return std::get<1>(state_); }

  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }

 private:
  std::variant<T, Error> state_;
};

// Result of an operation that produces nothing but may fail.
struct Ok {};
using Status = Result<Ok>;

enum class Severity { Info, Warning, Error };

const char* to_string(Severity severity);

// One observation of a validation pass or a reader: what, where, how bad.
// `code` is a stable kebab-case identifier (e.g. "nadir-mismatch") that tests
// and scripts can match; `message` is for people.
struct Finding {
  Severity severity = Severity::Warning;
  std::string code;
  std::string message;
  SourceLoc where;
};

// The most severe entry, or Severity::Info for an empty list.
Severity worst(const std::vector<Finding>& findings);

[[noreturn]] void check_failed(const char* condition, const char* file, int line,
                               const char* message);

}  // namespace gonio

// Stops the program when an invariant of Gonio's own code is broken. Never use
// it for bad input: that is an Error value.
#define GONIO_CHECK(cond)                                                  \
  do {                                                                     \
    if (!(cond)) ::gonio::check_failed(#cond, __FILE__, __LINE__, nullptr); \
  } while (false)

#define GONIO_CHECK_MSG(cond, msg)                                     \
  do {                                                                 \
    if (!(cond)) ::gonio::check_failed(#cond, __FILE__, __LINE__, msg); \
  } while (false)
