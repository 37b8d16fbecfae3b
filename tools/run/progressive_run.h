// The progressive loop that `gonio simulate` and `gonio watch` share:
// iterations of photons traced into one far field, a callback after each,
// and three ways to stop — every planned iteration done, the estimated
// candela error under a target (--target-error), or the caller asking (a
// changed model in `gonio watch`).
//
// The error estimate is the one `gonio bench` validates against its reference
// (tools/bench/bench_reference.h: "estimated" against "measured" from two halves):
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
// Under the Sobol' sampler (sim/samplers/sampler.h) photons are not independent:
// scrambled Sobol' points are better spread than that, and the count-based
// estimate over-states their error (1.3–4× at 2²⁰ photons on the samples).
// There the estimate comes from the run's K replicates (photon i belongs to
// replicate i mod K, an independent scramble; sim::Simulation::
// replicate_far_field): each replicate's far field, binned into the same
// table, is an independent unbiased estimate I_{r,b}, and the run's table is
// (for N a multiple of K exactly) their mean, whose variance per bin is
// estimated without bias by s_b² / K, s_b² = Σ_r (I_{r,b} − Ī_b)² / (K − 1):
//   estimated_rms_error_pct = 100 · √(Σ Ω_b s_b² / K / Σ Ω_b) / max_b I_b
// The bracket is an unbiased estimate of the mean squared error (no
// small-K factor is needed for it: s² is unbiased for any K ≥ 2; a
// Student-t factor would be for a confidence interval of one bin, not for
// the mean square over thousands of bins, whose sum has many more degrees
// of freedom). The error of a randomised QMC estimate falls faster than
// 1/√photons, so the photons still needed for a target are over-stated by
// the 1/√photons rule: the run just reaches the target sooner than planned.
// Guided emission (unequal photon power) and runs with K = 1 have no
// replicates: they keep the count-based estimate.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>

#include "photometry/diagnostics.h"
#include "sim/detectors/far_field.h"
#include "sim/detectors/resample.h"
#include "sim/scene.h"
#include "sim/simulation.h"

namespace gonio::app {

// The count-based estimate above for a far field of plain emission on the
// resampler's grid [%]; NaN where nothing escaped.
double estimated_rms_error_pct(const sim::FarField& field, const sim::Resampler& resampler);
// The replicates' estimate above from the tables already binned: the run's
// (its peak) and the replicates' (≥ 2, same grid) [%]; NaN where nothing
// escaped.
double replicate_table_error_pct(const sim::BinnedField& table, std::span<const sim::BinnedField> tables);
// The estimate of a simulation: from its replicates where it has them
// (sim::Simulation::sobol_replicates() ≥ 2, at least one photon each),
// count-based otherwise [%]; NaN where nothing escaped.
double estimated_rms_error_pct(const sim::Simulation& simulation, const sim::Resampler& resampler);

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

}  // namespace gonio::app
