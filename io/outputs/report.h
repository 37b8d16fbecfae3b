// report.json of a simulation: the settings, the speed, and the energy
// ledger, as nlohmann::json so that later stages (outputs, filter) can add
// their own fields before it is written.
//
// Field names and units (every flux in lumens):
//   program {name, version}, model, seed, settings {...},
//   emitted_lm, escaped_lm, absorbed_lm, cutoff_lm,
//   photons_emitted, photons_escaped, photons_absorbed, photons_cutoff,
//   photon_power_lm, ledger {photons_close, flux_imbalance_lm, and for
//   spectral runs radiant_imbalance_w}, radiant (spectral runs: radiant_json),
//   photons_per_s, rays_per_s, rays, rays_per_photon, wall_s, trace_s,
//   setup_s, threads, iterations_done,
//   setup {load_s, check_s, validate_s, emission_tables_s, bvh_s, shading_s,
//          meshes, meshes_from_cache, max_rss_after_load_bytes,
//          max_rss_after_checks_bytes}  — the phases between the saved model
//          and the first photon [s]: reading the model, the model checks
//          (io/model/model_check.h; meshes found in the check cache are not checked
//          again), and the tracer's setup: scene validation, emission tables,
//          Embree BVH, per-corner shading data (sim/tracer/tracer.h),
//   max_rss_bytes (the process's memory high-water mark, getrusage ru_maxrss),
//   emitters [{name, emitted_lm, escaped_lm, absorbed_lm, cutoff_lm,
//              photons_emitted, photons_escaped, photons_absorbed, photons_cutoff}],
//   meshes [{name, material, hits, absorbed_lm, cutoff_lm, photons_absorbed,
//            photons_cutoff}],
//   materials [{name, hits, absorbed_lm, cutoff_lm, photons_absorbed, photons_cutoff}].
#pragma once

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "photometry/diagnostics.h"
#include "sim/ledger.h"

namespace gonio::io {

// What a run reports, as plain data.
struct SimulationReport {
  std::string program_version;
  std::string model;  // the model file (or scene name)

  // Settings.
  std::uint64_t photons_per_iteration = 0;
  int iterations = 0;
  std::uint64_t seed = 0;
  int threads = 0;
  int max_bounces = 0;
  int face_size = 0;
  bool robust_embree = true;
  std::string bvh_quality;        // the BVH build quality used: low, medium or high
  bool bvh_quality_auto = false;  // chosen by size and planned photons (--bvh-quality auto)

  // Speed.
  int iterations_done = 0;
  std::uint64_t photons = 0;
  std::uint64_t rays = 0;
  double wall_s = 0.0;   // the whole command [s]
  double trace_s = 0.0;  // tracing alone [s]
  double setup_s = 0.0;  // Simulation::create: the tracer's setup and the tallies [s]

  // The setup's phases [s] (see the top); 0 where a phase did not run.
  struct SetupPhases {
    double load_s = 0.0;
    double check_s = 0.0;
    double validate_s = 0.0;
    double emission_tables_s = 0.0;
    double bvh_s = 0.0;
    bool bvh_reused = false;  // the BVH of the previous run (gonio watch) served: same geometry
    double shading_s = 0.0;
    std::size_t meshes = 0;             // meshes the checks looked at (each instanced mesh once)
    std::size_t instances = 0;          // placements of instanced meshes (sim::Instance)
    std::size_t triangles_unique = 0;   // triangles stored: each instanced mesh once
    std::size_t triangles_placed = 0;   // triangles traced: instances counted
    std::size_t meshes_from_cache = 0;  // of these, found in the check cache
    std::uint64_t max_rss_after_load_bytes = 0;    // peak_memory_bytes() after loading
    std::uint64_t max_rss_after_checks_bytes = 0;  // and after the checks
  } setup;
  std::uint64_t max_rss_bytes = 0;  // peak_memory_bytes() when the report was made

  sim::Ledger ledger;
};

// This process's memory high-water mark so far [bytes] (getrusage's
// ru_maxrss: resident set, KiB on Linux).
std::uint64_t peak_memory_bytes();

nlohmann::json to_json(const SimulationReport& report);

// A spectral run's radiant books as report.json's "radiant" gives them:
// emitted_w, escaped_w, absorbed_w, cutoff_w, escaped_spectrum
// {wavelengths_nm, w_per_nm} (the escaped light's spectrum, 5 nm bands),
// method.
nlohmann::json radiant_json(const sim::RadiantLedger& radiant);

// Writes JSON (indented, trailing newline) atomically.
Status write_json(const std::string& path, const nlohmann::json& json);

}  // namespace gonio::io
