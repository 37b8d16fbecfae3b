// The series of `gonio bench`: how the error against the reference falls
// with time and photons, for the raw far field, the preview filter in its
// settings, and (optionally) importance-guided emission.
//
// Every series starts from the same seed. One plain run is traced, and after
// each iteration every filter setting filters the same far field: the filter
// never changes the photons, so the filtered series share one trace. Each
// series is charged the shared tracing time plus its own filter time (the
// filter applied once per iteration, as a progressive preview would), and
// nothing else: computing the errors is the benchmark's own cost. A guided
// series traces a run of its own (same seed, same iterations); its time
// includes the guide's update after each iteration. So does each series of
// another sampler (sim/samplers/sampler.h: the Sobol' series against the
// pseudo-random ones, same seed, same iterations).
//
// Iterations grow geometrically: the run reaches first · 2^(k / steps)
// photons after iteration k (rounded; the last one ends at `photons`), so
// the points lie evenly on the charts' log axes and the first iteration can
// be as sparse as the thesis's (well under one photon per texel).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "photometry/diagnostics.h"
#include "sim/convergence.h"
#include "sim/emitters/emission_guide.h"
#include "sim/tracer/next_event.h"
#include "sim/filter/preview_filter.h"
#include "sim/detectors/resample.h"
#include "sim/samplers/sampler.h"
#include "sim/scene.h"

namespace gonio::app {

struct BenchSettings {
  std::uint64_t photons = std::uint64_t{1} << 25;       // each series, in all
  std::uint64_t first_photons = std::uint64_t{1} << 14; // the first iteration
  int steps_per_doubling = 2;                           // iterations per doubling of photons
  std::uint64_t seed = 1;                               // of every series
  int threads = 0;                                      // 0: every core
  int max_bounces = 100;
  int face_size = 128;                                  // far-field cube map
  bool importance = false;                              // add the guided series
  // Sampler of the series above (sim/samplers/sampler.h); with compare_samplers the
  // Sobol' raw and adaptive series are added to pseudo-random ones.
  sim::SamplerKind sampler = sim::SamplerKind::Random;
  bool compare_samplers = false;
  int sobol_replicates = sim::kSobolReplicates;          // of the Sobol' runs (sim/samplers/sampler.h)
  sim::ImportanceSettings importance_settings{true};    // for them
  // Next-event estimation of the unguided series (sim/tracer/next_event.h).
  sim::NextEventMode next_event = sim::NextEventMode::Auto;
  int next_event_connections = sim::kDefaultConnections;
  double target_pct = 1.0;                              // candela RMS error to time [%]
  double cube_target = 0.1;                             // cube-map RMSE to time [1]
};

// Photons after each iteration: strictly increasing, ending at `photons`.
std::vector<std::uint64_t> photon_schedule(std::uint64_t first, std::uint64_t photons, int steps_per_doubling);

struct SeriesSpec {
  std::string name;   // CSV and file key, e.g. "bilateral-100"
  std::string label;  // legend, e.g. "bilateral, threshold 100"
  bool filtered = false;
  sim::PreviewFilterParams filter;  // when filtered
  bool guided = false;
  sim::SamplerKind sampler = sim::SamplerKind::Random;  // its run's
};

// raw; bilinear and bilateral at fixed thresholds 50, 100, 150, 200, 300
// (the thesis's mode, no adaptive stability); the adaptive default filter;
// with `importance`, guided raw and guided with the adaptive filter; all
// traced with `sampler`. With `add_sobol` (and a random `sampler`): Sobol'
// raw ("sobol") and Sobol' with the adaptive filter ("sobol-adaptive").
std::vector<SeriesSpec> default_series(bool importance, sim::SamplerKind sampler = sim::SamplerKind::Random,
                                       bool add_sobol = false);

struct SeriesPoint {
  int iteration = 0;                 // 1-based
  std::uint64_t photons = 0;         // drawn from the emitters so far
  std::uint64_t photons_traced = 0;  // traced so far (< photons only when guided)
  double trace_s = 0.0;              // shared tracing time so far [s]
  double filter_s = 0.0;             // this series's filter time so far [s]
  double time_s = 0.0;               // trace_s + filter_s [s]
  sim::CubeMapError cube;
  sim::TableError table;
  // The run's own estimate of its candela RMS error (tools/run/progressive_run.h:
  // count-based, or from the Sobol' replicates) [%]: raw series only (NaN
  // for filtered ones, and where nothing escaped); against table.rms_pct it
  // checks the estimate --target-error stops by.
  double estimated_rms_pct = 0.0;
};

struct SeriesResult {
  SeriesSpec spec;
  std::vector<SeriesPoint> points;
  // Summary (NaN where it does not apply or was not reached).
  double time_to_target_s = 0.0;        // table RMS error below target_pct for good [s]
  double photons_to_target = 0.0;       // the same in photons traced
  double time_to_cube_target_s = 0.0;   // cube-map RMSE below cube_target for good [s]
  double photons_to_cube_target = 0.0;  // the same in photons traced
  double cube_slope = 0.0;              // log-log slope of cube-map RMSE against photons traced
  double table_slope = 0.0;             // the same for the table's RMS error
  double filter_ms_per_iteration = 0.0; // mean filter time per iteration [ms]
};

struct BenchProgress {
  const char* run = "";  // "plain" or "guided"
  int iteration = 0;
  int iterations = 0;
  std::uint64_t photons = 0;
};

// Runs every series. Errors: the scene or settings (from the simulation).
Result<std::vector<SeriesResult>> run_series(
    const sim::SceneDesc& scene, const BenchSettings& settings, const std::vector<SeriesSpec>& specs,
    const sim::ConvergenceReference& reference,
    const std::function<void(const BenchProgress&)>& progress = {});

}  // namespace gonio::app
