// gonio design: optics from a target distribution (docs/design.md).
//
//   gonio design reflector --emitter FILE --target FILE|FORMULA --out DIR
//                [--cone FROM,TO] [--map uncrossed|crossed] [--distance MM]
//                [--nodes N] [--reflectance R] [--absolute] [--name NAME]
//                [--photons N] [--seed S] [--threads T] [--gamma-step DEG]
//   gonio design export FILE.design.toml --out DIR [--tolerance MM] [--gamma-step DEG]
//
// A reflector of revolution for a point source at the origin (the emitter's
// file in the luminaire's photometric frame) and a rotationally symmetric
// target (both averaged over C): design/reflector_design.h computes the
// profile. DIR gets NAME.design.toml (the polar table as variables), the
// emitter's file beside it, NAME.gltf and NAME.bin, target.ies (the target
// as designed against), and the design traced by app::simulate: NAME.ies,
// NAME.ldt and report.json, the run's report with a "design" section: the
// inputs, the fluxes, the map, the profile, and the traced distribution
// against the target (gonio compare's figures, flux-normalised, and the
// beam angles). It also writes NAME.step and its sidecar NAME.gonio.toml
// (design::write_design_step), as `gonio design export` does for any design
// file: DIR/STEM.step, DIR/STEM.gonio.toml, DIR/STEM.gltf and .bin.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <numbers>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "design/design_export.h"
#include "design/design_file.h"
#include "design/lens_design.h"
#include "design/reflector_design.h"
#include "io/model/cad.h"
#include "io/photometric/photometric_file.h"
#include "io/photometric/tm25.h"
#include "io/support/file_io.h"
#include "io/support/text.h"
#include "photometry/beam.h"
#include "photometry/compare.h"
#include "photometry/format.h"
#include "tools/cli/cli.h"
#include "tools/cli/commands.h"
#include "tools/cli/simulate_command.h"
#include "tools/run/json_figures.h"
#include "tools/run/photometric_input.h"
#include "tools/run/photometric_report.h"
#include "tools/run/simulate.h"

