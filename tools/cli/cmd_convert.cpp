// gonio convert IN OUT: IES ⇄ EULUMDAT (and IES → IES, LDT → LDT) by file
// extension, saying what the target format cannot carry.
#include <cstdio>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "gonio/version.h"
#include "io/photometric/photometric_file.h"
#include "io/support/file_io.h"
#include "tools/cli/cli.h"
#include "tools/cli/input_options.h"
#include "tools/cli/commands.h"
#include "tools/run/photometric_input.h"

namespace gonio::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* kDescription =
    "Converts a photometric file into the format OUT's extension names (.ies: IES\n"
    "LM-63, .ldt: EULUMDAT, .xml: IES TM-33-23, .gldf: a GLDF container holding the\n"
    "photometry in IN's own format with its product.xml; case-insensitive): between\n"
    "any two, or into the same format to change the version or clean a file up. IN is\n"
    "read by its extension, or by its content where that names no format; of a GLDF\n"
    "container the first photometry is converted. Intensities, flux and\n"
    "every field both formats carry are kept; what the target cannot hold (IES:\n"
    "alternative lamp sets, lamp colour, declared LOR/DFF, direct ratios, body\n"
    "dimensions; LDT: most keywords, TILT data, ballast factor) is reported on stderr\n"
    "as 'gonio: OUT: warning: message [code]', never dropped silently; 'info' lines\n"
    "say what was computed or filled in.\n"
    "\n"
    "EULUMDAT holds Type C photometry only: Type A and B input written as .ldt is\n"
    "resampled onto a regular Type C grid, C every 5 deg and gamma every 1 deg unless\n"
    "--c-step/--gamma-step say otherwise: each value is the mean over its C-cell of\n"
    "the model the flux is integrated from, so the flux is kept (to 0.05 % on the\n"
    "default grid); the warning states the grid and the flux before and after.\n"
    "Giving --c-step or --gamma-step resamples any input onto that grid.\n"
    "\n"
    "An IES TM-25 ray file (.tm25ray) is converted as its far field: every ray's\n"
    "direction binned by its luminous flux onto C every 5 deg and gamma every 2.5\n"
    "deg (the ray file's +z is the nadir, +x C0), positions ignored; the OTHER\n"
    "keyword says so. Ray files are written by 'gonio simulate --format tm25'.\n"
    "\n"
    "OUT is written to a temporary file and renamed, so a failure never leaves a\n"
    "half-written file; the input is never modified, and OUT naming the same file as\n"
    "IN (also through a link) is refused.\n"
    "\n"
    "Exit status: 0 success (warnings included), 1 the input could not be read or the\n"
    "output not written, 2 usage error.\n"
    "\n"
    "Examples:\n"
    "  gonio convert lamp.ies lamp.ldt\n"
    "  gonio convert old.ies new.ies --ies-version 2002\n"
    "  gonio convert flood_typeB.ies flood.ldt --c-step 2.5 --gamma-step 0.5";

}  // namespace

