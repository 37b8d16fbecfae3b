// gonio report FILE... --out X.html|X.pdf: the luminaire datasheet
// (io/outputs/datasheet.h), one section per file.
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "io/outputs/datasheet.h"
#include "io/support/file_io.h"
#include "tools/cli/cli.h"
#include "tools/cli/input_options.h"
#include "tools/cli/commands.h"
#include "tools/run/photometric_input.h"

namespace gonio::cli {

int run_report(const Args& args) {
  std::vector<std::string> files;
  std::string out;
  double height = 3.0, floor_reflectance = 0.2;
  std::string ugr_background = photometry::to_string(photometry::UgrBackground::Cie190);
  bool timing = false;
  std::string tolerance;
  app::InputOptions input;
  ArgParser p("report", "FILE... --out X.html|X.pdf [--height M] [--cu-floor RHO] [--ugr-background cie190|flux-transfer] [--tolerance REPORT.json]",
              "Writes the datasheet of one or more photometric files (IES, LDT, TM-33, GLDF, or\n"
              "a TM-25 ray file's far field): identification, polar and cartesian intensity\n"
              "diagrams, cone diagram and isolux plot on the floor at the mounting height,\n"
              "zonal lumens, UGR table (CIE 190:2010), coefficients of utilisation (IES zonal\n"
              "cavity), spacing criterion (IES), BUG rating (IES TM-15-11 Addendum A),\n"
              "luminance table, efficacy and the candela table.\n"
              "HTML is one self-contained file (inline SVG, no external resource); PDF is that\n"
              "page printed by a headless Chromium (Debian package chromium, or\n"
              "$GONIO_CHROMIUM). Each figure says its method, convention and the outside\n"
              "reference it is checked against; docs/methods.md, \"Light-planning figures\".\n"
              "\n"
              "Exit status: 0 written, 1 a file could not be read or the sheet not written,\n"
              "2 usage error.\n"
              "\n"
              "Examples:\n"
              "  gonio report samples/curves/downlight.ldt --out downlight.html\n"
              "  gonio report a.ies b.ldt --out sheet.pdf --height 4");
  p.positional_list("FILE", &files, 1, "the photometric files, one section each");
  p.option("out", &out, "X.html|X.pdf", "the datasheet to write (required)");
  p.option("height", &height, 0.1, 1000.0, "M", "mounting height of the cone diagram and isolux plot [m] (default 3)");
  p.option("cu-floor", &floor_reflectance, 0.0, 0.95, "RHO",
           "effective floor cavity reflectance of the CU table, 0..1 (default 0.2)");
  add_ugr_background_option(p, &ugr_background);
  p.option("tolerance", &tolerance, "REPORT.json",
           "gonio tolerance's DIR/report.json: the sheet gains its Monte Carlo yield table against the --spec limits");
  p.flag("timing", &timing, "print the time taken to stderr");
  add_input_options(p, &input);
  if (const auto outcome = p.parse(args); outcome != ArgParser::Outcome::Run) return ArgParser::exit_code(outcome);
  if (out.empty()) {
    print_error("report: --out X.html or --out X.pdf is required");
    std::fprintf(stderr, "%s\n", p.usage().c_str());
    return kExitUsage;
  }
  const auto start = std::chrono::steady_clock::now();
  std::vector<io::DatasheetEntry> entries;
  for (const std::string& f : files) {
    Result<io::PhotometricFile> read = app::read_input(f, input, false);
    if (!read.ok()) return kExitFailure;
    io::DatasheetEntry e;
    e.source = f;
    e.format = io::to_string(read->format);
    if (read->ies_version) e.format += std::string(" ") + io::to_string(*read->ies_version);
    e.distribution = std::move(read->distribution);
    entries.push_back(std::move(e));
  }
  io::DatasheetOptions options;
  options.mounting_height_m = height;
  options.floor_reflectance = floor_reflectance;
  options.ugr = app::ugr_options(ugr_background);
  if (!tolerance.empty()) {
    Result<std::string> text = io::read_file(tolerance, std::size_t{1} << 30);
    if (!text.ok()) {
      print_error(text.error());
      return kExitFailure;
    }
    nlohmann::json report = nlohmann::json::parse(*text, nullptr, false);
    if (report.is_discarded()) {
      print_error(make_error(tolerance, "not JSON: write gonio tolerance's report.json"));
      return kExitFailure;
    }
    options.tolerance_report = std::move(report);
    options.tolerance_source = tolerance;
  }
  if (Status s = io::write_datasheet(out, entries, options); !s.ok()) {
    print_error(s.error());
    return kExitFailure;
  }
  if (timing)
    std::fprintf(stderr, "gonio: report: %zu file(s) in %.3f s\n", files.size(),
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  std::printf("%s\n", out.c_str());
  return kExitOk;
}

}  // namespace gonio::cli
