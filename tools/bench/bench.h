// `gonio bench` as the application's own function, for every front end (the
// command line, the Python module, tests): plain options in, a checked plan,
// then one call that benches each model — a cached reference run
// (tools/bench/bench_reference.h), the series against it
// (tools/bench/bench_series.h), and DIR/series.csv, DIR/bench.json and the
// charts (tools/bench/bench_report.h); with several models each gets
// DIR/<name>/. A results page (Markdown) over all of them where asked
// (scripts/results.sh makes docs/results.md this way).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "photometry/diagnostics.h"
#include "sim/distributed.h"
#include "sim/detectors/resample.h"
#include "tools/bench/bench_report.h"
#include "tools/bench/bench_series.h"
#include "tools/run/console.h"
#include "tools/run/model_input.h"
#include "tools/run/option_bounds.h"

namespace gonio::app {

inline constexpr Bounds<long long> kBenchPhotonsBounds{1, 1LL << 36};
inline constexpr Bounds<long long> kBenchFirstBounds{1, 4'294'967'295LL};
inline constexpr Bounds<long long> kBenchStepsBounds{1, 16};
inline constexpr Bounds<long long> kBenchReferenceBounds{2, 1LL << 39};
inline constexpr Bounds<long long> kBenchSeedBounds{0, 9'223'372'036'854'775'806LL};
inline constexpr Bounds<long long> kBenchReferenceSeedBounds{0, 9'223'372'036'854'775'807LL};
inline constexpr Bounds<long long> kBenchFaceSizeBounds{1, 1024};
inline constexpr Bounds<double> kBenchTargetBounds{1e-3, 100.0};       // --target [% of peak]
inline constexpr Bounds<double> kBenchCubeTargetBounds{1e-4, 100.0};   // --cube-target
inline constexpr Bounds<double> kMinAcceptanceBounds{1e-4, 1.0};       // --min-acceptance

// gonio bench's options as a front end gives them: `gonio bench --help`'s
// options by the same names, with its defaults.
struct BenchOptions {
  std::vector<std::string> models;  // MODEL...
  std::string out_dir;              // --out DIR (created if missing)
  std::string page;                 // --page FILE: the results page; empty: none
  long long photons = 1LL << 25, first = 1LL << 14, steps = 2, seed = 1;
  long long reference_photons = 0;              // --reference N; 0: 16 × photons
  std::optional<long long> reference_seed;      // --reference-seed S; none: seed + 1
  long long threads = 0, max_bounces = 100;
  long long face_size = 0;                      // --face-size F; 0: what the grid needs
  double c_step = 5.0, gamma_step = 2.5, target = 1.0, cube_target = 0.1;
  bool importance = false;                      // --importance
  std::string next_event = "auto";              // --next-event auto|on|off (unguided series; sim/tracer/next_event.h)
  std::optional<long long> emission_face_size;  // --emission-face-size E (guided; default 32)
  std::optional<double> min_acceptance;         // --min-acceptance A (guided; default 1/16)
  std::string sampler = "both";                 // --sampler random|sobol|both
  bool no_png = false;                          // --no-png: charts as SVG only
  ModelInputOptions model_input;                // --allow-outside-paths, --no-instancing
  std::string command;  // the command as given, for the page ("gonio bench …")
};

// The options checked and resolved.
struct BenchPlan {
  std::vector<std::string> models;
  std::string out_dir, page, command;
  BenchSettings settings;
  sim::CGammaGrid grid;
  std::uint64_t reference_photons = 0;
  std::uint64_t reference_seed = 0;
  bool png = true;
  ModelInputOptions model_input;
};

// Errors name the option as the command line spells it.
Result<BenchPlan> plan_bench(const BenchOptions& options);

// How a front end follows a bench; every member may be empty.
struct BenchHooks {
  // The models' warnings and errors, and the error that stops the bench
  // (tools/run/console.h; empty: printed to stderr).
  MessageSink on_message;
  // The reference run of model `name`: photons done of total.
  std::function<void(const std::string& name, std::uint64_t done, std::uint64_t total)> on_reference;
  // The series of model `name`: after each iteration of each run.
  std::function<void(const std::string& name, const BenchProgress& progress)> on_series;
  // A model's files are written (rank 0).
  std::function<void(const BenchOutcome& outcome)> on_model;
};

// Benches every model of the plan (the page last, where asked). Under MPI
// (`ranks`; null: one process) every rank calls it: the ranks share the
// reference runs, rank 0 alone runs the series and writes, and a failure on
// one rank ends the job (sim::Ranks::abort). Returns each model's outcome
// (none on the other ranks; the reference's far field left empty), or
// nothing where a model could not be benched or a file written, each problem
// told to hooks.on_message.
std::optional<std::vector<BenchOutcome>> bench(const BenchPlan& plan, const BenchHooks& hooks = {},
                                               const sim::Ranks* ranks = nullptr);

}  // namespace gonio::app
