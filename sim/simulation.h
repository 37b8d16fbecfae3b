// A progressive simulation: iterations of N photons traced on T threads into
// one far field and one set of books, with a callback after each iteration
// (progress, previews).
//
// Photons are traced in fixed chunks of kChunkPhotons; photon i of the run
// (counting across iterations) draws from (seed, i). All accumulators are
// integers, so the far field and the ledger are identical bytes for any
// thread count, and K iterations of N photons equal one of K·N.
//
// Over the ranks of an MPI job (SimulationSettings::ranks, sim/distributed.h)
// each rank traces its share of every iteration's chunks and the iteration's
// integer counts are summed across the ranks before they are added: every
// rank then holds the same far field, books and guide, identical bytes to
// one process's whatever the rank count.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "photometry/diagnostics.h"
#include "sim/distributed.h"
#include "sim/emitters/emission_guide.h"
#include "sim/detectors/far_field.h"
#include "sim/tracer/spectral.h"
#include "sim/ledger.h"
#include "sim/tracer/next_event.h"
#include "sim/scene.h"
#include "sim/tracer/tracer.h"

namespace gonio::sim {

inline constexpr std::uint64_t kChunkPhotons = 4096;

struct SimulationSettings {
  std::uint64_t photons_per_iteration = 1'000'000;  // ≥ 1, < 2³²
  int iterations = 10;                               // ≥ 1; at most 2³⁹ photons in all
  std::uint64_t seed = 1;
  // Where photons' numbers come from (sim/samplers/sampler.h): pseudo-random or
  // Owen-scrambled Sobol' points; either gives the same bytes for any
  // thread count, iteration split or rank split.
  SamplerKind sampler = SamplerKind::Random;
  // Sobol': photon i belongs to replicate i mod K, an independent scramble
  // (sim/samplers/sampler.h), 1 … kMaxSobolReplicates; their spread gives the error
  // estimate (tools/run/progressive_run.h). Part of what photon i draws.
  int sobol_replicates = kSobolReplicates;
  int threads = 0;                                   // 0: every core
  int max_bounces = 100;                             // see TracerSettings
  int face_size = 128;  // texels per cube face edge: CubeMapGrid::face_size_for_step(2.5)
  bool robust_embree = true;                         // see EmbreeSceneOptions
  // BVH build quality (EmbreeSceneOptions); none: bvh_quality_for the
  // scene's unique triangles and photons_per_iteration · iterations.
  std::optional<EmbreeSceneOptions::Quality> bvh_quality;
  // Importance-guided emission (sim/emitters/emission_guide.h); off: plain emission.
  ImportanceSettings importance;
  // The job's ranks to share every iteration with (they must all run the
  // same scene and settings, iteration for iteration: run_iteration is
  // collective); null: this process alone. Not owned; must outlive the
  // Simulation.
  const Ranks* ranks = nullptr;
  // Keep the escapes of the run's photons 0 … N − 1 (Simulation::escaped_rays;
  // a ray file's rays); 0: none. This process's photons only under MPI.
  std::uint64_t capture_escaped_photons = 0;
  // Near-field planes at these distances [m] below the luminaire's
  // photometric centre (sim/detectors/near_field.h's luminous_centre, from a pilot of
  // the run's first photons); empty: none, and the photon loop pays nothing
  // for them.
  std::vector<double> near_field_distances_m;
  // Next-event estimation for the far field (sim/tracer/next_event.h): off, on, or
  // auto (on where the pilot finds that most escaping light leaves after a
  // non-delta event at surfaces whose connections escape). Not with guided
  // emission (on: an error; auto: off).
  NextEventMode next_event = NextEventMode::Off;
  int next_event_connections = kDefaultConnections;  // M per vertex, 1 … 1024
  // Luminance images from these viewing directions
  // (sim/detectors/luminance_image.h); no views: none, and the photon loop
  // pays nothing for them.
  LuminanceImageSettings luminance;
};

// What next-event estimation did in a run (Simulation::next_event()).
struct NextEventSummary {
  NextEventMode mode = NextEventMode::Off;
  bool enabled = false;          // connections made
  int connections_per_vertex = 0;
  double pilot_covered_share = 0.0;  // the pilot's shares (NextEventChoice) [0, 1]
  double pilot_multi_share = 0.0;
  std::vector<std::uint16_t> lobes;  // per mesh and side: the lobes connected (NextEventSettings)
  std::uint64_t vertices = 0, connections = 0, escaped = 0;  // over the run
  double booked_lm = 0.0;        // the connections' flux in the far field [lm]
  double covered_lm = 0.0;       // escapes they stand for, left out of the far field [lm]
};

struct SimulationStats {
  int iterations_done = 0;
  std::uint64_t photons = 0;   // drawn from the emitters so far
  std::uint64_t photons_traced = 0;  // traced so far: = photons unless guided emission dropped some
  std::uint64_t rays = 0;      // ray queries so far
  std::uint64_t volume_events = 0;   // free paths ended inside volumes so far
  double trace_s = 0.0;        // wall time spent tracing [s]
  double setup_s = 0.0;        // wall time of Simulation::create: the tracer's setup and
                               // the tallies [s]
  TracerSetupTimes tracer_setup;  // its parts (validation, emission tables, BVH)
  int threads = 0;             // threads used (by this rank)
  // Over MPI ranks (1 and this process's figures otherwise). `photons`,
  // `photons_traced`, `rays` count the whole job, and trace_s is this rank's
  // wall time including its waits, so photons_per_s() is the job's rate.
  int ranks = 1;
  std::uint64_t rank_photons = 0;  // drawn by this rank so far
  double rank_trace_s = 0.0;   // this rank's time tracing its share, without waits [s]
  double wait_s = 0.0;         // waiting for the other ranks to finish their shares [s]
  double reduce_s = 0.0;       // summing the iterations' counts across the ranks [s]
  double reduce_fastest_s = 0.0;  // the fastest iteration's sum: its cost without the
                                  // scheduling delays of a loaded machine [s]
  double rank_photons_per_s() const {
    return rank_trace_s > 0.0 ? static_cast<double>(rank_photons) / rank_trace_s : 0.0;
  }
  double photons_per_s() const { return trace_s > 0.0 ? static_cast<double>(photons) / trace_s : 0.0; }
  double rays_per_s() const { return trace_s > 0.0 ? static_cast<double>(rays) / trace_s : 0.0; }
};

class Simulation {
 public:
  // Checks the settings and the scene (errors name the part at fault) and
  // builds the tracer. The simulation keeps the scene: pass an rvalue to
  // move it in rather than hold two copies of a large model.
  // `previous`: an earlier simulation (e.g. of the model before it was
  // saved again); where its scene has the same geometry
  // (sim::same_geometry) and Embree options, its BVH is shared instead of
  // built again (stats().tracer_setup.bvh_reused).
  static Result<Simulation> create(SceneDesc scene, const SimulationSettings& settings,
                                   const Simulation* previous = nullptr);
  ~Simulation();
  Simulation(Simulation&&) noexcept;
  Simulation& operator=(Simulation&&) noexcept;

