// Gonio's cache folder (`--cache DIR`): files that save work between runs,
// each written atomically by its owner (io/support/file_io.h) under a name that says
// what it holds — the model checks' results (mesh-check-<hash>.json,
// io/model/model_check_cache.h), the overlaps that resample the far field onto
// the files' grids (resampler-<hash>.bin, tools/run/resampler_cache.h), the
// tessellations of CAD models (cad-<hash>.bin, io/model/cad.h) and the glossy
// lobes' energy tables (glossy-energy-<hash>.bin, tools/run/glossy_energy_cache.h).
//
// The folder is kept to a size limit, least recently used entries first: a
// read that uses an entry marks it used (its modification time set to now),
// and trim_cache removes the entries used longest ago until the folder's
// entries fit in nine tenths of the limit (so that a folder at the limit is
// not trimmed again at every run). Only Gonio's entries are counted and
// removed — other files in a folder named by --cache are left alone — and
// temporary files an interrupted write left behind (".<entry>.tmp<digits>")
// once they are an hour old.
#pragma once

#include <cstdint>
#include <string>

namespace gonio::io {

// Gonio's cache folder by default: $XDG_CACHE_HOME/gonio, else
// $HOME/.cache/gonio; empty when neither variable is set.
std::string default_cache_dir();

// The default limit of the folder's entries [bytes]: 1 GiB (an entry is a
// few kB for a model's checks, 2–4 MB for a resampler at the defaults).
inline constexpr std::uint64_t kDefaultCacheLimitBytes = std::uint64_t{1} << 30;

// The kinds of entry, and the file name of one under its key (16
// lower-case hex digits): mesh-check-<key>.json, resampler-<key>.bin,
// cad-<key>.bin, glossy-energy-<key>.bin.
enum class CacheEntry { MeshCheck, Resampler, CadModel, GlossyEnergy };
std::string cache_entry_name(CacheEntry kind, std::uint64_t key);

// Whether `name` (a file name, no folder) is one of Gonio's entries: a name
// cache_entry_name gives for some kind and key.
bool is_cache_entry_name(const std::string& name);

// Marks the entry at `path` as used now (its modification time). Failures
// are ignored: the entry only ages.
void mark_cache_entry_used(const std::string& path);

struct CacheTrim {
  std::uint64_t entries = 0;          // entries left
  std::uint64_t bytes = 0;            // their size
  std::uint64_t removed_entries = 0;  // entries removed (temporary leftovers not counted)
  std::uint64_t removed_bytes = 0;
};

// Removes the least recently used entries of `dir` while its entries hold
// more than `limit_bytes` (0: no limit), down to 9/10 of the limit, and
// temporary leftovers an hour old. A missing or unreadable folder, and an
// entry that cannot be removed, are no error (the figures say what is left).
CacheTrim trim_cache(const std::string& dir, std::uint64_t limit_bytes);

}  // namespace gonio::io
