// The stability suite (ctest label `stability`): scenes built for the cases
// where methods fail (shared/design/VALIDATION.md, "Where methods fail"),
// each run as a progressive simulation against a reference run of its own
// seed, and held to bounded behaviour:
//   - nothing is NaN or infinite: far field, every preview, the resampled
//     tables of both, the report;
//   - the energy ledger closes (photons exactly, flux to rounding);
//   - each preview filter's cube-map error (RMSE after mean scaling,
//     sim/convergence.h) stays within a stated factor of the raw map's at the
//     same photons, at every iteration (Case's factors, with what was
//     measured); the one setting that never converges by design, a fixed
//     threshold no texel reaches (everything upsampled from the coarsest
//     level), is held to never growing its error instead;
//   - the raw error, of the cube map and of the candela table, falls with
//     slope −0.5 ± 0.1 against photons (least squares over 7 iterations
//     doubling from 2¹⁴ to 2²⁰ photons, fewer for the slow scenes; the
//     reference has 8 times the last iteration's photons, its noise
//     variance taken out).
// The photon counts were chosen so that the slope is reliable: over 20
// seeds per case (GONIO_STABILITY_SEED=101…120; GONIO_STABILITY_VERBOSE=1
// prints slopes and ratios) every slope lay in [−0.54, −0.46].
//
// GONIO_STABILITY_SAMPLER=sobol (ctest's stability_sobol) runs the series
// with Owen-scrambled Sobol' points (sim/samplers/sampler.h); the references stay
// pseudo-random (their noise is taken out as Poisson noise). The raw error
// must then fall at least as fast as Monte Carlo's (slope ≤ −0.4). The
// preview filters' statistics assume Poisson noise, which Sobol' points
// beat, so their previews can lose to the better raw map (seed 11: the
// adaptive default up to 10 × it on the narrow spot, 3.1 × on the cut-off,
// 2.3 × on the glass cube); they are held to their factors against the
// pseudo-random raw map at the same photons instead (a run traced beside
// the series): a Sobol' preview is never worse than the filter promises a
// pseudo-random one. Every other bound holds as stated.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/model/model_check.h"
#include "io/outputs/report.h"
#include "photometry/distribution.h"
#include "sim/convergence.h"
#include "sim/filter/preview_filter.h"
#include "sim/detectors/resample.h"
#include "sim/shapes.h"
#include "sim/simulation.h"

