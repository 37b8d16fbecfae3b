// The glossy lobe's cost per scattering event against the thesis's sampler
// measured in the same run: Walter's half vector with the thesis's weight
// F √(cos θo / cos θi) / cos θh (what sim/bsdfs/material.cpp did before the lobe
// became a microfacet BRDF with visible-normal sampling).
//
//   build/benchmarks/gonio_material_benchmarks
//
// Counters: ns_per_event of sample_glossy, thesis_ns_per_event of the
// baseline, ratio = ns_per_event / thesis_ns_per_event. Incidence 25°…47°
// (the downlight's reflector sees 26°…45°); `smooth` is the downlight's
// aluminium (mx = my = 0.09, where Λ vanishes and is skipped), `rough`
// mx = my = 0.5 (Λ with erfc for both directions).
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <numbers>

#include "sim/bsdfs/material.h"
#include "sim/samplers/sampling.h"

namespace gonio::bench {
namespace {

constexpr int kEvents = 1 << 20;

struct Incidences {
  Vec3 wi[16];
  Incidences() {
    for (int i = 0; i < 16; ++i) {
      const double t = (25.0 + 1.5 * i) * std::numbers::pi / 180.0, p = 0.4 * i;
      wi[i] = {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
    }
  }
};

double thesis_weight(const sim::Material& m, const Vec3& wi, sim::PhotonRandom& rng) {
  double c, s;
  sim::sample_unit_circle(rng, &c, &s);
  const Vec3 h = sim::sample_beckmann_half_vector(m.glossy_mx, m.glossy_my, rng.uniform_open0(), c, s);
  const double ih = dot(wi, h);
  if (ih <= 0.0) return 0.0;
  const Vec3 wo = 2.0 * ih * h - wi;
  if (wo.z <= 0.0) return 0.0;
  return sim::schlick_fresnel(m.glossy_f0, ih) * std::sqrt(wo.z / wi.z) / h.z;
}

template <class F>
double seconds_for(F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void run(benchmark::State& state, double roughness) {
  sim::Material m;
  m.glossy = 1.0;
  m.glossy_mx = m.glossy_my = roughness;
  const Incidences in;
  double sum = 0.0, t_new = 0.0, t_old = 0.0;
  std::uint64_t seed = 1;
  for (auto _ : state) {
    ++seed;
    t_new += seconds_for([&] {
      for (int k = 0; k < kEvents; ++k) {
        sim::PhotonRandom rng(seed, static_cast<std::uint64_t>(k));
        sum += sim::sample_glossy(m, in.wi[k & 15], rng).weight;
      }
    });
    t_old += seconds_for([&] {
      for (int k = 0; k < kEvents; ++k) {
        sim::PhotonRandom rng(seed, static_cast<std::uint64_t>(k));
        sum += thesis_weight(m, in.wi[k & 15], rng);
      }
    });
  }
  benchmark::DoNotOptimize(sum);
  const double events = static_cast<double>(state.iterations()) * kEvents;
  state.counters["ns_per_event"] = 1e9 * t_new / events;
  state.counters["thesis_ns_per_event"] = 1e9 * t_old / events;
  state.counters["ratio"] = t_new / t_old;
}

void BM_GlossySample_smooth(benchmark::State& state) { run(state, 0.09); }
void BM_GlossySample_rough(benchmark::State& state) { run(state, 0.5); }
BENCHMARK(BM_GlossySample_smooth)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_GlossySample_rough)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace gonio::bench

BENCHMARK_MAIN();
