// gonio plot: the intensity diagram of a photometric file.
//
//   gonio plot FILE [--out X.svg|X.png] [--unit cd|cdklm] [--title T]
//
// Draws the C0–C180 and C90–C270 planes of an IES or EULUMDAT file, measured
// or simulated, as a polar diagram and on cartesian axes (io/outputs/intensity_diagram.h),
// in candela or in cd/klm. Types A and B are resampled to Type C first.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "io/outputs/intensity_diagram.h"
#include "io/outputs/plot.h"
#include "photometry/flux.h"
#include "photometry/resample.h"
#include "tools/cli/cli.h"
#include "tools/cli/input_options.h"
#include "tools/cli/commands.h"
#include "tools/run/photometric_input.h"

namespace gonio::cli {

int run_plot(const Args& args) {
  std::string file, out, unit = "cd", title;
  InputOptions input;
  ArgParser p("plot", "FILE [--out X.svg|X.png] [--unit cd|cdklm] [--ldt-isym3 standard|qlumedit]",
              "Draws the intensity diagram of a photometric file (IES, LDT, TM-33, GLDF, or a\n"
              "TM-25 ray file's far field): the C0-C180 and C90-C270 planes as a polar diagram\n"
              "(nadir down, C0 and C90 to the right) and on cartesian axes (gamma -180...180,\n"
              "C180 and C270 on the negative side). cd/klm is per 1000 lm of the rated lamp\n"
              "flux (of the luminaire's flux for absolute photometry).");
  p.positional("FILE", &file, "the photometric file (by its extension, else by its content)");
  p.option("out", &out, "X.svg|X.png", "the picture to write (default: FILE with the extension .svg)");
  p.choice("unit", &unit, {"cd", "cdklm"}, "candela (default) or cd/klm");
  p.option("title", &title, "T", "title above the diagram (default: the file name)");
  add_input_options(p, &input);
  if (const auto outcome = p.parse(args); outcome != ArgParser::Outcome::Run) return ArgParser::exit_code(outcome);
  if (out.empty()) out = std::filesystem::path(file).replace_extension(".svg").string();
  if (Result<io::ImageFormat> f = io::image_format_for(out); !f.ok()) {
    print_error("plot: " + f.error().message);
    std::fprintf(stderr, "%s\n", p.usage().c_str());
    return kExitUsage;
  }

  auto read = read_input(file, input, false);
  if (!read.ok()) return kExitFailure;
  photometry::Distribution d = std::move(read->distribution);
  if (d.type != photometry::PhotometricType::C) {
    Result<photometry::Distribution> c = photometry::to_type_c(d);
    if (!c.ok()) {
      print_error(file + ": " + c.error().message);
      return kExitFailure;
    }
    d = std::move(*c);
  }
  io::DiagramOptions options;
  options.title = title.empty() ? std::filesystem::path(file).filename().string() : title;
  if (unit == "cdklm") {
    options.per_klm_of_lm = d.absolute ? photometry::total_flux_lm(d) : d.rated_lamp_flux_lm();
    if (!(options.per_klm_of_lm > 0.0)) {
      print_error(file + ": cd/klm needs a positive flux, and this file has none");
      return kExitFailure;
    }
  }
  Result<io::Figure> figure = io::intensity_diagram(d, options);
  if (!figure.ok()) {
    print_error(file + ": " + figure.error().message);
    return kExitFailure;
  }
  if (Status s = io::write_figure(out, *figure); !s.ok()) {
    print_error(s.error());
    return kExitFailure;
  }
  std::printf("%s\n", out.c_str());
  return kExitOk;
}

}  // namespace gonio::cli
