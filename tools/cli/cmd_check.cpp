// gonio check FILE...: structure and plausibility of measured files, the
// readers' format-level findings plus photometry::check()'s model-level ones.
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gonio/version.h"
#include "io/photometric/photometric_file.h"
#include "photometry/validation.h"
#include "tools/cli/cli.h"
#include "tools/cli/input_options.h"
#include "tools/cli/commands.h"
#include "tools/run/photometric_input.h"

namespace gonio::cli {
namespace {

using json = nlohmann::ordered_json;

constexpr const char* kDescription =
    "Checks IES LM-63 (.ies), EULUMDAT (.ldt), IES TM-33 (.xml) and GLDF (.gldf, each\n"
    "photometry inside) files (other names by their content): the reader's\n"
    "format-level findings (with the line they concern) and the model-level checks of\n"
    "photometry/validation.h (angle ranges, symmetry, disagreeing poles and seams,\n"
    "negative or absurd intensities, implausible LOR and efficacy, declared LOR/DFF\n"
    "against the integrated values).\n"
    "\n"
    "The report goes to standard output: each finding as\n"
    "  gonio: FILE:LINE: SEVERITY: message [code]\n"
    "(LINE left out where a finding concerns the whole model), SEVERITY being error,\n"
    "warning or info, then one summary line per file ('FILE: clean (...)', 'FILE: 2\n"
    "warnings (...)', 'FILE: 1 error, unreadable') and, for several files, a total. A\n"
    "file that cannot be read is an error finding in the report, code 'unreadable',\n"
    "with the reader's file and line; the check goes on with the next. Codes are\n"
    "stable (photometry/validation.h, io/photometric/ies.h,\n"
    "io/photometric/ldt.h). Standard error carries only usage errors and, if the\n"
    "report could not be written, that.\n"
    "\n"
    "With --json, stdout is one JSON object instead:\n"
    "  {\"files\": [{\"file\", \"format\", \"version\", \"readable\", \"status\",\n"
    "              \"errors\", \"warnings\", \"infos\",\n"
    "              \"findings\": [{\"severity\", \"code\", \"message\", \"line\"}]}],\n"
    "   \"clean\", \"with_warnings\", \"with_errors\", \"exit_code\"}\n"
    "\n"
    "Exit status:\n"
    "  0  every file is clean (info lines do not count)\n"
    "  1  the report could not be written to standard output\n"
    "  2  usage error\n"
    "  3  warnings, but no errors\n"
    "  4  errors in at least one file (including files that could not be read)\n"
    "\n"
    "Example:\n"
    "  gonio check *.ies *.ldt";

constexpr int kExitWarnings = 3;
constexpr int kExitErrors = 4;

struct FileReport {
  std::string path;
  bool readable = false;
  std::string format;   // "IES LM-63-2002", "EULUMDAT"; empty if unreadable
  std::string version;  // LM-63 version; empty otherwise
  std::vector<Finding> findings;
  int errors = 0, warnings = 0, infos = 0;
};

void count(FileReport& r) {
  for (Finding& f : r.findings) {
    if (f.where.file.empty()) f.where.file = r.path;
    switch (f.severity) {
      case Severity::Error:
        ++r.errors;
        break;
      case Severity::Warning:
        ++r.warnings;
        break;
      case Severity::Info:
        ++r.infos;
        break;
    }
  }
}

// One report per photometry the file holds (several for a GLDF container,
// each named CONTAINER:ENTRY), or one unreadable report.
std::vector<FileReport> check_file(const std::string& path, const io::PhotometricReadOptions& options) {
  std::vector<FileReport> reports;
  auto files = io::read_photometric_files(path, options);
  if (!files.ok()) {
    FileReport r;
    r.path = path;
    SourceLoc where = files.error().where;
    if (where.file.empty()) where.file = path;
    r.findings.push_back({Severity::Error, "unreadable", files.error().message, where});
    count(r);
    reports.push_back(std::move(r));
    return reports;
  }
  for (io::PhotometricFile& file : *files) {
    FileReport r;
    r.path = file.container.empty() ? path : path + ":" + file.container_entry;
    r.readable = true;
    r.format = io::format_label(file);
    if (file.ies_version) r.version = io::to_string(*file.ies_version);
    if (file.tm33_version) r.version = io::to_string(*file.tm33_version);
    r.findings = std::move(file.findings);
    for (Finding f : photometry::check(file.distribution)) {
      f.where.file = r.path;
      r.findings.push_back(std::move(f));
    }
    count(r);
    reports.push_back(std::move(r));
  }
  return reports;
}

std::string plural(int n, const char* word) {
  return std::to_string(n) + " " + word + (n == 1 ? "" : "s");
}

const char* status(const FileReport& r) {
  return r.errors > 0 ? "errors" : r.warnings > 0 ? "warnings" : "clean";
}

std::string summary_line(const FileReport& r) {
  std::string s = r.path + ": ";
  if (r.errors == 0 && r.warnings == 0) {
    s += "clean";
  } else {
    if (r.errors > 0) s += plural(r.errors, "error");
    if (r.warnings > 0) s += (r.errors > 0 ? ", " : "") + plural(r.warnings, "warning");
  }
  if (r.infos > 0) s += ", " + plural(r.infos, "info");
  s += r.readable ? " (" + r.format + ")" : ", unreadable";
  return s;
}

json finding_json(const Finding& f) {
  return {{"severity", to_string(f.severity)},
          {"code", f.code},
          {"message", f.message},
          {"line", f.where.line > 0 ? json(f.where.line) : json(nullptr)}};
}

}  // namespace

int run_check(const Args& args) {
  std::vector<std::string> paths;
  bool as_json = false;
  InputOptions input;
  ArgParser parser("check", "FILE... [--json] [--ldt-isym3 standard|qlumedit]", kDescription);
  parser.positional_list("FILE", &paths, 1,
                         "IES LM-63 (.ies), EULUMDAT (.ldt), TM-33 (.xml) or GLDF (.gldf) files "
                         "(others by their content); each photometry of a GLDF is checked.");
  parser.flag("json", &as_json, "Print one JSON object instead of the findings and summaries.");
  add_input_options(parser, &input);
  if (const auto outcome = parser.parse(args); outcome != ArgParser::Outcome::Run)
    return ArgParser::exit_code(outcome);

  const io::PhotometricReadOptions options = read_options(input);
  int clean = 0, with_warnings = 0, with_errors = 0;
  json files = json::array();
  int report_count = 0;
  for (const std::string& path : paths)
   for (const FileReport& r : check_file(path, options)) {
    ++report_count;
    if (r.errors > 0) {
      ++with_errors;
    } else if (r.warnings > 0) {
      ++with_warnings;
    } else {
      ++clean;
    }
    if (as_json) {
      json findings = json::array();
      for (const Finding& f : r.findings) findings.push_back(finding_json(f));
      files.push_back({{"file", r.path},
                       {"format", r.readable ? json(r.format) : json(nullptr)},
                       {"version", r.version.empty() ? json(nullptr) : json(r.version)},
                       {"readable", r.readable},
                       {"status", status(r)},
                       {"errors", r.errors},
                       {"warnings", r.warnings},
                       {"infos", r.infos},
                       {"findings", std::move(findings)}});
    } else {
      for (const Finding& f : r.findings)
        std::printf("%s: %s\n", kProgramName, format_finding(f).c_str());
      std::printf("%s\n", summary_line(r).c_str());
    }
  }
  const int code = with_errors > 0 ? kExitErrors : with_warnings > 0 ? kExitWarnings : kExitOk;
  if (as_json) {
    const json report = {{"files", std::move(files)},
                         {"clean", clean},
                         {"with_warnings", with_warnings},
                         {"with_errors", with_errors},
                         {"exit_code", code}};
    std::printf("%s\n", report.dump(2, ' ', false, json::error_handler_t::replace).c_str());
  } else if (report_count > 1) {
    std::printf("%s: %d clean, %d with warnings, %d with errors\n",
                plural(report_count, "file").c_str(), clean, with_warnings,
                with_errors);
  }
  // A report that cannot be written is said to be by main() (tools/cli/main.cpp),
  // as for every command.
  return code;
}

}  // namespace gonio::cli
