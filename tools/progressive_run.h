// The progressive loop that `gonio simulate` and `gonio watch` share:
// iterations of photons traced into one far field, a callback after each,
// and three ways to stop — every planned iteration done, the estimated
// candela error under a target (--target-error), or the caller asking (a
// changed model in `gonio watch`).
//
// The error estimate is the one `gonio bench` validates against its reference
// (tools/bench_reference.h: "estimated" against "measured" from two halves):
// the run's own far field taken as a reference, its candela table's noise
// from photon counts, sim::ConvergenceReference::table_noise_pct():
//   estimated_rms_error_pct = 100 · √(Σ Ω_b v_b / Σ Ω_b) / max_b I_b
// over the bins b of the output grid (v_b the binned Poisson variance of the
// intensity). It assumes photons of equal power (plain emission, what
// simulate and watch trace); it falls as 1/√photons, so the photons still
// needed for a target T are photons · ((estimate / T)² − 1), which gives the
// time left. A run without escaped flux has no estimate (NaN): it never stops
// by target error.
//
// Under the Sobol' sampler (sim/sampler.h) the same count-based estimate is
// given. It assumes independent photons, and scrambled Sobol' points are
// better spread than that, so it over-states their error (README, Measured
// figures: 1.3–4× at 2²⁰ photons on the samples): --target-error stops where
// the pseudo-random sampler would, with a smaller error than the target.
// An estimate from independent scrambles is not made yet.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>

#include "photometry/diagnostics.h"
#include "sim/far_field.h"
#include "sim/resample.h"
#include "sim/scene.h"
#include "sim/simulation.h"

namespace gonio::cli {

// The estimate above for a far field of plain emission on the resampler's
// grid [%]; NaN where nothing escaped.
double estimated_rms_error_pct(const sim::FarField& field, const sim::Resampler& resampler);

struct ProgressiveSettings {
  sim::SimulationSettings simulation;  // photons per iteration, iterations (at most), seed, …
  // Stop once the estimate is at or under this [%]; 0: no target (run every iteration).
  double target_error_pct = 0.0;
  // Photons of the first iteration when fewer than photons_per_iteration
  // (0: the same): a small first iteration gives a first preview sooner.
  std::uint64_t first_iteration_photons = 0;
};

enum class StopReason { Iterations, TargetError, Cancelled };
const char* to_string(StopReason reason);  // "iterations", "target-error", "cancelled"

struct IterationReport {
  sim::SimulationProgress progress;
  double estimated_rms_error_pct = 0.0;  // after this iteration [%] (NaN: no flux yet)
};

struct ProgressiveOutcome {
  sim::Simulation simulation;
  StopReason stopped_by = StopReason::Iterations;
  int iterations_done = 0;  // planned iterations completed (slices not counted)
  double estimated_rms_error_pct = 0.0;  // at the end [%]
};

// After each iteration; returns false to stop the run (StopReason::Cancelled).
using IterationCallback = std::function<bool(const IterationReport&, const sim::Simulation&)>;
// Asked between slices of at most kCancelSlicePhotons photons inside an
// iteration; true stops the run at once (StopReason::Cancelled, the partial
// iteration not reported). Slicing changes no photon: the far field is the
// same bytes as unsliced (photon indices are run-wide).
using CancelCheck = std::function<bool()>;
inline constexpr std::uint64_t kCancelSlicePhotons = std::uint64_t{1} << 14;

// Creates the simulation (errors: those of sim::Simulation::create) and runs
// it. `resampler` (the output grid's, same face size) gives the estimate;
// without one (null) there is none (NaN) and target_error_pct must be 0.
Result<ProgressiveOutcome> run_progressive(sim::SceneDesc scene, const ProgressiveSettings& settings,
                                           const sim::Resampler* resampler,
                                           const IterationCallback& on_iteration = {},
                                           const CancelCheck& cancel = {},
                                           const sim::Simulation* previous = nullptr);

}  // namespace gonio::cli
