// What every front end of the application prints to the terminal: the
// message conventions (`gonio: FILE:LINE: message` on stderr), the exit
// codes, and the rate and figure formats of progress lines.
//
// Exit codes shared by all subcommands (docs/conventions.md "Exit codes"):
//   0  success
//   1  the work failed: unreadable or invalid input, a write error, a failed
//      energy check
//   2  usage error: unknown option, missing or malformed argument
// `gonio check` adds its own codes for findings (see tools/cli/cmd_check.cpp).
#pragma once

#include <functional>
#include <string>

#include "photometry/diagnostics.h"

namespace gonio::app {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;

// Prints "gonio: <message>" to stderr.
void print_error(const std::string& message);
// Prints "gonio: <file>:<line>: <message>" to stderr.
void print_error(const Error& error);
// Prints "gonio: warning: <message>" to stderr.
void print_warning(const std::string& message);
// "<file>:<line>: <severity>: <message> [<code>]" (parts that are unknown
// left out), the form findings of readers, writers and checks take.
std::string format_finding(const Finding& finding);
// Prints "gonio: " + format_finding(finding) to stderr.
void print_finding(const Finding& finding);

// What the application tells its front end as it works (a model's findings,
// the error that stops a run): one message as gonio prints it to stderr
// after "gonio: " ("FILE:LINE: message"; a warning's text begins
// "warning: "), with its severity. The command line prints it; another front
// end (tests, the Python module) may collect it. Empty: printed as gonio
// prints it.
using MessageSink = std::function<void(Severity severity, const std::string& text)>;
// Passes a message to `sink`, or prints "gonio: TEXT" to stderr where it is empty.
void tell(const MessageSink& sink, Severity severity, const std::string& text);
// An error, as to_string(error) with Severity::Error.
void tell(const MessageSink& sink, const Error& error);

// Whether standard error is a terminal (progress output goes there only then).
bool stderr_is_terminal();

// A rate as "1.23 M", "45.6 k" or "789 " (progress lines: photons/s).
std::string format_rate(double per_s);

}  // namespace gonio::app
