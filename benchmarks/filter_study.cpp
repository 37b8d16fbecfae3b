// gonio_filter_study: the measurement behind the preview filter's defaults.
//
// Synthetic far fields with known intensity (smooth lobes, hard cut-offs, a
// narrow beam, a spot over a cube corner, strut shadows) are filled with
// photons drawn from them, as a tracer fills its histogram, and the preview
// of every configuration is compared with the exact (converged) map at
// several photon densities. The error is the solid-angle weighted relative
// RMS error sqrt(Σ Ω (I − R)² / Σ Ω R²), the thesis's RMSE (chapter 8) made
// independent of the source's flux. The score of a configuration is the
// geometric mean over fields and densities of its error divided by the raw
// map's error: below 1 the preview is better than the histogram.
//
// Usage: gonio_filter_study [--face-size N] [--seed S] [--broad | --confirm] [--traced]
//                           [--gltf MODEL]... [--reference PHOTONS_PER_TEXEL] [--detail NAME]...
//   --broad sweeps every family of configurations in coarse steps (which
//   families work); the default sweeps around the winners; --confirm checks
//   the chosen defaults against their neighbours (run it with other seeds).
//   --traced measures on luminaires traced by the photon tracer (a bell with
//   an opal shade, a reflector spot, built in code; or the glTF models given
//   with --gltf) against a run of --reference photons per texel (1000), up to
//   40 photons per texel (minutes); --detail prints a configuration's error
//   ratio per field and density.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <map>
#include <memory>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "benchmarks/bench_scenes.h"
#include "io/model/gltf.h"
#include "sim/detectors/far_field_sampler.h"
#include "sim/filter/preview_filter.h"
#include "sim/shapes.h"
#include "sim/simulation.h"