namespace gonio::sim {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

constexpr int kDoublings = 6;

// The series' sampler (references: always random).
SamplerKind series_sampler() {
  const char* s = std::getenv("GONIO_STABILITY_SAMPLER");
  return s ? parse_sampler(s).value_or(SamplerKind::Random) : SamplerKind::Random;
}

// The series seed; the reference's is another.
std::uint64_t series_seed() {
  const char* s = std::getenv("GONIO_STABILITY_SEED");
  return s ? std::strtoull(s, nullptr, 10) : 11;
}

Material named(const char* name) {
  Material m;
  m.name = name;
  return m;
}

// A filter setting and the factor its preview's error may reach over the
// raw map's at the same photons.
struct FilterCase {
  std::string name;
  PreviewFilterParams params;
  double factor;  // NaN: no factor (see `bounded_by_flat_map`)
};

PreviewFilterParams fixed(Interpolation i, double threshold) {
  PreviewFilterParams p;
  p.interpolation = i;
  p.adaptive = false;
  p.threshold_photons = threshold;
  return p;
}

PreviewFilterParams adaptive_with(double threshold) {
  PreviewFilterParams p;
  p.threshold_photons = threshold;
  return p;
}

struct Case {
  std::string name;
  SceneDesc scene;
  int face_size = 64;
  CGammaGrid grid{10.0, 5.0};
  int max_bounces = 100;
  // Factors of the preview's error over the raw map's at the same photons.
  // The defaults hold for smooth far fields (globe, TIR cube, degenerate
  // shade: measured at most 0.26, 0.40 and 1.00 over 20 seeds), where the
  // filters help; the spot and the cut-off state their own.
  double adaptive_factor = 0.5;  // adaptive default, and adaptive with an unreachable threshold
  double fixed_factor = 0.6;     // the thesis's bilinear and bilateral at threshold 100
  double zero_factor = 1.02;     // threshold 0: only texels without photons are upsampled
  bool sealed = false;  // nothing escapes
  // Photons of the first iteration (the last has 2⁶ times as many) and of
  // the reference; slow scenes use fewer.
  std::uint64_t first = std::uint64_t{1} << 14;
  std::uint64_t reference = std::uint64_t{1} << 23;
};

struct CaseRun {
  std::vector<double> photons;
  std::vector<double> raw_rmse;
  std::vector<double> raw_table_rms;
  Ledger ledger;
  SimulationStats stats;
};

bool all_finite(std::span<const double> v) {
  for (double x : v)
    if (!std::isfinite(x)) return false;
  return true;
}

// Every number in a JSON document is finite (nlohmann writes NaN as null:
// a null anywhere counts as a failure too).
bool json_finite(const nlohmann::json& j) {
  if (j.is_null()) return false;
  if (j.is_number_float()) return std::isfinite(j.get<double>());
  if (j.is_structured())
    for (const auto& e : j)
      if (!json_finite(e)) return false;
  return true;
}

void expect_table_finite(const Resampler& resampler, const FarField& field, const std::string& what) {
  const BinnedField binned = resampler.bin(field);
  EXPECT_TRUE(all_finite(binned.flux_lm)) << what;
  EXPECT_TRUE(all_finite(binned.variance_lm2)) << what;
  const photometry::Distribution d = to_distribution(binned, photometry::Symmetry::None);
  EXPECT_TRUE(photometry::validate(d).ok()) << what;
  EXPECT_TRUE(all_finite(d.candela)) << what;
}

FarField preview_as_field(const PreviewFilter& f, int face_size) {
  FarField out(face_size);
  for (std::size_t t = 0; t < out.texel_count(); ++t)
    out.add(t, f.intensity_cd()[t] * out.grid().texel_solid_angle(t), 0);
  return out;
}

Simulation make_simulation(const Case& c, std::uint64_t seed, SamplerKind sampler = series_sampler()) {
  SimulationSettings s;
  s.photons_per_iteration = 1;
  s.iterations = 1;
  s.seed = seed;
  s.sampler = sampler;
  s.threads = 2;
  s.face_size = c.face_size;
  s.max_bounces = c.max_bounces;
  auto sim = Simulation::create(c.scene, s);
  EXPECT_TRUE(sim.ok()) << c.name << ": " << (sim.ok() ? "" : sim.error().message);
  return std::move(sim.value());
}

void expect_ledger_closes(const Ledger& l, const std::string& what) {
  EXPECT_TRUE(l.photons_close()) << what;
  EXPECT_LE(std::abs(l.flux_imbalance_lm()), 1e-9 * l.emitted.flux_lm) << what;
  io::SimulationReport report;
  report.program_version = "test";
  report.model = what;
  report.ledger = l;
  EXPECT_TRUE(json_finite(io::to_json(report))) << what << ": report";
}

// Runs a case: reference, then the series with every filter; checks
// everything but the slope, which the caller checks (it needs the run).
CaseRun run_case(const Case& c) {
  const auto resampler = std::make_shared<const Resampler>(c.face_size, c.scene.frame, c.grid);
  const std::uint64_t seed = series_seed();
  std::optional<ConvergenceReference> judge;
  if (!c.sealed) {
    Simulation reference = make_simulation(c, seed + 1'000'003, SamplerKind::Random);
    reference.run_iteration(c.reference);
    auto j = ConvergenceReference::create(reference.far_field(), resampler);
    EXPECT_TRUE(j.ok()) << c.name;
    if (j.ok()) judge.emplace(std::move(j.value()));
  }
  const std::vector<FilterCase> filters = {
      {"adaptive default", PreviewFilterParams{}, c.adaptive_factor},
      {"adaptive, threshold never reached", adaptive_with(1e30), c.adaptive_factor},
      {"bilateral 100", fixed(Interpolation::Bilateral, 100.0), c.fixed_factor},
      {"bilinear 100", fixed(Interpolation::Bilinear, 100.0), c.fixed_factor},
      {"threshold 0", fixed(Interpolation::Bilateral, 0.0), c.zero_factor},
      {"threshold never reached", fixed(Interpolation::Bilateral, 1e30), std::nan("")},
  };
  PreviewFilter filter(c.face_size, filters.front().params);

  Simulation sim = make_simulation(c, seed);
  std::optional<Simulation> random_sim;  // Sobol' series: the filters' yardstick
  if (judge && series_sampler() != SamplerKind::Random) random_sim.emplace(make_simulation(c, seed, SamplerKind::Random));
  CaseRun run;
  std::vector<double> first_error(filters.size(), 0.0);
  for (int k = 0; k <= kDoublings; ++k) {
    sim.run_iteration(k == 0 ? c.first : c.first << (k - 1));
    if (random_sim) random_sim->run_iteration(k == 0 ? c.first : c.first << (k - 1));
    const FarField field = sim.far_field();
    const std::string at = c.name + ", iteration " + std::to_string(k + 1);
    EXPECT_TRUE(all_finite(field.flux_lm())) << at;
    const std::vector<double> raw = texel_intensities(field);
    EXPECT_TRUE(all_finite(raw)) << at;
    expect_table_finite(*resampler, field, at + ", raw table");
    expect_ledger_closes(sim.ledger(), at);
    run.photons.push_back(static_cast<double>(sim.stats().photons));

    std::optional<CubeMapError> raw_error;
    double yardstick = 0.0;  // the raw error the filters' factors apply to
    if (judge) {
      raw_error = judge->cube_map_error(raw);
      yardstick = raw_error->rmse;
      if (random_sim)
        yardstick = std::max(yardstick, judge->cube_map_error(texel_intensities(random_sim->far_field())).rmse);
      run.raw_rmse.push_back(raw_error->rmse);
      run.raw_table_rms.push_back(judge->table_error(raw).rms_pct);
      EXPECT_TRUE(std::isfinite(raw_error->rmse)) << at;
    }
    for (std::size_t fi = 0; fi < filters.size(); ++fi) {
      const FilterCase& f = filters[fi];
      filter.set_params(f.params);
      const PreviewStats& ps = filter.apply(field);
      const std::string what = at + ", " + f.name;
      EXPECT_TRUE(all_finite(filter.intensity_cd())) << what;
      EXPECT_TRUE(std::isfinite(ps.preview_flux_lm)) << what;
      for (double v : filter.intensity_cd()) {
        if (!(v >= 0.0)) {
          ADD_FAILURE() << what << ": negative intensity " << v;
          break;
        }
      }
      expect_table_finite(*resampler, preview_as_field(filter, c.face_size), what + ", preview table");
      if (c.sealed) {
        EXPECT_EQ(ps.preview_flux_lm, 0.0) << what;
        continue;
      }
      if (!judge) continue;
      const CubeMapError e = judge->cube_map_error(filter.intensity_cd());
      EXPECT_TRUE(std::isfinite(e.rmse)) << what;
      if (k == 0) first_error[fi] = e.rmse;
      if (std::isnan(f.factor)) {
        // Every texel upsampled from the coarsest level, whatever the
        // photons: it never converges to the raw map (that is the setting's
        // failure), but its error must not grow either.
        EXPECT_LE(e.rmse, 1.02 * first_error[fi]) << what;
      } else {
        EXPECT_LE(e.rmse, f.factor * yardstick) << what << " (raw " << raw_error->rmse << ", against "
                                                 << yardstick << ")";
      }
      if (std::getenv("GONIO_STABILITY_VERBOSE"))
        std::printf("R|%s|%s|%d|%.4f|%.4g\n", c.name.c_str(), f.name.c_str(), k + 1, e.rmse / raw_error->rmse,
                    e.rmse);
    }
  }
  run.ledger = sim.ledger();
  run.stats = sim.stats();
  return run;
}

void expect_slope(const CaseRun& run, const std::string& name) {
  const double slope = log_log_slope(run.photons, run.raw_rmse);
  const double table_slope = log_log_slope(run.photons, run.raw_table_rms);
  if (std::getenv("GONIO_STABILITY_VERBOSE"))
    std::printf("S|%s|%.4f|%.4f\n", name.c_str(), slope, table_slope);
  if (series_sampler() == SamplerKind::Random) {
    EXPECT_NEAR(slope, -0.5, 0.1) << name;
    EXPECT_NEAR(table_slope, -0.5, 0.1) << name;
  } else {
    EXPECT_LE(slope, -0.4) << name;
    EXPECT_LE(table_slope, -0.4) << name;
  }
}

// A point emitter with a rotationally symmetric Type C profile
// I(γ) = cosⁿ γ (γ < 30°, 0 beyond) pointing at the nadir: n = 182 puts half
// the peak at γ = 5°, a 10° beam.
SceneDesc narrow_spot() {
  auto d = std::make_shared<photometry::Distribution>();
  d->type = photometry::PhotometricType::C;
  d->symmetry = photometry::Symmetry::Rotational;
  d->absolute = true;
  d->horizontal_deg = {0.0};
  for (double g = 0.0; g <= 180.0 + 1e-9; g += 0.25) {
    d->vertical_deg.push_back(g);
    d->candela.push_back(g < 30.0 ? 1000.0 * std::pow(std::cos(g * kDeg), 182.0) : 0.0);
  }
  SceneDesc s;
  s.name = "narrow spot";
  s.materials = {named("none")};
  Emitter e;
  e.name = "spot";
  e.flux_lm = 1000.0;
  e.profile = d;
  s.emitters = {e};
  return s;
}

TEST(Stability, NarrowSpotBeam) {
  Case c{"narrow spot (10° beam)", narrow_spot()};
  // A 10° beam covers ~100 texels of a face of 128 and a handful on the
  // coarse levels: every filter blurs its flanks, and filtering does not
  // help here. Over 20 seeds the preview's error reached 2.30 × the raw
  // map's (adaptive: its test keeps the beam's core but smooths the flanks,
  // where the counts are high and the raw map is already good), 1.80 ×
  // (bilinear 100), 1.39 × (bilateral 100) and 1.003 × (threshold 0).
  c.face_size = 128;
  c.grid = {5.0, 2.5};
  c.adaptive_factor = 2.75;
  c.fixed_factor = 2.3;
  c.zero_factor = 1.05;
  const CaseRun run = run_case(c);
  expect_slope(run, c.name);
}

// An isotropic lamp at the top of a black tube open at the bottom: light
// leaves in a cone with a sharp cut-off at γ = atan(r / h) = 30°, beyond it
// nothing.
TEST(Stability, SharpCutOff) {
  SceneDesc s;
  s.name = "cut-off";
  s.materials = {named("black")};
  const double r = 0.05, h = r / std::tan(30.0 * kDeg);
  const ProfilePoint tube[] = {{r, -h}, {r, 0.0}};
  LatheOptions o;
  o.segments = 128;
  o.shading_normals = false;
  Mesh wall = lathe(tube, o);
  wall.name = "tube";
  Mesh cap = disc(r, 128);
  cap.name = "cap";
  s.meshes = {wall, cap};
  Emitter e;
  e.name = "lamp";
  e.flux_lm = 1000.0;
  e.position = {0.0, -1e-4, 0.0};
  s.emitters = {e};
  Case c{"sharp cut-off", s};
  // Measured over 20 seeds: adaptive 0.71 × the raw error, the fixed
  // thresholds 1.56 × (light upsampled across the cut-off into the dark),
  // threshold 0 1.32 × (the empty texels beyond the cut-off get light).
  c.adaptive_factor = 1.0;
  c.fixed_factor = 2.0;
  c.zero_factor = 1.6;
  const CaseRun run = run_case(c);
  // A third of a per cent of the cone's cap is the tube's mouth polygon.
  EXPECT_NEAR(run.ledger.escaped.flux_lm / 1000.0, (1.0 - std::cos(30.0 * kDeg)) / 2.0, 0.002);
  expect_slope(run, c.name);
}

// The first iteration with a handful of photons: 64 photons on 24 576
// texels. Nothing may be NaN, and the filter must help, not hurt. Then six
// doubling iterations to 4096 photons, still sparse (one photon in six
// texels): the raw error falls with slope −0.5 from the first photon on
// (over 20 seeds: cube map −0.507 to −0.493, table −0.519 to −0.477).
TEST(Stability, SparseFirstIteration) {
  SceneDesc s;
  s.name = "sparse";
  Material white = named("white");
  white.diffuse_reflect = 0.8;
  s.materials = {white};
  Mesh plate = disc(0.1, 32);
  transform(plate, translation({0.0, 0.05, 0.0}));
  flip(plate);  // faces down, towards the lamp
  s.meshes = {plate};
  Emitter e;
  e.flux_lm = 100.0;
  s.emitters = {e};
  SimulationSettings set;
  set.photons_per_iteration = 64;
  set.iterations = 1;
  set.face_size = 64;
  set.threads = 2;
  set.seed = series_seed();
  set.sampler = series_sampler();
  auto sim = Simulation::create(s, set);
  ASSERT_TRUE(sim.ok());
  sim->run_iteration();
  const FarField field = sim->far_field();
  EXPECT_LE(field.total_photons(), 64u);
  expect_ledger_closes(sim->ledger(), "sparse");
  // A long run of the same scene as the truth.
  SimulationSettings ref_set = set;
  ref_set.seed = set.seed + 1'000'003;
  ref_set.sampler = SamplerKind::Random;
  auto ref = Simulation::create(s, ref_set);
  ASSERT_TRUE(ref.ok());
  ref->run_iteration(std::uint64_t{1} << 21);
  const auto resampler = std::make_shared<const Resampler>(64, s.frame, CGammaGrid{10.0, 5.0});
  auto judge = ConvergenceReference::create(ref->far_field(), resampler);
  ASSERT_TRUE(judge.ok());
  const double raw = judge->cube_map_error(texel_intensities(field)).rmse;
  for (const PreviewFilterParams& p :
       {PreviewFilterParams{}, fixed(Interpolation::Bilinear, 100.0), fixed(Interpolation::Bilateral, 50.0),
        fixed(Interpolation::Bilateral, 0.0), fixed(Interpolation::Bilateral, 1e30)}) {
    PreviewFilter filter(64, p);
    const PreviewStats& ps = filter.apply(field);
    EXPECT_TRUE(all_finite(filter.intensity_cd()));
    EXPECT_TRUE(std::isfinite(ps.preview_flux_lm));
    expect_table_finite(*resampler, preview_as_field(filter, 64), "sparse preview");
    const double err = judge->cube_map_error(filter.intensity_cd()).rmse;
    EXPECT_TRUE(std::isfinite(err));
    // With threshold 0 the 64 photons stand as they are; every other
    // setting smooths them: several times closer to the truth than raw.
    EXPECT_LE(err, (p.threshold_photons == 0.0 ? 1.0 + 1e-9 : 0.5) * raw) << p.threshold_photons;
  }
  CaseRun run;
  for (int k = 0; k <= kDoublings; ++k) {
    if (k > 0) sim->run_iteration(std::uint64_t{64} << (k - 1));
    const std::vector<double> intensities = texel_intensities(sim->far_field());
    run.photons.push_back(static_cast<double>(sim->stats().photons));
    run.raw_rmse.push_back(judge->cube_map_error(intensities).rmse);
    run.raw_table_rms.push_back(judge->table_error(intensities).rms_pct);
    expect_ledger_closes(sim->ledger(), "sparse, iteration " + std::to_string(k + 1));
  }
  EXPECT_EQ(run.photons.back(), 4096.0);
  expect_slope(run, "sparse first iterations");
}

// Threshold extremes on a smooth scene (an opal globe): threshold 0 keeps
// every texel that has a photon; an unreachable threshold with adaptive
// stability off upsamples everything from the coarsest level. run_case
// covers both in every case; this one holds the unreachable threshold with
// adaptive stability on to the adaptive factor on a smooth distribution,
// where that test is what decides.
TEST(Stability, ThresholdExtremesOnASmoothGlobe) {
  SceneDesc s;
  s.name = "globe";
  Material opal{"opal", 0.35, 0.55, 0.0};
  s.materials = {opal};
  Mesh globe = sphere(0.1, 48, 24);
  globe.name = "globe";
  s.meshes = {globe};
  Emitter e;
  e.name = "lamp";
  e.flux_lm = 1000.0;
  e.position = {0.02, 0.01, 0.0};
  s.emitters = {e};
  Case c{"opal globe", s};
  c.first = std::uint64_t{1} << 13;
  c.reference = std::uint64_t{1} << 22;
  const CaseRun run = run_case(c);
  expect_slope(run, c.name);
}

// A point lamp at the centre of a glass cube (n = 1.5, no absorption): a
// ray whose direction cosines all stay below c = √(1 − 1/n²) meets every
// face beyond the critical angle, and the cube keeps them: it is trapped by
// total internal reflection until the bounce limit. The trapped fraction of
// an isotropic source is 1 − 3(1 − c) = 3c − 2 (the three caps |dᵢ| > c do
// not overlap since 2c² > 1): 0.2361. The rest leaves after Fresnel
// reflections; near the critical angle a few need more than the limit.
// A 1000 lm point lamp at `lamp` inside one mesh of one material, the mesh
// wound outward or (inverted) inside out.
SceneDesc lamp_inside(const std::string& name, const Material& material, Mesh mesh, bool inverted,
                      const Vec3& lamp = {}) {
  SceneDesc s;
  s.name = name;
  s.materials = {material};
  if (inverted) flip(mesh);
  s.meshes = {std::move(mesh)};
  Emitter e;
  e.name = "lamp";
  e.flux_lm = 1000.0;
  e.position = lamp;
  s.emitters = {e};
  return s;
}

// The lamp at the centre of a 5 cm cube of clear glass (n = 1.5).
SceneDesc glass_cube(const std::string& name, bool inverted) {
  Material glass = named("glass");
  glass.dielectric = 1.0;
  glass.ior = 1.5;
  Mesh cube = box(0.05, 0.05, 0.05);
  cube.name = "cube";
  return lamp_inside(name, glass, std::move(cube), inverted);
}

TEST(Stability, TotalInternalReflectionTrap) {
  const SceneDesc s = glass_cube("TIR cube", false);
  Case c{"TIR trap", s};
  c.max_bounces = 16;
  c.first = std::uint64_t{1} << 12;
  c.reference = std::uint64_t{1} << 21;
  const CaseRun run = run_case(c);
  const double trapped = 3.0 * std::sqrt(1.0 - 1.0 / 2.25) - 2.0;
  const double cut = run.ledger.cutoff.flux_lm / run.ledger.emitted.flux_lm;
  EXPECT_GE(cut, trapped - 0.003);
  EXPECT_LE(cut, trapped + 0.01);
  EXPECT_EQ(run.ledger.absorbed.photons, 0u);
  expect_slope(run, c.name);
}

// Degenerate geometry: an open white shade (an open mesh, lit from inside
// and outside) with zero-area triangles (three collinear corners, and a
// repeated corner) and every triangle duplicated on top of itself. The
// tracer must neither crash nor lose light: the ledger closes, and the
// far field converges like any other.
TEST(Stability, DegenerateGeometry) {
  SceneDesc s;
  s.name = "degenerate";
  Material white = named("white");
  white.diffuse_reflect = 0.7;
  white.diffuse_transmit = 0.1;
  s.materials = {white};
  const ProfilePoint bowl[] = {{0.0, 0.08}, {0.06, 0.06}, {0.1, 0.0}};
  Mesh shade = lathe(bowl, {});
  shade.name = "open shade";
  shade.normals.clear();
  shade.tangents.clear();
  const std::size_t n = shade.indices.size();
  for (std::size_t i = 0; i < n; ++i) shade.indices.push_back(shade.indices[i]);  // duplicated
  const auto v = static_cast<std::uint32_t>(shade.positions.size());
  shade.positions.push_back({0.0f, -0.05f, 0.0f});
  shade.positions.push_back({0.01f, -0.05f, 0.0f});
  shade.positions.push_back({0.02f, -0.05f, 0.0f});  // collinear
  shade.indices.insert(shade.indices.end(), {v, v + 1, v + 2, v, v, v + 1});
  s.meshes = {shade};
  Emitter e;
  e.name = "lamp";
  e.flux_lm = 1000.0;
  e.position = {0.0, 0.02, 0.0};
  s.emitters = {e};
  Case c{"degenerate geometry", s};
  c.first = std::uint64_t{1} << 13;
  c.reference = std::uint64_t{1} << 22;
  const CaseRun run = run_case(c);
  EXPECT_GT(run.ledger.escaped.flux_lm, 0.0);
  expect_slope(run, c.name);
}

// Inverted geometry: closed meshes wound inside out (every normal facing
// in). A diffuse surface scatters the same whichever way it faces, so an
// opal globe wound inside out gives the light of the right one: the model
// checks accept it (they check the orientation of refractive volumes only),
// and its escaped flux and the share of it going down (the lamp sits off
// centre) match the right globe's within photon noise.
SceneDesc opal_globe(bool inverted) {
  const Material opal{"opal", 0.35, 0.55, 0.0};
  Mesh globe = sphere(0.1, 24, 12);
  globe.name = "globe";
  return lamp_inside(inverted ? "inverted globe" : "globe", opal, std::move(globe), inverted, {0.02, 0.01, 0.0});
}

TEST(Stability, InvertedDiffuseGlobe) {
  const SceneDesc inverted = opal_globe(true);
  EXPECT_LT(worst(io::check_model(inverted)), Severity::Error);
  // Measured over 20 seeds: the filters' errors at most 0.19 × the raw map's.
  Case c{"inverted opal globe", inverted};
  c.first = std::uint64_t{1} << 12;
  c.reference = std::uint64_t{1} << 21;
  const CaseRun run = run_case(c);
  expect_slope(run, c.name);

  // Against the globe wound the right way, another seed, as many photons:
  // the fractions escaped and escaped downwards agree within 4σ of their
  // binomial noise.
  Case right{"opal globe", opal_globe(false)};
  Simulation sim = make_simulation(right, series_seed() + 7);
  sim.run_iteration(static_cast<std::uint64_t>(run.photons.back()));
  const auto fractions = [](const Ledger& l, const FarField& f) {
    double down = 0.0;
    for (std::size_t t = 0; t < f.texel_count(); ++t)
      if (f.grid().texel_direction(t).y < 0.0) down += static_cast<double>(f.photons(t));
    const double emitted = static_cast<double>(l.emitted.photons);
    return std::pair{static_cast<double>(l.escaped.photons) / emitted, down / emitted};
  };
  Simulation again = make_simulation(c, series_seed());
  again.run_iteration(static_cast<std::uint64_t>(run.photons.back()));
  const auto [escaped_inverted, down_inverted] = fractions(again.ledger(), again.far_field());
  const auto [escaped_right, down_right] = fractions(sim.ledger(), sim.far_field());
  const double n = run.photons.back();
  const auto sigma = [&](double p) { return std::sqrt(2.0 * p * (1.0 - p) / n); };
  EXPECT_GT(escaped_right, 0.5);
  EXPECT_NEAR(escaped_inverted, escaped_right, 4.0 * sigma(escaped_right));
  EXPECT_NEAR(down_inverted, down_right, 4.0 * sigma(down_right));
}

// A refractive volume inside out: the TIR cube with inward normals. The
// model checks refuse it (inverted-volume, an error: `simulate` and `bench`
// trace nothing); traced anyway, the tracer takes the lamp's side for the
// outside, so light leaves through six refracting windows instead of being
// trapped. Whatever it makes of it, nothing may be NaN, the books must close
// and the far field converge.
TEST(Stability, InvertedGlassCube) {
  const SceneDesc s = glass_cube("inverted glass cube", true);
  const std::vector<Finding> findings = io::check_model(s);
  ASSERT_EQ(findings.size(), 1u);
  EXPECT_EQ(findings[0].code, "inverted-volume");
  EXPECT_EQ(findings[0].severity, Severity::Error);
  EXPECT_NE(findings[0].message.find("cube"), std::string::npos) << findings[0].message;

  Case c{"inverted glass cube", s};
  // Each window's light has sharp edges, which the fixed thresholds blur as
  // on the cut-off. Measured over 20 seeds: adaptive 0.84 × the raw error,
  // bilinear and bilateral 100 1.30 ×, threshold 0 1.007 ×.
  c.adaptive_factor = 1.0;
  c.fixed_factor = 1.6;
  c.max_bounces = 16;
  c.first = std::uint64_t{1} << 12;
  c.reference = std::uint64_t{1} << 21;
  const CaseRun run = run_case(c);
  EXPECT_GT(run.ledger.escaped.flux_lm, 0.0);
  expect_slope(run, c.name);
}

// An emitter sealed in a closed box, black and white: nothing escapes. The
// far field, previews and tables are all zeros (finite), the books say all
// was absorbed (or cut off in the white box), and a bench reference of it is
// an error rather than a division by zero.
TEST(Stability, SealedEmitter) {
  for (const double reflectance : {0.0, 0.9}) {
    SceneDesc s;
    s.name = "sealed";
    Material wall = named("wall");
    wall.diffuse_reflect = reflectance;
    s.materials = {wall};
    Mesh b = box(0.1, 0.1, 0.1);
    flip(b);  // white side inwards
    b.name = "box";
    s.meshes = {b};
    Emitter e;
    e.name = "lamp";
    e.flux_lm = 500.0;
    s.emitters = {e};
    Case c{reflectance > 0.0 ? "sealed in white" : "sealed in black", s};
    c.sealed = true;
    c.max_bounces = 30;
    const CaseRun run = run_case(c);
    EXPECT_EQ(run.ledger.escaped.photons, 0u);
    EXPECT_EQ(run.ledger.escaped.flux_lm, 0.0);
    EXPECT_EQ(run.ledger.absorbed.photons + run.ledger.cutoff.photons, run.stats.photons);
    if (reflectance == 0.0) {
      EXPECT_EQ(run.ledger.cutoff.photons, 0u);
    }
    Simulation sim = make_simulation(c, 3);
    sim.run_iteration(1000);
    const auto resampler = std::make_shared<const Resampler>(64, s.frame, CGammaGrid{10.0, 5.0});
    EXPECT_FALSE(ConvergenceReference::create(sim.far_field(), resampler).ok());
  }
}

}  // namespace
}  // namespace gonio::sim
