// Cost of resampling the far field to a Type C grid: building the overlap
// matrix once, and applying it to a map (what a simulation does after every
// iteration), against the floor of reading every texel once.
#include <benchmark/benchmark.h>

#include <random>

#include "sim/detectors/resample.h"
#include "sim/detectors/symmetry.h"

namespace {

using namespace gonio;

sim::CGammaGrid grid_of(const benchmark::State& state) {
  return {static_cast<double>(state.range(0)) / 10.0, static_cast<double>(state.range(1)) / 10.0};
}

sim::FarField random_field(int face) {
  sim::FarField field(face);
  std::mt19937_64 rng(1);
  std::exponential_distribution<double> e(1.0);
  for (std::size_t t = 0; t < field.texel_count(); ++t) field.add(t, e(rng), 1 + rng() % 50);
  return field;
}

// Arguments: C-step and γ-step in tenths of a degree.
void BM_BuildResampler(benchmark::State& state) {
  const sim::CGammaGrid g = grid_of(state);
  const int face = sim::face_size_for(g);
  const auto frame = photometry::make_frame({0.3, 1.0, 0.2}, {1.0, 0.1, -0.4});
  for (auto _ : state) {
    sim::Resampler r(face, frame, g);
    benchmark::DoNotOptimize(r.nonzeros());
  }
  state.counters["face"] = face;
}
BENCHMARK(BM_BuildResampler)->Args({50, 25})->Args({100, 50})->Args({10, 10})->Unit(benchmark::kMillisecond);

// A narrow beam's list (issue 44): γ every 0.1° to 5°, then every 1°, C every
// 5°, at the face given (128: the default map; 1024: the face it selects);
// against it the uniform 0.1° γ step (argument 0) at its face 1024.
void BM_BuildResamplerNarrowBeamList(benchmark::State& state) {
  sim::CGammaGrid g{5.0, 0.1};
  if (state.range(0) > 0) {
    for (int k = 0; k <= 50; ++k) g.gamma_angles_deg.push_back(k / 10.0);
    for (int k = 6; k <= 180; ++k) g.gamma_angles_deg.push_back(k);
  }
  const int face = state.range(0) > 0 ? static_cast<int>(state.range(0)) : sim::face_size_for(g);
  const auto frame = photometry::make_frame({0.3, 1.0, 0.2}, {1.0, 0.1, -0.4});
  for (auto _ : state) {
    sim::Resampler r(face, frame, g);
    benchmark::DoNotOptimize(r.nonzeros());
    state.counters["nonzeros"] = static_cast<double>(r.nonzeros());
  }
  state.counters["face"] = face;
  state.counters["bins"] = static_cast<double>(g.bin_count());
}
BENCHMARK(BM_BuildResamplerNarrowBeamList)->Arg(128)->Arg(1024)->Arg(0)->Iterations(1)->Unit(benchmark::kMillisecond);

void BM_ResampleMap(benchmark::State& state) {
  const sim::CGammaGrid g = grid_of(state);
  const int face = sim::face_size_for(g);
  const sim::Resampler r(face, {}, g);
  const sim::FarField field = random_field(face);
  for (auto _ : state) {
    sim::BinnedField b = r.bin(field);
    benchmark::DoNotOptimize(b.flux_lm.data());
  }
  state.counters["nonzeros"] = static_cast<double>(r.nonzeros());
  state.counters["texels"] = static_cast<double>(field.texel_count());
}
BENCHMARK(BM_ResampleMap)->Args({50, 25})->Args({10, 10})->Unit(benchmark::kMicrosecond);

// Baseline: one pass over the map's flux and photon counts.
void BM_ReadMapOnce(benchmark::State& state) {
  const int face = sim::face_size_for(grid_of(state));
  const sim::FarField field = random_field(face);
  for (auto _ : state) {
    benchmark::DoNotOptimize(field.total_flux_lm());
    benchmark::DoNotOptimize(field.total_photons());
  }
}
BENCHMARK(BM_ReadMapOnce)->Args({50, 25})->Args({10, 10})->Unit(benchmark::kMicrosecond);

void BM_DetectSymmetry(benchmark::State& state) {
  const sim::CGammaGrid g = grid_of(state);
  const int face = sim::face_size_for(g);
  const sim::BinnedField b = sim::Resampler(face, {}, g).bin(random_field(face));
  for (auto _ : state) {
    sim::SymmetryDecision d = sim::detect_symmetry(b);
    benchmark::DoNotOptimize(d.symmetry);
  }
}
BENCHMARK(BM_DetectSymmetry)->Args({50, 25})->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
