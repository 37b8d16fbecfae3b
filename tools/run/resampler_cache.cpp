#include "tools/run/resampler_cache.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <optional>
#include <utility>
#include <vector>

#include "io/support/bytes.h"
#include "io/support/cache_folder.h"
#include "io/support/content_hash.h"
#include "io/support/file_io.h"

namespace gonio::app {
namespace {

static_assert(std::endian::native == std::endian::little, "the cache stores numbers little-endian");

constexpr char kMagic[16] = {'g', 'o', 'n', 'i', 'o', '-', 'r', 'e', 's', 'a', 'm', 'p', 'l', 'e', 'r', '\n'};
// Larger files are not read (a face of 512 at 1° holds a few million entries).
constexpr std::size_t kMaxFileBytes = std::size_t{1} << 30;

// Everything the rows depend on, hashed: the file's name, and the header's
// check that the entry is for these parameters.
void hash_parameters(io::ContentHash& h, int face_size, const photometry::PhotometricFrame& frame,
                     const sim::CGammaGrid& grid) {
  h.value(static_cast<std::uint32_t>(sim::kResamplerRevision));
  h.value(static_cast<std::uint32_t>(face_size));
  h.value(grid.c_step_deg);
  h.value(grid.gamma_step_deg);
  // Explicit angle lists (non-uniform grids); empty lists add their sizes only.
  h.value(static_cast<std::uint64_t>(grid.c_angles_deg.size()));
  for (double c : grid.c_angles_deg) h.value(c);
  h.value(static_cast<std::uint64_t>(grid.gamma_angles_deg.size()));
  for (double g : grid.gamma_angles_deg) h.value(g);
  h.vec(frame.c0);
  h.vec(frame.c90);
  h.vec(frame.up);
}

std::string serialize(const sim::Resampler& r, const photometry::PhotometricFrame& frame) {
  const sim::Resampler::Rows rows = r.rows();
  std::string out(kMagic, sizeof kMagic);
  io::ContentHash parameters;
  hash_parameters(parameters, r.face_size(), frame, r.grid());
  io::append_bytes(out, parameters.digest());
  io::append_bytes(out, static_cast<std::uint64_t>(rows.solid_angle_sr.size()));
  io::append_bytes(out, static_cast<std::uint64_t>(rows.texel.size()));
  io::append_all_bytes(out, rows.row_start);
  io::append_all_bytes(out, rows.texel);
  io::append_all_bytes(out, rows.fraction);
  io::append_all_bytes(out, rows.solid_angle_sr);
  io::append_digest(out);
  return out;
}

std::optional<sim::Resampler> deserialize(std::string_view bytes, int face_size,
                                          const photometry::PhotometricFrame& frame,
                                          const sim::CGammaGrid& grid) {
  if (bytes.size() < sizeof kMagic + 8 || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    return std::nullopt;
  const std::optional<std::string_view> sealed = io::without_digest(bytes);
  if (!sealed) return std::nullopt;
  io::ByteReader in(*sealed);
  in.skip(sizeof kMagic);
  std::uint64_t parameters_digest = 0, bins = 0, nonzeros = 0;
  io::ContentHash parameters;
  hash_parameters(parameters, face_size, frame, grid);
  if (!in.get(&parameters_digest) || parameters_digest != parameters.digest()) return std::nullopt;
  if (!in.get(&bins) || !in.get(&nonzeros) || bins != grid.bin_count()) return std::nullopt;
  sim::Resampler::Rows rows;
  if (!in.get_all(&rows.row_start, bins + 1) || !in.get_all(&rows.texel, nonzeros) ||
      !in.get_all(&rows.fraction, nonzeros) || !in.get_all(&rows.solid_angle_sr, bins))
    return std::nullopt;
  if (in.at() != sealed->size()) return std::nullopt;
  Result<sim::Resampler> r = sim::Resampler::from_rows(face_size, grid, std::move(rows));
  if (!r.ok()) return std::nullopt;
  return std::move(r.value());
}

}  // namespace

std::string resampler_cache_name(int face_size, const photometry::PhotometricFrame& frame,
                                 const sim::CGammaGrid& grid) {
  io::ContentHash h;
  hash_parameters(h, face_size, frame, grid);
  return io::cache_entry_name(io::CacheEntry::Resampler, h.digest());
}

sim::Resampler cached_resampler(int face_size, const photometry::PhotometricFrame& frame,
                                const sim::CGammaGrid& grid, const std::string& cache_dir,
                                ResamplerSource* source) {
  ResamplerSource s;
  std::string path;
  if (!cache_dir.empty()) {
    path = (std::filesystem::path(cache_dir) / resampler_cache_name(face_size, frame, grid)).string();
    if (Result<std::string> bytes = io::read_file(path, kMaxFileBytes); bytes.ok()) {
      if (std::optional<sim::Resampler> r = deserialize(*bytes, face_size, frame, grid)) {
        s.from_cache = true;
        io::mark_cache_entry_used(path);
        if (source) *source = s;
        return std::move(*r);
      }
    }
  }
  sim::Resampler built(face_size, frame, grid);
  if (!path.empty()) {
    s.stored = io::make_directories(cache_dir).ok() && io::write_file_atomic(path, serialize(built, frame)).ok();
  }
  if (source) *source = s;
  return built;
}

std::shared_ptr<const sim::Resampler> shared_resampler(int face_size, const photometry::PhotometricFrame& frame,
                                                       const sim::CGammaGrid& grid, const std::string& cache_dir) {
  if (cache_dir.empty()) return std::make_shared<const sim::Resampler>(cached_resampler(face_size, frame, grid, cache_dir));
  struct Kept {
    std::string cache_dir, name;
    std::shared_ptr<const sim::Resampler> resampler;
  };
  constexpr std::size_t kKept = 4;
  static std::mutex mutex;
  static std::vector<Kept> kept;  // the most recently used last
  const std::string name = resampler_cache_name(face_size, frame, grid);
  {
    const std::lock_guard<std::mutex> lock(mutex);
    for (std::size_t i = 0; i < kept.size(); ++i) {
      if (kept[i].cache_dir != cache_dir || kept[i].name != name) continue;
      std::rotate(kept.begin() + static_cast<std::ptrdiff_t>(i), kept.begin() + static_cast<std::ptrdiff_t>(i) + 1,
                  kept.end());
      return kept.back().resampler;
    }
  }
  auto made = std::make_shared<const sim::Resampler>(cached_resampler(face_size, frame, grid, cache_dir));
  const std::lock_guard<std::mutex> lock(mutex);
  if (kept.size() >= kKept) kept.erase(kept.begin());
  kept.push_back({cache_dir, name, made});
  return made;
}

}  // namespace gonio::app
