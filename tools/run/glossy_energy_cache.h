// The glossy lobes' energy tables (sim/bsdfs/glossy_energy.h) kept on disk
// between processes, keyed by all a table depends on: the lobe (Beckmann,
// F = 1), its roughness mx and my, the table's nodes (sim::kEnergyBins), the
// quadrature (sim::kEnergyQuadrature) and the table code's revision
// (sim::kGlossyEnergyRevision). Building the bell's two tables took ~0.3 s
// of the first preview of `gonio watch` (issue 43); reading them takes well
// under a millisecond, and the same table comes back bit for bit (the
// nodes are stored; e_avg and the cdf are computed from them as a build
// does), so the outputs are the same bytes either way.
//
// Files: DIR/glossy-energy-<hash>.bin (io/support/cache_folder.h), written
// atomically; one that is unreadable, truncated, corrupted (XXH3 of its
// contents stored at its end), for another key or with nodes outside
// [0, 1] is rebuilt and rewritten. A folder that cannot be written is no
// error: the tables are then built every time. An empty cache_dir
// (`--no-cache`) builds them in the process as before.
#pragma once

#include <memory>
#include <string>

#include "sim/bsdfs/glossy_energy.h"
#include "sim/scene.h"

namespace gonio::app {

struct GlossyEnergySource {
  int from_cache = 0;  // tables read back
  int built = 0;       // tables built here (stored where the folder allows)
  int stored = 0;      // of those, written to the cache
};

// Makes the energy table of every compensated glossy lobe of `scene` the
// process's own (sim::offer_glossy_energy): read from `cache_dir` where it
// holds one, else built and stored there. Tables the process already holds
// are left alone. Simulation::create then finds them all.
GlossyEnergySource load_glossy_energy_tables(const sim::SceneDesc& scene, const std::string& cache_dir);

// The table of a roughness as `cache_dir` holds it; null where it holds
// none, or one that is damaged or for another key (the file is not removed:
// the next store replaces it).
std::shared_ptr<const sim::GlossyEnergy> read_cached_glossy_energy(double mx, double my, const std::string& cache_dir);

// Writes `table` into `cache_dir` (made where missing), atomically; false
// where the folder cannot be written.
bool store_glossy_energy(const sim::GlossyEnergy& table, const std::string& cache_dir);

// The cache file's name for a roughness (glossy-energy-<16 hex>.bin).
std::string glossy_energy_cache_name(double mx, double my);

}  // namespace gonio::app
