#include "tools/run/progressive_run.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include "sim/convergence.h"

namespace gonio::app {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A Resampler owned elsewhere, as the shared_ptr ConvergenceReference takes.
std::shared_ptr<const sim::Resampler> borrowed(const sim::Resampler& r) {
  return std::shared_ptr<const sim::Resampler>(&r, [](const sim::Resampler*) {});
}

}  // namespace

double estimated_rms_error_pct(const sim::FarField& field, const sim::Resampler& resampler) {
  auto self = sim::ConvergenceReference::create(field, borrowed(resampler));
  if (!self.ok()) return kNaN;
  return self->table_noise_pct();
}

double replicate_table_error_pct(const sim::BinnedField& table, std::span<const sim::BinnedField> tables) {
  GONIO_CHECK(tables.size() >= 2);
  const std::size_t bins = table.flux_lm.size();
  const auto k = static_cast<double>(tables.size());
  double peak_cd = 0.0, weighted = 0.0, solid_angle = 0.0;
  for (std::size_t b = 0; b < bins; ++b) {
    const double omega = table.solid_angle_sr[b];
    if (!(omega > 0.0)) continue;
    peak_cd = std::max(peak_cd, table.intensity_cd(b));
    double m = 0.0;
    for (const sim::BinnedField& t : tables) m += t.flux_lm[b];
    m /= k;
    double ss = 0.0;
    for (const sim::BinnedField& t : tables) ss += (t.flux_lm[b] - m) * (t.flux_lm[b] - m);
    // Var of the mean intensity: s² / K, s² = ss / (K − 1), in cd² (÷ Ω²).
    weighted += omega * ss / (k - 1.0) / k / (omega * omega);
    solid_angle += omega;
  }
  if (!(peak_cd > 0.0)) return kNaN;
  return 100.0 * std::sqrt(weighted / solid_angle) / peak_cd;
}

double estimated_rms_error_pct(const sim::Simulation& simulation, const sim::Resampler& resampler) {
  const int k = simulation.sobol_replicates();
  if (k < 2 || simulation.stats().photons < static_cast<std::uint64_t>(k))
    return estimated_rms_error_pct(simulation.far_field(), resampler);
  // One replicate's far field at a time: K tables, not K cube maps. The
  // estimate reads only the tables' flux (and the bins' solid angles):
  // bin_flux gives the values bin() would, without the variances (issue 40).
  std::vector<sim::BinnedField> tables(static_cast<std::size_t>(k));
  for (int r = 0; r < k; ++r)
    tables[static_cast<std::size_t>(r)].flux_lm = resampler.bin_flux(simulation.replicate_far_field(r).flux_lm());
  sim::BinnedField table;
  table.flux_lm = resampler.bin_flux(simulation.far_field().flux_lm());
  table.solid_angle_sr = resampler.bin_solid_angle_sr();
  return replicate_table_error_pct(table, tables);
}

const char* to_string(StopReason reason) {
  switch (reason) {
    case StopReason::Iterations: return "iterations";
    case StopReason::TargetError: return "target-error";
    case StopReason::Cancelled: return "cancelled";
  }
  return "?";
}

Result<ProgressiveOutcome> run_progressive(sim::SceneDesc scene, const ProgressiveSettings& settings,
                                           const sim::Resampler* resampler,
                                           const IterationCallback& on_iteration, const CancelCheck& cancel,
                                           const sim::Simulation* previous) {
  GONIO_CHECK(settings.target_error_pct >= 0.0);
  GONIO_CHECK(resampler || settings.target_error_pct == 0.0);
  auto created = sim::Simulation::create(std::move(scene), settings.simulation, previous);
  if (!created.ok()) return created.error();
  ProgressiveOutcome out{std::move(created.value()), StopReason::Iterations, 0, kNaN};
  sim::Simulation& s = out.simulation;
  const sim::SimulationSettings& ss = settings.simulation;
  const int iterations = ss.iterations;
  const std::uint64_t per_iteration = ss.photons_per_iteration;
  std::uint64_t first = settings.first_iteration_photons;
  if (first == 0 || first > per_iteration) first = per_iteration;
  const std::uint64_t total = first + per_iteration * static_cast<std::uint64_t>(iterations - 1);
  for (int k = 0; k < iterations; ++k) {
    const std::uint64_t photons = k == 0 ? first : per_iteration;
    if (!cancel) {
      s.run_iteration(photons);
    } else {
      for (std::uint64_t done = 0; done < photons;) {
        if (cancel()) {
          out.stopped_by = StopReason::Cancelled;
          return out;
        }
        const std::uint64_t slice = std::min(kCancelSlicePhotons, photons - done);
        s.run_iteration(slice);
        done += slice;
      }
    }
    out.iterations_done = k + 1;
    const sim::SimulationStats st = s.stats();
    IterationReport r;
    r.progress.iteration = k + 1;
    r.progress.iterations = iterations;
    r.progress.photons_done = st.photons;
    r.progress.photons_total = total;
    r.progress.elapsed_s = st.trace_s;
    r.progress.photons_per_s = st.photons_per_s();
    if (resampler) out.estimated_rms_error_pct = estimated_rms_error_pct(s, *resampler);
    r.estimated_rms_error_pct = out.estimated_rms_error_pct;
    // Photons still to trace: the rest of the plan, or fewer where the
    // estimate (∝ 1/√photons) reaches the target sooner.
    double remaining = static_cast<double>(total - st.photons);
    const bool reached = settings.target_error_pct > 0.0 &&
                         out.estimated_rms_error_pct <= settings.target_error_pct;
    if (settings.target_error_pct > 0.0 && std::isfinite(out.estimated_rms_error_pct)) {
      const double ratio = out.estimated_rms_error_pct / settings.target_error_pct;
      remaining = std::min(remaining, std::max(0.0, static_cast<double>(st.photons) * (ratio * ratio - 1.0)));
    }
    if (reached) remaining = 0.0;
    r.progress.remaining_s = r.progress.photons_per_s > 0.0 ? remaining / r.progress.photons_per_s : 0.0;
    const bool go_on = on_iteration ? on_iteration(r, s) : true;
    if (reached) {
      out.stopped_by = StopReason::TargetError;
      break;
    }
    if (!go_on) {
      out.stopped_by = StopReason::Cancelled;
      break;
    }
  }
  return out;
}

}  // namespace gonio::app