int run_convert(const Args& args) {
  std::string in_path, out_path, ies_version = "2019", isym3_out = app::kIsym3Standard;
  double c_step = 5.0, gamma_step = 1.0;
  bool quiet = false;
  app::InputOptions input;
  ArgParser parser("convert",
                   "IN OUT [--ies-version 2002|2019] [--c-step D --gamma-step D] "
                   "[--ldt-isym3 standard|qlumedit] [--ldt-isym3-out standard|qlumedit] [--quiet]",
                   kDescription);
  parser.positional("IN", &in_path, "The file to read (.ies, .ldt, .xml, .gldf; others by content).");
  parser.positional("OUT", &out_path,
                    "The file to write (.ies, .ldt, .xml or .gldf); replaced if it exists, never IN itself.");
  parser.choice("ies-version", &ies_version, {"2002", "2019"},
                "LM-63 version of .ies output (default 2019).");
  parser.option("c-step", &c_step, 0.25, 90.0, "D",
                "C-plane step of the Type C resampling grid [deg] (default 5); must divide the "
                "C range of the symmetry (90, 180 or 360 deg).");
  parser.option("gamma-step", &gamma_step, 0.1, 90.0, "D",
                "Gamma step of the Type C resampling grid [deg] (default 1); must divide 90.");
  add_input_options(parser, &input);
  parser.choice("ldt-isym3-out", &isym3_out, {app::kIsym3Standard, app::kIsym3QLumEdit},
                "Plane order of .ldt output with Isym 3 (default standard; see --ldt-isym3).");
  parser.flag("quiet", &quiet, "Print only warnings and errors: no info lines, no summary.");
  if (const auto outcome = parser.parse(args); outcome != ArgParser::Outcome::Run)
    return ArgParser::exit_code(outcome);

  const auto usage_error = [&](const std::string& message) {
    print_error("convert: " + message);
    std::fprintf(stderr, "%s\nTry 'gonio convert --help'.\n", parser.usage().c_str());
    return kExitUsage;
  };
  const auto out_format = io::format_for_path(out_path);
  if (!out_format)
    return usage_error("cannot tell the output format from '" + out_path +
                       "': its extension must be .ies, .ldt, .xml or .gldf");
  if (*out_format == io::PhotometricFormat::Tm25)
    return usage_error("cannot write a TM-25 ray file from a photometric file: a far field has no rays "
                       "('gonio simulate --format tm25' writes a luminaire's rays)");
  if (*out_format != io::PhotometricFormat::Ies && *out_format != io::PhotometricFormat::Gldf &&
      parser.given("ies-version"))
    return usage_error("--ies-version applies to .ies output only");
  if (*out_format != io::PhotometricFormat::Ldt && parser.given("ldt-isym3-out"))
    return usage_error("--ldt-isym3-out applies to .ldt output only");
  if (io::same_file(in_path, out_path)) {
    print_error(out_path + ": is the input file " + in_path +
                " (the same file, possibly through a link); refusing to overwrite the input");
    return kExitFailure;
  }

  auto file = app::read_input(in_path, input, !quiet);
  if (!file.ok()) return kExitFailure;

  io::PhotometricWriteOptions options;
  options.ies.version =
      ies_version == "2002" ? io::IesVersion::LM63_2002 : io::IesVersion::LM63_2019;
  options.ldt.isym3_order = app::isym3_order(isym3_out);
  // [FILEGENINFO] of LM-63-2019 output where the input has none.
  options.ies.file_generation_info = std::string("Converted by Gonio ") + kVersion + " from " +
                                     fs::path(in_path).filename().string() + " (" +
                                     io::to_string(file->format) + ")";
  options.type_c_grid.c_step_deg = c_step;
  options.type_c_grid.gamma_step_deg = gamma_step;
  options.always_resample = parser.given("c-step") || parser.given("gamma-step");
  // GLDF output packages the photometry in the input's own format.
  options.gldf_photometry = file->format;

  std::vector<Finding> warnings;
  const Status written =
      io::write_photometric_file(out_path, file->distribution, options, &warnings);
  int warning_count = 0;
  for (Finding& w : warnings) {
    if (w.where.file.empty()) w.where.file = out_path;
    if (w.severity != Severity::Info) ++warning_count;
    if (w.severity != Severity::Info || !quiet) print_finding(w);
  }
  if (!written.ok()) {
    print_error(written.error());
    return kExitFailure;
  }
  if (!quiet) {
    std::string what = io::to_string(*out_format);
    if (*out_format == io::PhotometricFormat::Ies)
      what += std::string(" ") + io::to_string(options.ies.version);
    std::printf("Wrote %s (%s) from %s; %d warning%s\n", out_path.c_str(), what.c_str(),
                in_path.c_str(), warning_count, warning_count == 1 ? "" : "s");
  }
  return std::fflush(stdout) == 0 ? kExitOk : kExitFailure;
}

}  // namespace gonio::cli
