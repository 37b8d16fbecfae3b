// The reference run of `gonio bench`: a long run of plain emission with a
// seed of its own (so its noise is independent of the series it judges),
// cached in the output directory as reference.exr (the far field: flux and
// photons per texel) and reference.json (what it was made from). A cached
// reference is reused only when everything that shapes it matches: program
// version, a hash of the model file, a hash of the scene as loaded (so a
// changed buffer, image or profile the model refers to counts too), seed,
// photons, face size, bounce limit and Embree's robust mode. Threads do not
// matter (same seed, same bytes).
//
// Its own noise is measured twice: estimated from its photon statistics
// (sim/convergence.h: ν and the binned variance), and measured by splitting
// it into its two halves, photons [0, N/2) and [N/2, N): they are
// independent runs of N/2 photons, so the mean-scaled squared difference of
// the halves is 2 × 2ν of the whole (each half has twice its variance).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "photometry/diagnostics.h"
#include "sim/convergence.h"
#include "sim/distributed.h"
#include "sim/detectors/far_field.h"
#include "sim/detectors/resample.h"
#include "sim/scene.h"

namespace gonio::app {

// What a reference is made from; equal keys, equal references.
struct ReferenceKey {
  std::string program_version;
  std::string tracer_revision;  // kTracerRevision: a hash of the sim/ sources
  std::string model_hash;  // io::content_hash_hex (XXH3-64) of the model file's bytes, 16 hex digits
  std::string scene_hash;  // scene_hash() of the loaded scene (XXH3-64), 16 hex digits
  std::uint64_t seed = 0;
  std::uint64_t photons = 0;
  int face_size = 0;
  int max_bounces = 0;
  bool robust_embree = true;

  nlohmann::json to_json() const;
  bool operator==(const ReferenceKey&) const = default;
};

struct ReferenceNoise {
  double cube_map_estimated = 0.0;  // √ν after mean scaling [1]
  double cube_map_measured = 0.0;   // from the two halves [1]
  double table_estimated_pct = 0.0; // relative to the peak [%]
  double table_measured_pct = 0.0;  // from the two halves [%]
};

struct Reference {
  ReferenceKey key;
  sim::FarField far_field{1};
  double trace_s = 0.0;     // tracing time when it was made [s]
  int threads = 0;          // threads it was made with
  ReferenceNoise noise;
  bool reused = false;      // read from the cache rather than traced now
};

// Reads DIR/reference.{json,exr} if they hold `key`, else traces the
// reference (photons in iterations of up to 2²⁴, `progress(done, total)`
// after each) and writes both files. Errors: an unreadable or inconsistent
// cache is not an error (it is traced again); a failed trace or write is.
// With `ranks` (an MPI job, sim/distributed.h; collective): rank 0 decides
// whether its cache holds the reference, every rank traces its share, and
// rank 0 alone writes and returns the reference; the other ranks return
// one with the key alone.
Result<Reference> load_or_make_reference(const std::string& dir, const ReferenceKey& key,
                                         const sim::SceneDesc& scene, int threads,
                                         std::shared_ptr<const sim::Resampler> resampler,
                                         const std::function<void(std::uint64_t, std::uint64_t)>& progress,
                                         const sim::Ranks* ranks = nullptr);

}  // namespace gonio::app