namespace {

using gonio::Result;
using gonio::Vec3;
using namespace gonio::sim;
namespace sim = gonio::sim;
namespace bench = gonio::bench;

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

struct Field {
  std::string name;
  std::function<double(const Vec3&)> intensity;  // [cd] of a unit direction
};

double angle_between(const Vec3& a, const Vec3& b) {
  return std::acos(std::clamp(dot(a, b), -1.0, 1.0));
}

std::vector<Field> fields() {
  const Vec3 nadir{0, -1, 0};
  const Vec3 corner = gonio::normalize(Vec3{1, -1, 1});
  return {
      {"lambert", [](const Vec3& d) { return std::max(0.0, -d.y) + 0.02; }},
      {"asym-lobe",
       [](const Vec3& d) {
         const double c = std::max(0.0, -d.y);
         return (1.0 + 0.6 * d.x) * c * c + 0.05 * std::max(0.0, d.y) + 0.01;
       }},
      {"spot30", [=](const Vec3& d) { return angle_between(d, nadir) < 30 * kDeg ? 1.0 : 0.01; }},
      {"corner-spot25",
       [=](const Vec3& d) { return angle_between(d, corner) < 25 * kDeg ? 1.0 : 0.01; }},
      {"beam10",
       [=](const Vec3& d) {
         const double a = angle_between(d, nadir) / (5.0 * kDeg);  // σ = 5°: FWHM 11.8°
         return std::exp(-0.5 * a * a) + 0.002;
       }},
      {"struts",
       [](const Vec3& d) {
         if (d.y >= 0.0) return 0.02;
         // Four 6°-wide strut shadows at C = 0°, 90°, 180°, 270° (and 45° off).
         const double c = std::atan2(d.z, d.x) + kPi / 4;
         const double to_strut = std::abs(std::remainder(c, kPi / 2));
         const double half = 3.0 * kDeg;
         return to_strut < half ? 0.03 : -d.y + 0.02;
       }},
  };
}

struct Config {
  std::string name;
  PreviewFilterParams params;
  double density_kappa = 0.0;  // > 0: threshold = κ · mean photons per texel
  bool raw = false;
  int level_delta = 0;         // ≠ 0: the automatic levels for the face size + this
};

std::string fmt(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// A configuration's name: every parameter that differs from the study's
// baseline (σ_d = 0.5, σ_r = 0.2, shadow borders on).
std::string describe(const PreviewFilterParams& p, double kappa) {
  std::string s = p.adaptive ? "adaptive " : (kappa > 0.0 ? "density " : "fixed ");
  s += p.interpolation == Interpolation::Bilinear
           ? "bilinear"
           : (p.range_scale == RangeScale::Estimate ? "bilateral/est" : "bilateral/max");
  s += kappa > 0.0 ? " T=" + fmt(kappa) + "·n̄"
                   : " T=" + (p.threshold_photons > 1e100 ? std::string("inf") : fmt(p.threshold_photons));
  s += " L=" + (p.levels >= 16 ? std::string("all") : (p.levels == 0 ? std::string("auto") : std::to_string(p.levels)));
  if (p.adaptive) s += " z=" + fmt(p.adaptive_z);
  if (p.interpolation == Interpolation::Bilateral && (p.sigma_d != 0.5 || p.sigma_r != 0.2))
    s += " sd=" + fmt(p.sigma_d) + " sr=" + fmt(p.sigma_r);
  if (!p.shadow_borders) s += " no-borders";
  return s;
}

struct Builder {
  std::vector<Config> out;
  void add(const PreviewFilterParams& p, double kappa = 0.0) {
    const std::string name = describe(p, kappa);
    for (const Config& c : out)
      if (c.name == name) return;
    out.push_back({name, p, kappa});
  }
};

PreviewFilterParams make(Interpolation kind, RangeScale scale, double threshold, int levels, bool adaptive) {
  PreviewFilterParams p;
  p.interpolation = kind;
  p.range_scale = scale;
  p.threshold_photons = threshold;
  p.levels = levels;
  p.adaptive = adaptive;
  return p;
}

constexpr Interpolation kBilinear = Interpolation::Bilinear, kBilateral = Interpolation::Bilateral;
constexpr RangeScale kEst = RangeScale::Estimate, kMax = RangeScale::LocalMax;

// The broad sweep (every family, coarse steps): which families work.
std::vector<Config> broad() {
  Builder b;
  b.out.push_back({"raw", {}, 0.0, true});
  for (auto [kind, scale] : {std::pair{kBilinear, kEst}, {kBilateral, kEst}, {kBilateral, kMax}}) {
    for (double t : {10.0, 25.0, 50.0, 100.0, 200.0, 400.0, 800.0})
      for (int levels : {4, 6, 16}) b.add(make(kind, scale, t, levels, false));
    for (double t : {50.0, 100.0, 400.0}) {
      PreviewFilterParams p = make(kind, scale, t, 16, false);
      p.shadow_borders = false;
      b.add(p);
    }
    for (double z : {2.0, 3.0, 4.0, 5.0}) {
      for (double cap : {100.0, 400.0, 1600.0, 6400.0, 25600.0, 1e300}) {
        for (int levels : {4, 6, 16}) {
          PreviewFilterParams p = make(kind, scale, cap, levels, true);
          p.adaptive_z = z;
          b.add(p);
          p.shadow_borders = false;
          if (levels == 16) b.add(p);
        }
      }
    }
  }
  for (RangeScale scale : {kEst, kMax})
    for (double sd : {0.25, 0.5, 1.0})
      for (double sr : {0.1, 0.2, 0.4, 0.8}) {
        PreviewFilterParams p = make(kBilateral, scale, 100.0, 16, false);
        p.sigma_d = sd;
        p.sigma_r = sr;
        b.add(p);
      }
  for (double kappa : {0.5, 1.0, 2.0, 4.0, 8.0}) b.add(make(kBilateral, kEst, 0.0, 16, false), kappa);
  return b.out;
}

// The confirmation: the defaults against their neighbours and the thesis's
// fixed threshold, for other seeds and face sizes.
std::vector<Config> confirm() {
  Builder b;
  b.out.push_back({"raw", {}, 0.0, true});
  const PreviewFilterParams defaults;
  b.add(defaults);
  for (double z : {3.0, 4.0}) {
    PreviewFilterParams p = defaults;
    p.adaptive_z = z;
    b.add(p);
  }
  for (double cap : {1600.0, 25600.0, 1e300}) {
    PreviewFilterParams p = defaults;
    p.threshold_photons = cap;
    b.add(p);
  }
  for (int delta : {-1, 1}) {
    b.out.push_back({"", defaults, 0.0, false, delta});  // resolved in main()
  }
  PreviewFilterParams bilinear = defaults;
  bilinear.interpolation = kBilinear;
  b.add(bilinear);
  PreviewFilterParams thesis = defaults;
  thesis.adaptive = false;
  thesis.threshold_photons = PreviewFilterParams::kFixedThreshold;
  b.add(thesis);
  thesis.interpolation = kBilinear;
  b.add(thesis);
  b.add(make(kBilateral, kMax, 0.0, 0, false), 2.0);
  return b.out;
}

// The focused sweep around the families that won the broad one: levels,
// thresholds, σ_d and σ_r for the fixed and the adaptive filter.
std::vector<Config> focused() {
  Builder b;
  b.out.push_back({"raw", {}, 0.0, true});
  for (auto [kind, scale] : {std::pair{kBilinear, kEst}, {kBilateral, kMax}}) {
    for (int levels : {3, 4, 5, 6, 16}) {
      for (double t : {25.0, 50.0, 100.0, 200.0}) b.add(make(kind, scale, t, levels, false));
      for (double cap : {1600.0, 6400.0, 25600.0}) b.add(make(kind, scale, cap, levels, true));
    }
  }
  for (bool adaptive : {false, true}) {
    for (int levels : {4, 5}) {
      for (double sd : {0.35, 0.5, 0.7, 1.0}) {
        for (double sr : {0.1, 0.2, 0.3, 0.5, 0.8}) {
          PreviewFilterParams p = make(kBilateral, kMax, adaptive ? 6400.0 : 100.0, levels, adaptive);
          p.sigma_d = sd;
          p.sigma_r = sr;
          b.add(p);
        }
      }
    }
  }
  for (double z : {2.5, 3.0, 3.5})
    for (int levels : {4, 5}) {
      PreviewFilterParams p = make(kBilateral, kMax, 6400.0, levels, true);
      p.adaptive_z = z;
      b.add(p);
    }
  return b.out;
}

struct Truth {
  std::vector<double> intensity;  // exact texel mean [cd], or a long run's
  std::vector<double> omega;      // [sr]
  double flux = 0.0;              // [lm]
  double norm = 0.0;              // Σ Ω R²
  double noise = 0.0;             // Σ Ω var(R): a long run's own photon noise, 0 if exact
};

// The relative RMS error; a reference's own noise, independent of the
// estimate's, adds Σ Ω var(R) to the squared error and is taken out.
double rel_rms(const Truth& truth, std::span<const double> estimate, double scale) {
  double err = 0.0;
  for (std::size_t t = 0; t < estimate.size(); ++t) {
    const double d = estimate[t] * scale - truth.intensity[t];
    err += truth.omega[t] * d * d;
  }
  return std::sqrt(std::max(err - truth.noise, 0.0) / truth.norm);
}

// Traced far fields: luminaires built in code, a long run as the reference.
struct TracedCase {
  std::string name;
  sim::SceneDesc scene;
};

// The luminaire models given with --gltf, or two built in code.
std::vector<TracedCase> traced_cases(const std::vector<std::string>& models) {
  std::vector<TracedCase> out;
  for (const std::string& path : models) {
    std::vector<gonio::Finding> findings;
    Result<sim::SceneDesc> scene = gonio::io::load_gltf(path, &findings);
    if (!scene.ok()) {
      std::fprintf(stderr, "gonio_filter_study: %s\n", gonio::to_string(scene.error()).c_str());
      std::exit(1);
    }
    const std::size_t slash = path.find_last_of('/');
    out.push_back({path.substr(slash == std::string::npos ? 0 : slash + 1), std::move(scene.value())});
  }
  if (!models.empty()) return out;
  out.push_back({"bell (opal)", bench::bell_scene(128, 48)});
  // A spot: a Lambertian sphere of 1 cm radius at the focus of a mirror
  // paraboloid (f = 5 cm, aperture 10 cm, hole 2 cm, ρ = 0.9) opening down.
  sim::SceneDesc spot;
  spot.name = "reflector spot";
  sim::Material black, mirror;
  black.name = "black";
  mirror.name = "mirror";
  mirror.mirror = 0.9;
  spot.materials = {black, mirror};
  sim::Mesh source = sim::sphere(0.01, 64, 32);
  source.material = 0;
  sim::Mesh reflector = sim::paraboloid(0.05, 0.1, 0.02, 96, 192);
  reflector.material = 1;
  spot.meshes = {source, reflector};
  sim::Emitter e;
  e.kind = sim::Emitter::Kind::Area;
  e.mesh = 0;
  e.flux_lm = 1000.0;
  spot.emitters = {e};
  out.push_back({"reflector spot", spot});
  return out;
}

// Runs `scene` until its far field holds `photons` photons (emitted) and
// returns it; iterations of `per_iteration` photons.
class TracedRun {
 public:
  TracedRun(const sim::SceneDesc& scene, int face_size, std::uint64_t per_iteration, std::uint64_t seed) {
    sim::SimulationSettings settings;
    settings.photons_per_iteration = per_iteration;
    settings.iterations = 1;
    settings.seed = seed;
    settings.face_size = face_size;
    Result<sim::Simulation> sim = sim::Simulation::create(scene, settings);
    if (!sim.ok()) {
      std::fprintf(stderr, "gonio_filter_study: %s\n", gonio::to_string(sim.error()).c_str());
      std::exit(1);
    }
    sim_ = std::make_unique<sim::Simulation>(std::move(sim.value()));
  }
  sim::FarField until(std::uint64_t photons) {
    while (sim_->stats().photons < photons) sim_->run_iteration();
    return sim_->far_field();
  }

 private:
  std::unique_ptr<sim::Simulation> sim_;
};

}  // namespace

int main(int argc, char** argv) {
  int n = 128;
  unsigned seed = 1;
  std::vector<std::string> detail;
  int sweep = 0;  // focused, broad, confirm
  bool traced = false;
  std::vector<std::string> models;
  double reference_density = 1000.0;  // photons per texel of a traced reference
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--face-size") && i + 1 < argc) {
      n = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--seed") && i + 1 < argc) {
      seed = static_cast<unsigned>(std::atoi(argv[++i]));
    } else if (!std::strcmp(argv[i], "--broad")) {
      sweep = 1;
    } else if (!std::strcmp(argv[i], "--confirm")) {
      sweep = 2;
    } else if (!std::strcmp(argv[i], "--traced")) {
      traced = true;
    } else if (!std::strcmp(argv[i], "--gltf") && i + 1 < argc) {
      traced = true;
      models.push_back(argv[++i]);
    } else if (!std::strcmp(argv[i], "--reference") && i + 1 < argc) {
      reference_density = std::atof(argv[++i]);
    } else if (!std::strcmp(argv[i], "--detail") && i + 1 < argc) {
      detail.push_back(argv[++i]);
    } else {
      std::fprintf(stderr, "usage: gonio_filter_study [--face-size N] [--seed S] [--broad | --confirm] [--traced] [--gltf MODEL]... "
                   "[--reference PHOTONS_PER_TEXEL] [--detail NAME]...\n");
      return 2;
    }
  }
  const CubeMapGrid grid(n);
  std::vector<Config> configs = sweep == 1 ? broad() : (sweep == 2 ? confirm() : focused());
  for (Config& c : configs) {
    if (c.level_delta != 0) {
      c.params.levels = PreviewFilter::auto_levels(n) + c.level_delta;
      c.name = describe(c.params, c.density_kappa);
    }
  }
  // Photons per texel; the traced references (1000) limit those to 40.
  const std::vector<double> densities = traced ? (reference_density >= 1000.0 ? std::vector<double>{0.25, 1.0, 2.5, 10.0, 40.0}
                                                                              : std::vector<double>{0.25, 1.0, 2.5, 10.0})
                                               : std::vector<double>{0.25, 1.0, 2.5, 10.0, 40.0, 160.0, 640.0};
  // log(error / raw error) per config, field, density.
  std::vector<std::vector<double>> log_ratio(configs.size());
  std::vector<std::vector<double>> flux_ratio(configs.size());
  std::printf("face size %d, %zu texels, %zu configurations, seed %u\n", n, grid.texel_count(), configs.size(),
              seed);
  double filter_seconds = 0.0;
  std::size_t filter_calls = 0;
  // Each case: a name, the truth, and the histogram at a photon density.
  struct Case {
    std::string name;
    std::function<Truth()> truth;
    std::function<FarField(std::uint64_t photons)> histogram;
  };
  std::vector<Case> cases;
  if (!traced) {
    for (const Field& field : fields()) {
      auto expected = std::make_shared<std::vector<double>>(expected_texel_flux(grid, field.intensity, 4));
      auto sampler = std::make_shared<FarFieldSampler>(*expected);
      auto histogram = std::make_shared<FarField>(n);
      auto rng = std::make_shared<std::mt19937_64>(seed);
      cases.push_back({field.name,
                       [=] {
                         Truth truth;
                         truth.intensity.resize(expected->size());
                         truth.omega.resize(expected->size());
                         for (std::size_t t = 0; t < expected->size(); ++t) {
                           truth.omega[t] = grid.texel_solid_angle(t);
                           truth.intensity[t] = (*expected)[t] / truth.omega[t];
                           truth.flux += (*expected)[t];
                         }
                         return truth;
                       },
                       [=](std::uint64_t photons) {
                         sampler->add_photons(*histogram, photons - histogram->total_photons(), 1.0, *rng);
                         return *histogram;
                       }});
    }
  } else {
    // Iterations of a quarter photon per texel (a multiple of the tracer's
    // 4096-photon chunks for faces of 128 and 256); the reference is a run
    // with another seed and `reference_density` photons per texel.
    const std::uint64_t quarter = grid.texel_count() / 4;
    for (const TracedCase& c : traced_cases(models)) {
      auto run = std::make_shared<TracedRun>(c.scene, n, quarter, seed);
      const sim::SceneDesc scene = c.scene;
      cases.push_back({c.name,
                       [=] {
                         const auto start = std::chrono::steady_clock::now();
                         TracedRun reference(scene, n, 64 * quarter, seed + 1000);
                         const FarField r = reference.until(static_cast<std::uint64_t>(
                             reference_density * static_cast<double>(grid.texel_count())));
                         Truth truth;
                         truth.intensity.resize(r.texel_count());
                         truth.omega.resize(r.texel_count());
                         for (std::size_t t = 0; t < r.texel_count(); ++t) {
                           truth.omega[t] = grid.texel_solid_angle(t);
                           truth.intensity[t] = r.intensity_cd(t);
                           truth.flux += r.flux_lm(t);
                           // Photons of equal flux: var(I) = I² / n.
                           if (r.photons(t) > 0)
                             truth.noise += truth.omega[t] * truth.intensity[t] * truth.intensity[t] /
                                            static_cast<double>(r.photons(t));
                         }
                         std::fprintf(stderr, "  reference %s: %.0f s\n", scene.name.c_str(),
                                      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
                         return truth;
                       },
                       [=](std::uint64_t photons) { return run->until(photons); }});
    }
  }
  for (const Case& one : cases) {
    Truth truth = one.truth();
    for (std::size_t t = 0; t < truth.intensity.size(); ++t)
      truth.norm += truth.omega[t] * truth.intensity[t] * truth.intensity[t];
    PreviewFilter filter(n, configs[1].params);
    std::printf("\n%-14s", one.name.c_str());
    for (double density : densities) {
      const auto target = static_cast<std::uint64_t>(density * static_cast<double>(grid.texel_count()));
      const FarField histogram = one.histogram(target);
      // Intensities to the truth's scale: the synthetic histograms carry
      // photons of 1 lm, the traced ones the emitted flux already.
      double histogram_flux = 0.0;
      for (double f : histogram.flux_lm()) histogram_flux += f;
      const double scale = truth.flux / histogram_flux;
      double raw_error = 0.0;
      for (std::size_t c = 0; c < configs.size(); ++c) {
        double error;
        if (configs[c].raw) {
          std::vector<double> raw(histogram.texel_count());
          for (std::size_t t = 0; t < raw.size(); ++t) raw[t] = histogram.intensity_cd(t);
          error = raw_error = rel_rms(truth, raw, scale);
          flux_ratio[c].push_back(1.0);
        } else {
          PreviewFilterParams p = configs[c].params;
          if (configs[c].density_kappa > 0.0) p.threshold_photons = configs[c].density_kappa * density;
          filter.set_params(p);
          const auto start = std::chrono::steady_clock::now();
          const PreviewStats& s = filter.apply(histogram);
          filter_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
          ++filter_calls;
          error = rel_rms(truth, filter.intensity_cd(), scale);
          flux_ratio[c].push_back(s.preview_flux_lm / s.raw_flux_lm);
        }
        log_ratio[c].push_back(std::log(error / raw_error));
      }
      std::printf("  n̄=%-5g raw %.4f", density, raw_error);
    }
    std::fflush(stdout);
  }
  std::vector<std::string> field_names;
  for (const Case& c : cases) field_names.push_back(c.name);
  for (const std::string& name : detail) {
    for (std::size_t c = 0; c < configs.size(); ++c) {
      if (configs[c].name != name) continue;
      std::printf("\n\n%s: error / raw error (preview/raw flux) per field and photons per texel", name.c_str());
      for (std::size_t i = 0; i < log_ratio[c].size(); ++i) {
        if (i % densities.size() == 0) std::printf("\n  %-14s", field_names[i / densities.size()].c_str());
        std::printf(" %5.2f (%.3f)", std::exp(log_ratio[c][i]), flux_ratio[c][i]);
      }
    }
  }
  std::printf("\n\nmean filter time %.2f ms per apply (face size %d)\n", 1e3 * filter_seconds / filter_calls, n);

  // Scores: geometric mean of error / raw error, overall, early (n̄ ≤ 2.5)
  // and late (n̄ ≥ 40), and the worst case; flux ratio range.
  struct Row {
    std::size_t c;
    double all, early, late, worst, flux_lo, flux_hi;
  };
  std::vector<Row> rows;
  const std::size_t per_field = densities.size();
  for (std::size_t c = 0; c < configs.size(); ++c) {
    Row r{c, 0, 0, 0, -1e9, 1e9, -1e9};
    int ne = 0, nl = 0;
    for (std::size_t i = 0; i < log_ratio[c].size(); ++i) {
      const double v = log_ratio[c][i], d = densities[i % per_field];
      r.all += v;
      if (d <= 2.5) r.early += v, ++ne;
      if (d >= std::min(40.0, densities.back())) r.late += v, ++nl;
      r.worst = std::max(r.worst, v);
      r.flux_lo = std::min(r.flux_lo, flux_ratio[c][i]);
      r.flux_hi = std::max(r.flux_hi, flux_ratio[c][i]);
    }
    r.all = std::exp(r.all / static_cast<double>(log_ratio[c].size()));
    r.early = std::exp(r.early / ne);
    r.late = std::exp(r.late / nl);
    r.worst = std::exp(r.worst);
    rows.push_back(r);
  }
  std::sort(rows.begin(), rows.end(), [](const Row& a, const Row& b) { return a.all < b.all; });
  std::printf("\nerror / raw error, geometric means: all; early (≤ 2.5 photons per texel); late (≥ %g)\n",
              std::min(40.0, densities.back()));
  std::printf("%-52s %7s %7s %7s %7s  %s\n", "configuration", "all", "early", "late", "worst", "preview/raw flux");
  for (const Row& r : rows)
    std::printf("%-52s %7.3f %7.3f %7.3f %7.3f  %.3f…%.3f\n", configs[r.c].name.c_str(), r.all, r.early, r.late,
                r.worst, r.flux_lo, r.flux_hi);
  return 0;
}
