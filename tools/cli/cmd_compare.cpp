// gonio compare: how far one photometric file is from another.
//
//   gonio compare A B [--json] [--plot X.svg] [--c-step DEG] [--gamma-step DEG]
//                 [--normalize]
//
// Both files are brought to one Type C grid over the whole sphere and B is
// compared with the reference A (photometry/compare.h): RMS and largest
// difference relative to A's peak, flux of each and their ratio, beam and
// field angle differences in both main planes; --plot overlays both files'
// C0–C180 and C90–C270 curves in one diagram.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "io/outputs/intensity_diagram.h"
#include "io/outputs/plot.h"
#include "photometry/beam.h"
#include "photometry/compare.h"
#include "tools/cli/cli.h"
#include "tools/cli/input_options.h"
#include "tools/cli/commands.h"
#include "tools/run/photometric_input.h"
#include "tools/run/photometric_report.h"

namespace gonio::cli {
namespace {


std::string degrees(double v) {
  if (!std::isfinite(v)) return "none";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f°", v);
  return buf;
}

std::string signed_degrees(double v) {
  if (!std::isfinite(v)) return "n/a";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%+.2f°", v);
  return buf;
}

// Whether two distributions were measured on the same angles: the same type
// and vertical angles, and the same planes once each is expanded over the
// whole circle by its symmetry (to 1e-6°).
std::string angle_counts(const photometry::Distribution& d) {
  const photometry::Distribution full = photometry::expand_symmetry(d);
  return std::to_string(full.horizontal_deg.size()) + " planes x " + std::to_string(d.vertical_deg.size()) +
         " vertical angles";
}

}  // namespace

int run_compare(const Args& args) {
  std::string file_a, file_b, plot;
  bool json_out = false, normalize = false;
  double c_step = 5.0, gamma_step = 2.5;
  app::InputOptions input;
  ArgParser p("compare",
              "A B [--json] [--plot X.svg] [--c-step DEG] [--gamma-step DEG] [--normalize] "
              "[--ldt-isym3 standard|qlumedit]",
              "Compares photometric file B with the reference A (IES or EULUMDAT, any type): both\n"
              "are resampled to one Type C grid over the whole sphere; differences are relative\n"
              "to A's peak intensity, the RMS weighted by solid angle. Also the flux of each,\n"
              "their ratio, and the beam (50 %) and field (10 %) angle differences in the\n"
              "C0-C180 and C90-C270 planes.");
  p.positional("A", &file_a, "the reference file");
  p.positional("B", &file_b, "the file compared with it");
  p.flag("json", &json_out, "print the comparison as JSON on stdout");
  p.option("plot", &plot, "X.svg|X.png", "also draw both files' C0-C180 and C90-C270 curves in one diagram");
  p.option("c-step", &c_step, 0.1, 90.0, "DEG", "C spacing of the common grid (default 5; divides 360)");
  p.option("gamma-step", &gamma_step, 0.1, 90.0, "DEG", "gamma spacing of the common grid (default 2.5; divides 90)");
  p.flag("normalize", &normalize, "scale B to A's flux first: compare shapes only");
  add_input_options(p, &input);
  if (const auto outcome = p.parse(args); outcome != ArgParser::Outcome::Run) return ArgParser::exit_code(outcome);
  if (!plot.empty()) {
    if (Result<io::ImageFormat> f = io::image_format_for(plot); !f.ok()) {
      print_error("compare: " + f.error().message);
      std::fprintf(stderr, "%s\n", p.usage().c_str());
      return kExitUsage;
    }
  }
  photometry::CompareOptions options;
  options.c_step_deg = c_step;
  options.gamma_step_deg = gamma_step;
  options.normalize_flux = normalize;
  const double c_steps = 360.0 / c_step, g_steps = 90.0 / gamma_step;
  if (std::abs(c_steps - std::round(c_steps)) > 1e-9 * c_steps ||
      std::abs(g_steps - std::round(g_steps)) > 1e-9 * g_steps) {
    print_error("compare: --c-step must divide 360 and --gamma-step 90 into whole steps (e.g. 5 and 2.5)");
    std::fprintf(stderr, "%s\n", p.usage().c_str());
    return kExitUsage;
  }

  auto a = app::read_input(file_a, input, false);
  if (!a.ok()) return kExitFailure;
  auto b = app::read_input(file_b, input, false);
  if (!b.ok()) return kExitFailure;
  const std::string format_a = io::format_label(*a), format_b = io::format_label(*b);
  Result<photometry::Comparison> cmp = photometry::compare(a->distribution, b->distribution, options);
  if (!cmp.ok()) {
    print_error("compare: " + cmp.error().message);
    return kExitFailure;
  }
  const photometry::Comparison& c = *cmp;
  const double beam_a0 = photometry::beam_angle(a->distribution, 0.0).angle_deg;
  const double beam_a90 = photometry::beam_angle(a->distribution, 90.0).angle_deg;
  const double beam_b0 = photometry::beam_angle(b->distribution, 0.0).angle_deg;
  const double beam_b90 = photometry::beam_angle(b->distribution, 90.0).angle_deg;

  if (!plot.empty()) {
    io::OverlayOptions o;
    o.label_a = "A " + std::filesystem::path(file_a).filename().string();
    o.label_b = "B " + std::filesystem::path(file_b).filename().string();
    o.scale_b = c.scale;
    o.title = normalize ? "B scaled to A's flux" : "";
    Result<io::Figure> figure = io::overlay_diagram(a->distribution, b->distribution, o);
    if (!figure.ok()) {
      print_error("compare: " + figure.error().message);
      return kExitFailure;
    }
    if (Status s = io::write_figure(plot, *figure); !s.ok()) {
      print_error(s.error());
      return kExitFailure;
    }
  }

  // Files on different angles are each interpolated onto the common grid:
  // the comparison then holds the interpolation's error too.
  const bool grids_differ = !photometry::same_angles(a->distribution, b->distribution);
  if (json_out) {
    nlohmann::json j = app::compare_json(file_a, *a, file_b, *b, c, options);
    if (!plot.empty()) j["plot"] = plot;
    std::printf("%s\n", j.dump(2).c_str());
    return kExitOk;
  }
  std::printf("A: %s (%s), %.6g lm\n", file_a.c_str(), format_a.c_str(), c.flux_a_lm);
  std::printf("B: %s (%s), %.6g lm\n", file_b.c_str(), format_b.c_str(), c.flux_b_lm);
  std::printf("grid: C every %g°, gamma every %g°, whole sphere%s\n", c_step, gamma_step,
              normalize ? "; B scaled to A's flux" : "");
  if (grids_differ)
    std::printf("angles: A and B differ (A %s, B %s): both are interpolated onto the common grid, whose\n"
                "  error adds to the differences (gonio simulate --grid-like A puts a simulation on A's angles)\n",
                angle_counts(a->distribution).c_str(), angle_counts(b->distribution).c_str());
  else
    std::printf("angles: A and B share theirs (%s)\n", angle_counts(a->distribution).c_str());
  std::printf("RMS difference:     %.3f %% of A's peak (%.6g cd)\n", 100.0 * c.rms_relative, c.reference_cd);
  std::printf("largest difference: %.3f %% of A's peak, at C %g°, gamma %g°\n", 100.0 * c.max_relative,
              c.max_at_c_deg, c.max_at_gamma_deg);
  if (std::isfinite(c.flux_ratio))
    std::printf("flux: B - A = %+.6g lm (B/A = %.5f)\n", c.flux_b_lm - c.flux_a_lm, c.flux_ratio);
  else
    std::printf("flux: B - A = %+.6g lm (A emits nothing)\n", c.flux_b_lm - c.flux_a_lm);
  std::printf("beam angle C0-C180:  A %s, B %s (%s)\n", degrees(beam_a0).c_str(), degrees(beam_b0).c_str(),
              signed_degrees(c.beam_difference_c0_c180_deg).c_str());
  std::printf("beam angle C90-C270: A %s, B %s (%s)\n", degrees(beam_a90).c_str(), degrees(beam_b90).c_str(),
              signed_degrees(c.beam_difference_c90_c270_deg).c_str());
  std::printf("field angle difference: C0-C180 %s, C90-C270 %s\n",
              signed_degrees(c.field_difference_c0_c180_deg).c_str(),
              signed_degrees(c.field_difference_c90_c270_deg).c_str());
  if (!plot.empty()) std::printf("plot: %s\n", plot.c_str());
  return kExitOk;
}

}  // namespace gonio::cli