  // Traces one more iteration of photons_per_iteration photons.
  void run_iteration();
  // Traces one more iteration of `photons` photons (1 ≤ photons < 2³², and
  // at most 2³⁹ in all: GONIO_CHECK): photons keep their run-wide indices,
  // so iterations of any sizes that add up to the same count give the same
  // far field (progressive schedules, `gonio bench`). Over ranks, this rank
  // traces its share and the call is collective.
  void run_iteration(std::uint64_t photons);

  const SimulationSettings& settings() const;
  const SceneDesc& scene() const;
  const Tracer& tracer() const;
  SimulationStats stats() const;

  // The far field of every photon so far: per texel the escaped photons and
  // their flux, each photon carrying total flux / photons emitted (guided
  // emission: total flux × its power units / all power units emitted).
  FarField far_field() const;
  // Replicates counted (plain emission under the Sobol' sampler, or with
  // next-event estimation under either, with K > 1 replicates: K; 0
  // otherwise).
  int sobol_replicates() const;
  // The far field of replicate r's photons alone (i mod K = r), each
  // carrying total flux / that replicate's photons: an independent estimate
  // of the same far field (0 ≤ r < sobol_replicates()).
  FarField replicate_far_field(int replicate) const;
  // The escapes kept (SimulationSettings::capture_escaped_photons), by
  // photon index: the same whatever the threads.
  const std::vector<EscapedRay>& escaped_rays() const;
  // The near-field planes of every photon so far
  // (SimulationSettings::near_field_distances_m; empty when none), each
  // photon carrying the flux far_field() gives it.
  std::vector<NearFieldPlane> near_field() const;
  // Where the planes lie (null when none).
  const NearFieldPlanes* near_field_planes() const;
  // The luminance images of every photon so far (settings().luminance's
  // views, in order; empty when none).
  std::vector<LuminanceImage> luminance_images() const;
  // Next-event estimation's choice and counts (mode Off: nothing).
  NextEventSummary next_event() const;
  // The emission guide (null unless settings().importance.enabled).
  const EmissionGuide* emission_guide() const;

  // Spectral scenes (SceneDesc::spectral()): X and Z per texel beside the
  // far field's Y (its flux), same units; empty otherwise (sim/tracer/spectral.h).
  ColourFarField colour_far_field() const;
  // The books of every photon so far.
  Ledger ledger() const;
  // Total flux of the scene's emitters [lm].
  double total_flux_lm() const;

 private:
  struct Impl;
  explicit Simulation(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

struct SimulationProgress {
  int iteration = 0;             // iterations done
  int iterations = 0;            // planned
  std::uint64_t photons_done = 0;
  std::uint64_t photons_total = 0;
  double elapsed_s = 0.0;        // since tracing began [s]
  double photons_per_s = 0.0;    // mean rate so far
  double remaining_s = 0.0;      // estimate at that rate [s]
};

// Runs all iterations, calling `on_iteration` (if set) after each.
Result<Simulation> simulate(
    SceneDesc scene, const SimulationSettings& settings,
    const std::function<void(const SimulationProgress&, const Simulation&)>& on_iteration = {});

}  // namespace gonio::sim