namespace gonio::cli {
namespace {

namespace fs = std::filesystem;

// "A,B" as two numbers.
bool two_numbers(const std::string& text, double& a, double& b) {
  const std::size_t comma = text.find(',');
  if (comma == std::string::npos) return false;
  const std::optional<double> x = io::parse_number(text.substr(0, comma));
  const std::optional<double> y = io::parse_number(text.substr(comma + 1));
  if (!x || !y) return false;
  a = *x;
  b = *y;
  return true;
}

// A target formula: uniform:FROM,TO | cos:N,TO | linear:K,C (C in degrees).
// Nothing where `text` is not one (a file, then).
std::optional<Result<photometry::Distribution>> target_formula(const std::string& text,
                                                               const photometry::Distribution& emitter,
                                                               const design::ReflectorDesignOptions& o) {
  const std::size_t colon = text.find(':');
  if (colon == std::string::npos) return std::nullopt;
  const std::string kind = text.substr(0, colon);
  if (kind != "uniform" && kind != "cos" && kind != "linear") return std::nullopt;
  double a = 0, b = 0;
  if (!two_numbers(text.substr(colon + 1), a, b))
    return Result<photometry::Distribution>(
        make_error("--target " + io::shown(text) + ": write " + kind + ":A,B with two numbers"));
  if (kind == "linear") {
    if (a == 0.0 || a == 1.0)
      return Result<photometry::Distribution>(make_error("--target linear:K,C: K must be neither 0 nor 1"));
    return Result<photometry::Distribution>(
        design::linear_map_target(emitter, a, b * std::numbers::pi / 180.0, o.from_deg, o.to_deg, 0.01));
  }
  const double to = b, from = kind == "uniform" ? a : 0.0;
  if (!(from >= 0.0 && to > from && to <= 180.0) || (kind == "cos" && !(a >= 0.0)))
    return Result<photometry::Distribution>(make_error(
        "--target " + io::shown(text) + ": uniform:FROM,TO needs 0 ≤ FROM < TO ≤ 180, cos:N,TO needs N ≥ 0, 0 < TO ≤ 180"));
  std::vector<double> gamma, candela;
  for (int i = 0; i <= 3600; ++i) {
    const double g = 0.05 * i;
    gamma.push_back(g);
    const bool in = g >= from - 1e-9 && g <= to + 1e-9;
    candela.push_back(!in ? 0.0 : kind == "uniform" ? 1000.0 : 1000.0 * std::pow(std::max(std::cos(g * std::numbers::pi / 180.0), 0.0), a));
  }
  return Result<photometry::Distribution>(design::rotational_distribution(gamma, candela));
}

// The first bytes of a file (empty where it cannot be read): what it is.
std::string read_prefix(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return {};
  char buffer[8] = {};
  const std::size_t n = std::fread(buffer, 1, sizeof buffer, f);
  std::fclose(f);
  return std::string(buffer, n);
}

// A distribution averaged over C, on its own γ nodes.
photometry::Distribution c_mean(const photometry::Distribution& d) {
  const photometry::Distribution e = photometry::expand_symmetry(d);
  std::vector<double> candela;
  for (double g : e.vertical_deg) candela.push_back(design::rotational_intensity(e, g));
  return design::rotational_distribution(e.vertical_deg, candela);
}

int fail(const std::string& message) {
  print_error("design: " + message);
  return kExitFailure;
}

// gonio design export: a design file's parts as STEP (with its sidecar) and glTF.
// What report.json says of a design against its target: gonio compare's
// figures and the C0 beam angles of both, and the designed profile r(θ).
nlohmann::json against_target(const std::string& target_path, const photometry::Distribution& target,
                              const std::string& traced_path, const io::PhotometricFile& traced,
                              const photometry::Comparison& cmp, const photometry::CompareOptions& compare) {
  io::PhotometricFile target_file;
  target_file.distribution = target;
  nlohmann::json against = app::compare_json(target_path, target_file, traced_path, traced, cmp, compare);
  against["beam_angle_target_deg"] = app::json_number(photometry::beam_angle(target, 0.0).angle_deg);
  against["beam_angle_traced_deg"] = app::json_number(photometry::beam_angle(traced.distribution, 0.0).angle_deg);
  return against;
}

// A beam angle of against_target's, as printed (null where it is undefined).
std::string beam_text(const nlohmann::json& against, const char* key) {
  const nlohmann::json& v = against.at(key);
  return v.is_number() ? format_number(v.get<double>(), 4) : std::string("undefined");
}

nlohmann::json profile_json(const design::PolarProfile& p) {
  nlohmann::json profile = {{"theta_deg", nlohmann::json::array()}, {"r_mm", nlohmann::json::array()}};
  for (std::size_t i = 0; i < p.theta.size(); ++i) {
    profile["theta_deg"].push_back(p.theta[i] * 180.0 / std::numbers::pi);
    profile["r_mm"].push_back(p.r[i] * 1e3);
  }
  return profile;
}

int export_design(const std::string& path, const std::string& out_dir, double tolerance_mm, double gamma_step) {
  const std::string stem = design::model_stem(path);
  if (!design::is_design_path(path) || stem.empty()) return fail(path + ": not a design file (NAME.design.toml)");
  Result<design::Design> d = design::read_design_file(path);
  if (!d.ok()) return fail(to_string(d.error()));
  if (Status s = io::make_directories(out_dir); !s.ok()) return fail(to_string(s.error()));
  const std::string step_path = (fs::path(out_dir) / (stem + ".step")).string();
  Result<design::StepExportInfo> step = design::write_design_step(*d, step_path, tolerance_mm);
  if (!step.ok()) return fail(to_string(step.error()));
  const std::string gltf_path = (fs::path(out_dir) / (stem + ".gltf")).string();
  if (Status s = design::write_design_gltf(*d, gltf_path, io::tessellation_for_grid(gamma_step)); !s.ok())
    return fail(to_string(s.error()));
  std::printf("design: %s (%zu part(s), B-spline profiles within %s mm of the exact ones' samples, largest %s mm), "
              "%s, %s\n",
              step_path.c_str(), step->parts, format_number(tolerance_mm).c_str(),
              format_number(step->max_deviation_mm, 3).c_str(), step->sidecar.c_str(), gltf_path.c_str());
  return kExitOk;
}

// --feedback's default for a lens and a point source (docs/design.md,
// "Feedback for a lens"): the iterations that correct the Fresnel losses'
// dependence on the angle of incidence.
constexpr long long kLensPointFeedback = 1;

// gonio design reflector|lens: the inputs as run_design parsed them.
struct DesignRun {
  std::string kind, emitter_path, target_text, out_dir, cone, map = "uncrossed", name, die;
  double distance_mm = 0.0, inner_mm = 0.0, ior = 1.491, reflectance = 1.0, gamma_step = 1.0,
         tolerance_mm = design::kStepToleranceMm, die_w = 0.0, die_h = 0.0;
  long long nodes = 61, photons = 2'000'000, seed = 1, threads = 0, feedback = -1, die_rays = 200'000;
  bool absolute = false;
  bool ray_file = false;  // --emitter is a TM-25 ray file
  std::string correction = "auto";  // --correction: auto, part, part-steps, all or cumulative
};

// The emitter as the design file names it (copy_emitter).
struct EmitterCopy {
  std::string file, key;  // beside the design file; "profile" or "ray_file"
};

// The emitter into the output folder as the design file names it: the
// photometric file as a point source, a ray file as its rays, or a die of
// the stated size made of rays. `reach_mm`: the farthest ray origin from the
// source (0 for a point source), for the lens's cavity.
Result<EmitterCopy> copy_emitter(const DesignRun& in, const photometry::Distribution& emitter, double& reach_mm) {
  EmitterCopy out{"emitter" + fs::path(in.emitter_path).extension().string(), "profile"};
  reach_mm = 0.0;
  if (in.die_w > 0.0) {
    out = {"emitter.tm25ray", "ray_file"};
    io::Tm25RaySet rays = io::make_luminous_ray_set(
        design::die_rays(emitter, in.die_w * 1e-3, in.die_h * 1e-3, static_cast<std::size_t>(in.die_rays)));
    rays.header.light_source = "a die of " + in.die + " mm emitting " + fs::path(in.emitter_path).filename().string();
    rays.header.ray_file_creator = "gonio design " + in.kind + " --die";
    reach_mm = 0.5 * std::hypot(in.die_w, in.die_h);
    if (Status s = io::write_tm25_file((fs::path(in.out_dir) / out.file).string(), rays); !s.ok()) return s.error();
  } else if (in.ray_file) {
    // The ray file's far field (what the design used) takes its +z as the
    // nadir, +x as C0 and −y as C90 (tools/run/ray_file_far_field.h); a
    // design file places a ray set's coordinates as they are (nadir −Z): the
    // copy is turned by 180° about X, (x, y, z) → (x, −y, −z), positions and
    // directions, so that the design traces the light it was designed for.
    out = {"emitter.tm25ray", "ray_file"};
    Result<io::Tm25RaySet> rays = io::read_tm25_file(in.emitter_path);
    if (!rays.ok()) return rays.error();
    const std::size_t n = rays->ray_count(), stride = static_cast<std::size_t>(rays->columns.count);
    for (std::size_t i = 0; i < n; ++i) {
      float* ray = rays->items.data() + i * stride;
      const double x = ray[0], y = ray[1], z = ray[2];
      reach_mm = std::max(reach_mm, std::sqrt(x * x + y * y + z * z));
      for (std::size_t item : {1, 2, 4, 5}) ray[item] = -ray[item];
    }
    rays->header.additional_info =
        "turned by 180 deg about X by gonio design " + in.kind + " (the design's frame, nadir -Z)";
    if (Status s = io::write_tm25_file((fs::path(in.out_dir) / out.file).string(), *rays); !s.ok()) return s.error();
  } else {
    Result<std::string> bytes = io::read_file(in.emitter_path, std::size_t{256} << 20);
    if (!bytes.ok()) return bytes.error();
    if (Status s = io::write_file_atomic((fs::path(in.out_dir) / out.file).string(), *bytes); !s.ok()) return s.error();
  }
  return out;
}

// One design traced: what the feedback and the report read.
struct Traced {
  std::optional<app::SimulatePlan> plan;
  std::optional<app::SimulateResult> result;
  std::optional<io::PhotometricFile> file;
  // Against the target, flux-normalised: over C-γ, averaged over C, and the
  // beam: averaged over C where the target has light, scaled to the target's
  // flux there (design::in_target_scale), the rest left out: stray light
  // (a lens's Fresnel reflections, which no design of its surfaces sends
  // into the beam) counts neither against the beam's shape nor as its error.
  std::optional<photometry::Comparison> cmp, cmp_mean, cmp_beam;
};

struct TraceSetup {
  const DesignRun& in;
  const ArgParser& p;
  std::chrono::steady_clock::time_point start;
  const photometry::Distribution& target;
  std::string design_path, traced_path;
  photometry::CompareOptions compare;
};

// The share of the target the feedback corrects at γ (degrees), for a part
// that takes the emitter's light over FROM…TO (a lens: 0…TO, its light
// added to the direct light): design::design_share, and with
// --correction part-steps 0 near the target's steps.
std::function<double(double)> correction_share(const DesignRun& in, const photometry::Distribution& emitter,
                                               const photometry::Distribution& target, double from_deg, double to_deg,
                                               bool lens, double target_scale) {
  auto emitter_x = std::make_shared<const photometry::Distribution>(photometry::expand_symmetry(emitter));
  auto target_x = std::make_shared<const photometry::Distribution>(photometry::expand_symmetry(target));
  double target_peak = 0.0;
  for (double v : target.candela) target_peak = std::max(target_peak, v);
  const bool steps = in.correction == "part-steps";
  return [=](double g) {
    return design::design_share(*emitter_x, *target_x, g, from_deg, to_deg, lens, target_scale) *
           (steps ? design::away_from_steps(*target_x, target_peak, g) : 1.0);
  };
}

// report.json's comparison with the target: gonio compare's figures, and
// the trace averaged over C and over the beam (Traced's cmp_mean, cmp_beam).
nlohmann::json against_traced(const std::string& target_path, const photometry::Distribution& target,
                              const TraceSetup& setup, const Traced& t) {
  nlohmann::json against = against_target(target_path, target, setup.traced_path, *t.file, *t.cmp, setup.compare);
  against["rms_relative_c_mean"] = t.cmp_mean->rms_relative;
  against["max_relative_c_mean"] = t.cmp_mean->max_relative;
  against["rms_relative_beam"] = t.cmp_beam->rms_relative;
  against["max_relative_beam"] = t.cmp_beam->max_relative;
  return against;
}

// Traces the design file at setup.design_path with seed + iteration (each
// iteration its own seed: the correction follows the design, not one seed's
// photon noise) and compares it with the target; 0 or the exit code.
int trace_design(const TraceSetup& s, long long iteration, Traced& t) {
  app::SimulateOptions options;
  options.out_dir = s.in.out_dir;
  options.stem = s.in.name;
  options.format_list = "ies,ldt";
  options.photons = s.in.photons;
  options.iterations = 1;
  options.seed = s.in.seed + iteration;
  options.threads = s.in.threads;
  options.gamma_step = s.in.gamma_step;
  options.no_cache = true;
  t.plan = plan_or_usage("design", s.design_path, options, s.p);
  if (!t.plan) return kExitUsage;
  t.result = app::simulate(*t.plan, {}, s.start);
  if (!t.result || !t.result->files) return kExitFailure;
  Result<io::PhotometricFile> read = app::read_input(s.traced_path, app::InputOptions{}, false);
  if (!read.ok()) return kExitFailure;
  t.file = std::move(*read);
  Result<photometry::Comparison> c = photometry::compare(s.target, t.file->distribution, s.compare);
  if (!c.ok()) return fail(c.error().message);
  t.cmp = *c;
  // The design is rotationally symmetric: its error is the C-averaged trace's.
  const photometry::Distribution mean = c_mean(t.file->distribution);
  Result<photometry::Comparison> m = photometry::compare(s.target, mean, s.compare);
  if (!m.ok()) return fail(m.error().message);
  t.cmp_mean = *m;
  // The beam: the C-averaged trace where the target has light, scaled to the
  // target's flux there; its light elsewhere (stray light) left out.
  photometry::Distribution scaled = mean;
  const double k = design::in_target_scale(s.target, mean);
  const photometry::Distribution target_x = photometry::expand_symmetry(s.target);
  double peak = 0.0;
  for (double v : s.target.candela) peak = std::max(peak, v);
  for (std::size_t i = 0; i < scaled.candela.size(); ++i)
    scaled.candela[i] = design::rotational_intensity(target_x, scaled.vertical_deg[i]) > 1e-6 * peak ? k * scaled.candela[i] : 0.0;
  photometry::CompareOptions as_is = s.compare;
  as_is.normalize_flux = false;
  Result<photometry::Comparison> shape = photometry::compare(s.target, scaled, as_is);
  if (!shape.ok()) return fail(shape.error().message);
  t.cmp_beam = *shape;
  return 0;
}

struct FeedbackOutcome {
  long long kept = 0;
  std::string stopped;
  nlohmann::json history = nlohmann::json::array();
};

// The feedback both designs share (docs/design.md "Extended emitters:
// feedback"): design `d` traced; `iterations` times the target corrected by
// the trace (design::feedback_target) and designed again (`redesign`); the
// design kept (in `d`, its files written and traced again where it is not
// the last) is the iteration whose C-averaged trace is nearest the target:
// flux-normalised, or with `keep_by_beam` scaled on the target's light
// (Traced::cmp_beam). `write` writes a design's file for an iteration.
//
// `share`: the power the ratio is taken to at γ (--correction part: the
// part's share of the target, design::design_share; part-steps: that, and 0
// near the target's steps, design::away_from_steps); all: the ratio as it is.
template <class D>
int feedback_loop(D& d, const TraceSetup& setup, long long iterations, bool keep_by_beam,
                  const std::function<double(double)>& share,
                  const std::function<Status(const D&, long long)>& write,
                  const std::function<Result<D>(const photometry::Distribution&)>& redesign,
                  const std::function<const design::PolarProfile&(const D&)>& profile, Traced& t,
                  FeedbackOutcome& out) {
  auto write_and_trace = [&](const D& design, long long iteration) -> int {
    if (Status s = write(design, iteration); !s.ok()) return fail(to_string(s.error()));
    return trace_design(setup, iteration, t);
  };
  photometry::Distribution design_target = setup.target;
  std::optional<D> best;
  long long last = 0;
  double best_rms = std::numeric_limits<double>::infinity();
  for (long long iteration = 0;; ++iteration) {
    if (const int failed = write_and_trace(d, iteration); failed != 0) return failed;
    last = iteration;
    out.history.push_back(
        {{"iteration", iteration},
         {"seed", setup.in.seed + iteration},
         {"rms_relative_c_mean", t.cmp_mean->rms_relative},
         {"max_relative_c_mean", t.cmp_mean->max_relative},
         {"rms_relative_beam", t.cmp_beam->rms_relative},
         {"rms_relative", t.cmp->rms_relative},
         {"max_relative", t.cmp->max_relative},
         {"beam_angle_traced_deg", app::json_number(photometry::beam_angle(t.file->distribution, 0.0).angle_deg)}});
    const double rms = keep_by_beam ? t.cmp_beam->rms_relative : t.cmp_mean->rms_relative;
    if (rms < best_rms) {
      best_rms = rms;
      out.kept = iteration;
      best = d;
    }
    if (iteration >= iterations) break;
    // T_{n+1} = T_n · T/traced, renormalised (design::feedback_target).
    photometry::Distribution next =
        setup.in.correction == "cumulative"
            ? design::feedback_target_cumulative(design_target, setup.target, t.file->distribution)
            : design::feedback_target(design_target, setup.target, t.file->distribution, 0.01,
                                      setup.in.correction != "all" ? share : std::function<double(double)>{});
    Result<D> again = redesign(next);
    if (!again.ok()) {
      out.stopped = "iteration " + std::to_string(iteration + 1) + ": " + again.error().message;
      break;
    }
    out.history.back()["profile_change_next"] = design::profile_change(profile(d), profile(*again));
    design_target = std::move(next);
    d = std::move(*again);
  }
  if (out.kept != last) {
    // The files are the best iteration's: its design traced again with its seed (the same bytes).
    d = std::move(*best);
    if (const int failed = write_and_trace(d, out.kept); failed != 0) return failed;
  }
  return 0;
}

nlohmann::json feedback_json(const DesignRun& in, long long iterations, const FeedbackOutcome& f, bool keep_by_beam) {
  return {{"iterations", iterations},
          {"kept", f.kept},
          {"kept_by", keep_by_beam ? "rms_relative_beam" : "rms_relative_c_mean"},
          {"method", in.correction},
          {"correction", in.correction == "part" ? "multiplicative on the part's own light: T_{n+1} = T_n * (T/traced)^share, renormalised"
                         : in.correction == "part-steps"
                             ? "multiplicative on the part's own light away from the target's steps: T_{n+1} = T_n * "
                               "(T/traced)^share, share 0 within 3 deg of a step, renormalised"
                         : in.correction == "cumulative"
                             ? "cumulative: each flux quantile of T_n moved by gamma_T(u) - gamma_traced(u)"
                             : "multiplicative: T_{n+1} = T_n * T/traced, renormalised"},
          {"stopped", f.stopped.empty() ? nlohmann::json() : nlohmann::json(f.stopped)},
          {"per_iteration", f.history}};
}

void print_feedback(const FeedbackOutcome& f, bool keep_by_beam) {
  if (f.history.size() <= 1 && f.stopped.empty()) return;
  std::string line = keep_by_beam
                         ? "feedback: RMS of the C-averaged trace in the target's beam, per iteration:"
                         : "feedback: RMS of the C-averaged trace against the target, per iteration:";
  for (const nlohmann::json& h : f.history)
    line += " " + format_number(100.0 * h.at(keep_by_beam ? "rms_relative_beam" : "rms_relative_c_mean").get<double>(), 3) +
            " %";
  std::printf("%s; kept iteration %lld%s\n", line.c_str(), f.kept,
              f.stopped.empty() ? "" : (" (stopped at " + f.stopped + ")").c_str());
}

// The design file's glTF and STEP (the kept design's); the STEP's note for
// the printed line, or the exit code.
int write_cad_files(const DesignRun& in, const std::string& design_path, std::string& gltf_path,
                    std::string& step_path, std::string& step_note) {
  Result<design::Design> written = design::read_design_file(design_path);
  if (!written.ok()) return fail(to_string(written.error()));
  gltf_path = (fs::path(in.out_dir) / (in.name + ".gltf")).string();
  if (Status s = design::write_design_gltf(*written, gltf_path, io::tessellation_for_grid(in.gamma_step)); !s.ok())
    return fail(to_string(s.error()));
  step_path = (fs::path(in.out_dir) / (in.name + ".step")).string();
  if (io::cad_supported()) {
    Result<design::StepExportInfo> step = design::write_design_step(*written, step_path, in.tolerance_mm);
    if (!step.ok()) return fail(to_string(step.error()));
    step_note = ", " + step_path;
  } else {
    step_note = " (no STEP: this gonio was built without OpenCASCADE)";
  }
  return 0;
}

// The target: a formula (the lens's own linear:K,0, or target_formula's) or a file.
std::optional<photometry::Distribution> read_target(const DesignRun& in, const photometry::Distribution& emitter,
                                                    const design::ReflectorDesignOptions& o, double lens_to_deg,
                                                    const ArgParser& p, int& code) {
  if (in.kind == "lens" && in.target_text.rfind("linear:", 0) == 0) {
    double k = 0.0, c = 0.0;
    if (!two_numbers(in.target_text.substr(7), k, c) || k == 0.0 || c != 0.0) {
      print_usage_error("design", p, "--target linear:K,0 (a lens's exact case φ = Kθ): K ≠ 0, C = 0");
      code = kExitUsage;
      return std::nullopt;
    }
    return design::linear_lens_target(emitter, k, lens_to_deg, 0.01);
  }
  if (std::optional<Result<photometry::Distribution>> formula = target_formula(in.target_text, emitter, o)) {
    if (!formula->ok()) {
      print_usage_error("design", p, formula->error().message);
      code = kExitUsage;
      return std::nullopt;
    }
    return std::move(formula->value());
  }
  Result<io::PhotometricFile> file = app::read_input(in.target_text, app::InputOptions{}, false);
  if (!file.ok()) {
    code = kExitFailure;
    return std::nullopt;
  }
  return std::move(file->distribution);
}

// The design's text for the files' comment: "Emitter …, target …, cone …°, map …".
std::string inputs_note(const DesignRun& in, long long iteration) {
  return "Emitter " + fs::path(in.emitter_path).filename().string() +
         (in.die_w > 0.0 ? " as a die of " + in.die + " mm" : "") + ", target " + in.target_text + ", cone " + in.cone +
         "°, map " + in.map + (iteration > 0 ? ", feedback iteration " + std::to_string(iteration) : "");
}

// A lens of revolution (design/lens_design.h): the files as the reflector's,
// the design traced against the target, with feedback as the reflector's.
int design_lens(const DesignRun& in_args, const ArgParser& p, std::chrono::steady_clock::time_point start) {
  // auto: part. The cumulative correction takes the trace's light where the
  // lens sends it; the Fresnel reflections' stray light (7 % above 90°)
  // would shift every quantile of the beam (docs/design.md).
  DesignRun in = in_args;
  if (in.correction == "auto") in.correction = "part";
  design::LensDesignOptions o;
  double from = 0.0;
  if (!two_numbers(in.cone, from, o.to_deg) || from != 0.0 || !(o.to_deg > 0.0 && o.to_deg < 90.0)) {
    print_usage_error("design", p,
                      "--cone " + io::shown(in.cone) + ": a lens caps the source: give 0,TO in degrees, 0 < TO < 90");
    return kExitUsage;
  }
  if (!(in.ior > 1.0 && in.ior < 5.0)) {
    print_usage_error("design", p, "--ior must lie in (1, 5)");
    return kExitUsage;
  }
  o.map = in.map == "crossed" ? design::ReflectorMap::Crossed : design::ReflectorMap::Uncrossed;
  o.ior = in.ior;
  o.distance_m = in.distance_mm * 1e-3;
  o.inner_radius_m = (in.inner_mm > 0.0 ? in.inner_mm : 0.5 * in.distance_mm) * 1e-3;
  o.absolute = in.absolute;
  if (in.die_w > 0.0 && !(0.5 * std::hypot(in.die_w, in.die_h) < o.inner_radius_m * 1e3)) {
    print_usage_error("design", p,
                      "--die " + io::shown(in.die) + ": the die's corners lie " +
                          format_number(0.5 * std::hypot(in.die_w, in.die_h), 4) +
                          " mm from the source, not inside the lens's inner sphere (--inner, " +
                          format_number(o.inner_radius_m * 1e3, 4) + " mm): give a larger --inner or a smaller die");
    return kExitUsage;
  }
  Result<io::PhotometricFile> emitter = app::read_input(in.emitter_path, app::InputOptions{}, false);
  if (!emitter.ok()) return kExitFailure;
  int code = 0;
  std::optional<photometry::Distribution> target =
      read_target(in, emitter->distribution, design::ReflectorDesignOptions{}, o.to_deg, p, code);
  if (!target) return code;
  Result<design::LensDesign> d = design::design_lens(emitter->distribution, *target, o);
  if (!d.ok()) return fail("no lens gives this target: " + d.error().message);

  if (in.ray_file) {
    // The rays start in the cavity, or the design would trace them from inside the glass.
    Result<io::Tm25RaySet> rays = io::read_tm25_file(in.emitter_path);
    if (!rays.ok()) return fail(to_string(rays.error()));
    double reach_mm = 0.0;
    for (std::size_t i = 0; i < rays->ray_count(); ++i) {
      const float* ray = rays->ray(i);
      const double x = ray[0], y = ray[1], z = ray[2];
      reach_mm = std::max(reach_mm, std::sqrt(x * x + y * y + z * z));
    }
    if (!(reach_mm < o.inner_radius_m * 1e3))
      return fail(in.emitter_path + ": the ray file's rays start up to " + format_number(reach_mm, 4) +
                  " mm from the source, not inside the lens's inner sphere (--inner, " +
                  format_number(o.inner_radius_m * 1e3, 4) + " mm): give a larger --inner");
  }
  const fs::path dir(in.out_dir);
  if (Status s = io::make_directories(in.out_dir); !s.ok()) return fail(to_string(s.error()));
  double reach_mm = 0.0;
  Result<EmitterCopy> emitter_copy = copy_emitter(in, emitter->distribution, reach_mm);
  if (!emitter_copy.ok()) return fail(to_string(emitter_copy.error()));
  const std::string design_path = (dir / (in.name + ".design.toml")).string();
  const std::string target_path = (dir / "target.ies").string();
  if (Status s = io::write_photometric_file(target_path, *target, {}, nullptr); !s.ok()) return fail(to_string(s.error()));
  const bool extended = in.ray_file || in.die_w > 0.0;
  const long long iterations = in.feedback >= 0 ? in.feedback : (extended ? 3 : kLensPointFeedback);
  photometry::CompareOptions compare;
  compare.gamma_step_deg = 90.0 / std::round(90.0 / in.gamma_step);
  compare.normalize_flux = true;  // Fresnel reflections at both faces are real: compare the shapes
  const TraceSetup setup{in, p, start, *target, design_path, (dir / (in.name + ".ies")).string(), compare};
  Traced t;
  FeedbackOutcome f;
  design::LensDesignOptions again = o;
  again.allow_deficit = true;
  const std::function<Status(const design::LensDesign&, long long)> write = [&](const design::LensDesign& l,
                                                                                 long long iteration) -> Status {
    const std::string text = design::write_design(
        design::lens_design_document(l, emitter_copy->file, o.ior, in.name, emitter_copy->key),
        {"A lens designed by gonio design lens (docs/design.md).",
         inputs_note(in, iteration) + ", n = " + format_number(o.ior) + "."});
    return io::write_file_atomic(design_path, text);
  };
  const std::function<Result<design::LensDesign>(const photometry::Distribution&)> redesign =
      [&](const photometry::Distribution& next) { return design::design_lens(emitter->distribution, next, again); };
  const std::function<const design::PolarProfile&(const design::LensDesign&)> profile_of =
      [](const design::LensDesign& l) -> const design::PolarProfile& { return l.outer; };
  // The first design's scale: the user's target's.
  const std::function<double(double)> share =
      correction_share(in, emitter->distribution, *target, 0.0, o.to_deg, true, d->target_scale);
  if (const int failed =
          feedback_loop<design::LensDesign>(*d, setup, iterations, true, share, write, redesign, profile_of, t, f);
      failed != 0)
    return failed;
  const int run_code = print_run_files(*t.plan, t.result->run, *t.result->files);
  std::string gltf_path, step_path, step_note;
  if (const int failed = write_cad_files(in, design_path, gltf_path, step_path, step_note); failed != 0) return failed;

  nlohmann::json against = against_traced(target_path, *target, setup, t);
  const nlohmann::json profile = profile_json(d->outer);
  nlohmann::json report = t.result->files->report;
  report["design"] = {{"kind", "lens"},
                      {"emitter", in.emitter_path},
                      {"die_mm", in.die_w > 0.0 ? nlohmann::json::array({in.die_w, in.die_h}) : nlohmann::json()},
                      {"extended", extended},
                      {"target", in.target_text},
                      {"map", in.map},
                      {"cone_deg", {0.0, o.to_deg}},
                      {"ior", o.ior},
                      {"distance_mm", in.distance_mm},
                      {"inner_radius_mm", o.inner_radius_m * 1e3},
                      {"absolute", in.absolute},
                      {"emitter_flux_lm", d->emitter_flux_lm},
                      {"cone_flux_lm", d->cone_flux_lm},
                      {"direct_flux_lm", d->direct_flux_lm},
                      {"target_scale", d->target_scale},
                      {"refracted_gamma_deg", {d->target_from_deg, d->target_to_deg}},
                      {"largest_deviation_deg", d->largest_deviation_deg},
                      {"thinnest_mm", d->thinnest_m * 1e3},
                      {"files", {design_path, emitter_copy->file, gltf_path, step_path, target_path}},
                      {"outer_profile", profile},
                      {"feedback", feedback_json(in, iterations, f, true)},
                      {"against_target", against}};
  if (Status s = io::write_file_atomic(t.result->files->report_path, report.dump(2) + "\n"); !s.ok())
    return fail(to_string(s.error()));
  std::printf("design: %s (%zu points, map %s, cone %s°, n %s), %s%s, target.ies\n", design_path.c_str(),
              d->outer.theta.size(), in.map.c_str(), in.cone.c_str(), format_number(o.ior).c_str(), gltf_path.c_str(),
              step_note.c_str());
  print_feedback(f, true);
  std::printf("against the target (flux-normalised): RMS %s %% of its peak, largest %s %%, beam angle %s° (target %s°); "
              "in the target's beam (averaged over C, scaled to its flux there): RMS %s %%\n",
              format_number(100.0 * t.cmp->rms_relative, 3).c_str(), format_number(100.0 * t.cmp->max_relative, 3).c_str(),
              beam_text(against, "beam_angle_traced_deg").c_str(), beam_text(against, "beam_angle_target_deg").c_str(),
              format_number(100.0 * t.cmp_beam->rms_relative, 3).c_str());
  return run_code;
}

// A reflector of revolution (design/reflector_design.h).
int design_reflector(const DesignRun& in_args, const ArgParser& p, std::chrono::steady_clock::time_point start) {
  DesignRun in = in_args;
  design::ReflectorDesignOptions o;
  if (!two_numbers(in.cone, o.from_deg, o.to_deg) || !(o.from_deg >= 0 && o.from_deg < o.to_deg && o.to_deg <= 180)) {
    print_usage_error("design", p, "--cone " + io::shown(in.cone) + ": give FROM,TO in degrees, 0 ≤ FROM < TO ≤ 180");
    return kExitUsage;
  }
  o.map = in.map == "crossed" ? design::ReflectorMap::Crossed : design::ReflectorMap::Uncrossed;
  o.distance_m = in.distance_mm * 1e-3;
  o.nodes = static_cast<int>(in.nodes);
  o.absolute = in.absolute;
  o.reflectance = in.reflectance;

  Result<io::PhotometricFile> emitter = app::read_input(in.emitter_path, app::InputOptions{}, false);
  if (!emitter.ok()) return kExitFailure;
  int code = 0;
  std::optional<photometry::Distribution> target = read_target(in, emitter->distribution, o, 0.0, p, code);
  if (!target) return code;
  Result<design::ReflectorDesign> d = design::design_reflector(emitter->distribution, *target, o);
  if (!d.ok()) return fail("no reflector gives this target: " + d.error().message);
  if (in.correction == "auto") {
    // auto: cumulative for an extended emitter and a target without steps
    // (it wins on the exact cases' table), part for a target with steps (it
    // wins on the corpus LED's) and for a point source (which needs no
    // correction of blur: the cumulative one moves its profile by 0.7 % on
    // photon noise, the ratio by 0.03 %): docs/design.md, "Targets with steps".
    const photometry::Distribution expanded = photometry::expand_symmetry(*target);
    double peak = 0.0;
    for (double v : target->candela) peak = std::max(peak, v);
    bool steps = false;
    for (int g = 0; g <= 180 && !steps; ++g) steps = design::away_from_steps(expanded, peak, g) == 0.0;
    in.correction = steps || !(in.ray_file || in.die_w > 0.0) ? "part" : "cumulative";
  }

  const bool extended = in.ray_file || in.die_w > 0.0;
  const long long iterations = in.feedback >= 0 ? in.feedback : (extended ? 3 : 0);
  if (Status s = io::make_directories(in.out_dir); !s.ok()) return fail(to_string(s.error()));
  double reach_mm = 0.0;
  Result<EmitterCopy> emitter_copy = copy_emitter(in, emitter->distribution, reach_mm);
  if (!emitter_copy.ok()) return fail(to_string(emitter_copy.error()));
  const std::string design_path = (fs::path(in.out_dir) / (in.name + ".design.toml")).string();
  const std::string target_path = (fs::path(in.out_dir) / "target.ies").string();
  if (Status s = io::write_photometric_file(target_path, *target, {}, nullptr); !s.ok()) return fail(to_string(s.error()));
  photometry::CompareOptions compare;
  compare.gamma_step_deg = 90.0 / std::round(90.0 / in.gamma_step);
  compare.normalize_flux = true;
  const TraceSetup setup{in, p, start, *target, design_path, (fs::path(in.out_dir) / (in.name + ".ies")).string(), compare};
  Traced t;
  FeedbackOutcome f;
  design::ReflectorDesignOptions again = o;
  again.allow_deficit = true;
  const std::function<Status(const design::ReflectorDesign&, long long)> write =
      [&](const design::ReflectorDesign& r, long long iteration) -> Status {
    const std::string text = design::write_design(
        design::reflector_design_document(r, emitter_copy->file, in.reflectance, in.name, emitter_copy->key),
        {"A reflector designed by gonio design reflector (docs/design.md).", inputs_note(in, iteration) + "."});
    return io::write_file_atomic(design_path, text);
  };
  const std::function<Result<design::ReflectorDesign>(const photometry::Distribution&)> redesign =
      [&](const photometry::Distribution& next) { return design::design_reflector(emitter->distribution, next, again); };
  const std::function<const design::PolarProfile&(const design::ReflectorDesign&)> profile_of =
      [](const design::ReflectorDesign& r) -> const design::PolarProfile& { return r.profile; };
  // The first design's scale: the user's target's.
  const std::function<double(double)> share =
      correction_share(in, emitter->distribution, *target, o.from_deg, o.to_deg, false, d->target_scale);
  if (const int failed =
          feedback_loop<design::ReflectorDesign>(*d, setup, iterations, false, share, write, redesign, profile_of, t, f);
      failed != 0)
    return failed;
  const int run_code = print_run_files(*t.plan, t.result->run, *t.result->files);
  std::string gltf_path, step_path, step_note;
  if (const int failed = write_cad_files(in, design_path, gltf_path, step_path, step_note); failed != 0) return failed;

  // Against the target.
  nlohmann::json against = against_traced(target_path, *target, setup, t);
  const nlohmann::json profile = profile_json(d->profile);
  nlohmann::json report = t.result->files->report;
  report["design"] = {{"kind", "reflector"},
                      {"emitter", in.emitter_path},
                      {"die_mm", in.die_w > 0.0 ? nlohmann::json::array({in.die_w, in.die_h}) : nlohmann::json()},
                      {"extended", extended},
                      {"target", in.target_text},
                      {"map", in.map},
                      {"cone_deg", {o.from_deg, o.to_deg}},
                      {"distance_mm", in.distance_mm},
                      {"reflectance", in.reflectance},
                      {"absolute", in.absolute},
                      {"emitter_flux_lm", d->emitter_flux_lm},
                      {"cone_flux_lm", d->cone_flux_lm},
                      {"direct_flux_lm", d->direct_flux_lm},
                      {"target_scale", d->target_scale},
                      {"reflected_gamma_deg", {d->target_from_deg, d->target_to_deg}},
                      {"files", {design_path, emitter_copy->file, gltf_path, step_path, target_path}},
                      {"profile", profile},
                      {"feedback", feedback_json(in, iterations, f, false)},
                      {"against_target", against}};
  if (Status s = io::write_file_atomic(t.result->files->report_path, report.dump(2) + "\n"); !s.ok())
    return fail(to_string(s.error()));
  std::printf("design: %s (%zu points, map %s, cone %s°), %s%s, target.ies\n", design_path.c_str(),
              d->profile.theta.size(), in.map.c_str(), in.cone.c_str(), gltf_path.c_str(), step_note.c_str());
  print_feedback(f, false);
  std::printf("against the target: RMS %s %% of its peak (averaged over C: %s %%), largest %s %%, beam angle %s° (target %s°)\n",
              format_number(100.0 * t.cmp->rms_relative, 3).c_str(), format_number(100.0 * t.cmp_mean->rms_relative, 3).c_str(),
              format_number(100.0 * t.cmp->max_relative, 3).c_str(),
              beam_text(against, "beam_angle_traced_deg").c_str(), beam_text(against, "beam_angle_target_deg").c_str());
  return run_code;
}

}  // namespace

int run_design(const Args& args) {
  const auto start = std::chrono::steady_clock::now();
  DesignRun in;
  std::vector<std::string> files;
  ArgParser p("design",
              "reflector|lens --emitter FILE --target FILE|FORMULA --out DIR [options]\n"
              "       gonio design export FILE.design.toml --out DIR [--tolerance MM] [--gamma-step DEG]",
              "Designs a reflector of revolution that turns a point source's light into a\n"
              "rotationally symmetric target (both averaged over C): the energy-conserving map\n"
              "from the emitter's cone to the target's, and the profile from the reflector\n"
              "equation d(ln r)/dθ = cot((φ − θ)/2). Writes DIR/NAME.design.toml (the profile's\n"
              "polar table as variables), the emitter's file beside it, DIR/NAME.gltf,\n"
              "DIR/target.ies, and the design traced: DIR/NAME.ies, DIR/NAME.ldt and\n"
              "DIR/report.json with the design's figures against the target. A target no\n"
              "reflector can give is an error saying why. FORMULA: uniform:FROM,TO (constant\n"
              "intensity over γ FROM…TO), cos:N,TO (cosⁿγ to TO), linear:K,C (the exact case\n"
              "φ = Kθ + C° of the emitter over the cone, with its direct light); it also writes\n"
              "DIR/NAME.step (B-spline surfaces of revolution, named parts) and its sidecar\n"
              "DIR/NAME.gonio.toml. `gonio design export FILE.design.toml --out DIR` writes\n"
              "any design file's parts as DIR/STEM.step (with STEM.gonio.toml) and DIR/STEM.gltf.\n"
              "`gonio design lens` designs a lens of revolution instead: an inner sphere about\n"
              "the source and an outer surface from Snell's law, d(ln r)/dθ = sin(φ − θ)/(n −\n"
              "cos(φ − θ)), over the cone 0…TO; linear:K,0 is its exact case φ = Kθ.");
  p.positional("KIND", &in.kind,
               "what to do: reflector or lens (design one) or export (write a design file as STEP and glTF)");
  p.positional_list("FILE", &files, 0, "export: the design file");
  p.option("emitter", &in.emitter_path, "FILE", "the source: a photometric file (IES, LDT, TM-33; nadir −Z) or a TM-25 ray file");
  p.option("target", &in.target_text, "FILE|FORMULA", "the target distribution: a photometric file or a formula");
  p.option("out", &in.out_dir, "DIR", "output directory (created if missing)");
  p.option("cone", &in.cone, "FROM,TO", "the emitter's γ range the part catches [deg] (default 45,180; lens 0,60)");
  p.option("map", &in.map, "uncrossed|crossed",
           "uncrossed: reflected rays stay on their side of the axis (default); crossed: they cross it");
  p.option("distance", &in.distance_mm, 0.001, 1e6, "MM",
           "the reflector's distance from the source at TO (default 20); the lens's outer vertex's at 0 (default 10)");
  p.option("ior", &in.ior, 1.000001, 5.0, "N", "lens: the glass's refractive index (default 1.491, PMMA at 587.6 nm)");
  p.option("inner", &in.inner_mm, 0.001, 1e6, "MM", "lens: the radius of the inner sphere about the source (default --distance / 2)");
  p.option("nodes", &in.nodes, 4, 10000, "N", "points of the profile's polar table (default 61)");
  p.option("reflectance", &in.reflectance, 1e-6, 1.0, "R", "the mirror's specular reflectance (default 1)");
  p.flag("absolute", &in.absolute, "take the target's candela as they are, not scaled to the flux that leaves");
  p.option("name", &in.name, "NAME", "the part's and the files' name (default reflector, or lens)");
  p.option("photons", &in.photons, 1, 4'294'967'295LL, "N", "photons of the trace (default 2000000)");
  p.option("seed", &in.seed, 0, 9'223'372'036'854'775'807LL, "S", "seed of the trace (default 1)");
  p.option("threads", &in.threads, 0, 4096, "T", "threads of the trace (default 0: all cores)");
  p.option("gamma-step", &in.gamma_step, 0.1, 90.0, "DEG", "γ step of the traced files and the comparison (default 1)");
  p.option("tolerance", &in.tolerance_mm, 1e-6, 1.0, "MM",
           "STEP: the B-spline profiles' largest distance from the exact profile's samples (default 0.001)");
  p.option("die", &in.die, "WxH",
           "an extended emitter: a die of W × H mm in the XY plane, every point emitting the emitter's distribution "
           "(written as a ray file, emitter.tm25ray)");
  p.option("correction", &in.correction, "auto|part|part-steps|all|cumulative",
           "feedback: part corrects the target only where it is the part's own light, by that share; part-steps also "
           "not within 3° of a step of the target; all corrects it everywhere (before 2026-12-07); cumulative moves "
           "the target's light by the traced quantiles' shift; auto (default): cumulative for a reflector with an "
           "extended emitter and a target without steps, else part");
  p.option("die-rays", &in.die_rays, 1000, 100'000'000, "N", "rays of the die's ray file (default 200000)");
  p.option("feedback", &in.feedback, 0, 20, "N",
           "design again N times, each for the target corrected by the trace (default 3 for an extended emitter: a ray "
           "file or --die; for a point source 0 for a reflector, 1 for a lens: its Fresnel losses)");
  if (const auto outcome = p.parse(args); outcome != ArgParser::Outcome::Run) return ArgParser::exit_code(outcome);
  if (in.kind == "export") {
    if (files.size() != 1 || in.out_dir.empty()) {
      print_usage_error("design", p, files.size() != 1 ? "export takes one design file" : "--out DIR is required");
      return kExitUsage;
    }
    return export_design(files[0], in.out_dir, in.tolerance_mm, in.gamma_step);
  }
  if (!files.empty()) {
    print_usage_error("design", p, "unexpected argument " + io::shown(files[0]));
    return kExitUsage;
  }
  if (in.kind != "reflector" && in.kind != "lens") {
    print_usage_error("design", p, "KIND must be 'reflector', 'lens' or 'export'");
    return kExitUsage;
  }
  if (in.name.empty()) in.name = in.kind;
  if (in.cone.empty()) in.cone = in.kind == "lens" ? "0,60" : "45,180";
  if (in.distance_mm == 0.0) in.distance_mm = in.kind == "lens" ? 10.0 : 20.0;
  for (auto [value, option] : {std::pair{&in.emitter_path, "--emitter FILE"}, std::pair{&in.target_text, "--target"},
                               std::pair{&in.out_dir, "--out DIR"}})
    if (value->empty()) {
      print_usage_error("design", p, std::string(option) + " is required");
      return kExitUsage;
    }
  if (in.map != "uncrossed" && in.map != "crossed") {
    print_usage_error("design", p, "--map must be uncrossed or crossed");
    return kExitUsage;
  }
  if (in.name.find_first_of("/\\*?[]") != std::string::npos) {
    print_usage_error("design", p, "--name must be a plain name (no / \\ * ? [ ])");
    return kExitUsage;
  }
  if (in.correction != "auto" && in.correction != "part" && in.correction != "part-steps" && in.correction != "all" &&
      in.correction != "cumulative") {
    print_usage_error("design", p, "--correction must be auto, part, part-steps, all or cumulative");
    return kExitUsage;
  }
  in.ray_file = io::looks_like_tm25(read_prefix(in.emitter_path));
  if (!in.die.empty()) {
    const std::size_t x = in.die.find_first_of("xX");
    const std::optional<double> w = x == std::string::npos ? std::nullopt : io::parse_number(in.die.substr(0, x));
    const std::optional<double> h = x == std::string::npos ? std::nullopt : io::parse_number(in.die.substr(x + 1));
    if (!w || !h || !(*w > 0.0 && *h > 0.0 && *w <= 1e4 && *h <= 1e4)) {
      print_usage_error("design", p, "--die " + io::shown(in.die) + ": give WxH in millimetres, both > 0 (e.g. 1x1)");
      return kExitUsage;
    }
    if (in.ray_file) {
      print_usage_error("design", p, "--die applies to a photometric file, not to a ray file (its rays are the die)");
      return kExitUsage;
    }
    in.die_w = *w;
    in.die_h = *h;
  }
  return in.kind == "lens" ? design_lens(in, p, start) : design_reflector(in, p, start);  // auto resolved there
}

}  // namespace gonio::cli
