// The outputs' resamplers (sim/detectors/resample.h) kept on disk, keyed by all they
// depend on: the face size, the photometric frame, the grid and the
// builder's revision (sim::kResamplerRevision). Building one is the largest
// part of writing a run's files (the latitude-longitude map's 1.4° grid at
// face 128: ~0.35 s on two cores, an IES grid ~0.07 s); reading it back
// takes milliseconds, and the same rows come back, so the files are the same
// bytes either way.
//
// Files: DIR/resampler-<hash>.bin, written atomically; one that is
// unreadable, truncated, corrupted (XXH3 of its contents stored at its end)
// or for other parameters is rebuilt and rewritten. A folder that cannot be
// written is no error: the resampler is then built every time.
#pragma once

#include <memory>
#include <string>

#include "photometry/frame.h"
#include "sim/detectors/resample.h"

namespace gonio::app {

struct ResamplerSource {
  bool from_cache = false;  // read back, not built
  bool stored = false;      // built and written to the cache
};

// The resampler for (face size, frame, grid), from `cache_dir` where it holds
// one, else built (and stored there when cache_dir is not empty). Requires
// what the sim::Resampler constructor requires.
sim::Resampler cached_resampler(int face_size, const photometry::PhotometricFrame& frame,
                                const sim::CGammaGrid& grid, const std::string& cache_dir,
                                ResamplerSource* source = nullptr);

// The same resampler, shared: the last few that came from (or went into) a
// cache folder are kept in this process, keyed by the folder and the cache
// file's name, so that repeated evaluations (gonio.simulate in a loop, the
// candela table after the run's estimate) neither read nor hash the file
// again (issue 40). An empty cache_dir keeps nothing: built every time.
std::shared_ptr<const sim::Resampler> shared_resampler(int face_size, const photometry::PhotometricFrame& frame,
                                                       const sim::CGammaGrid& grid, const std::string& cache_dir);

// The cache file's name for these parameters (resampler-<16 hex>.bin).
std::string resampler_cache_name(int face_size, const photometry::PhotometricFrame& frame,
                                 const sim::CGammaGrid& grid);

}  // namespace gonio::app
