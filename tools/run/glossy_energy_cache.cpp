#include "tools/run/glossy_energy_cache.h"

#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <set>
#include <string_view>
#include <utility>

#include "io/support/bytes.h"
#include "io/support/cache_folder.h"
#include "io/support/content_hash.h"
#include "io/support/file_io.h"
#include "sim/bsdfs/glossy_energy.h"

namespace gonio::app {
namespace {

static_assert(std::endian::native == std::endian::little, "the cache stores numbers little-endian");

constexpr char kMagic[16] = {'g', 'o', 'n', 'i', 'o', '-', 'g', 'l', 'o', 's', 's', 'y', '-', 'e', 'n', '\n'};
using Nodes = std::array<double, sim::kEnergyBins + 1>;
// magic, key, mx, my, the nodes, the digest.
constexpr std::size_t kFileBytes = sizeof kMagic + 8 + 2 * sizeof(double) + sizeof(Nodes) + 8;

// Everything a table depends on: the file's name, and the header's check.
std::uint64_t key_of(double mx, double my) {
  io::ContentHash h;
  h.text("beckmann-glossy-energy");
  h.value(static_cast<std::uint32_t>(sim::kGlossyEnergyRevision));
  h.value(static_cast<std::uint32_t>(sim::kEnergyBins));
  h.value(static_cast<std::uint32_t>(sim::kEnergyQuadrature));
  h.value(mx);
  h.value(my);
  return h.digest();
}

std::string serialize(const sim::GlossyEnergy& t) {
  std::string out(kMagic, sizeof kMagic);
  io::append_bytes(out, key_of(t.mx, t.my));
  io::append_bytes(out, t.mx);
  io::append_bytes(out, t.my);
  io::append_bytes(out, t.e);
  io::append_digest(out);
  return out;
}

std::shared_ptr<const sim::GlossyEnergy> deserialize(std::string_view bytes, double mx, double my) {
  if (bytes.size() != kFileBytes || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0) return nullptr;
  const std::optional<std::string_view> sealed = io::without_digest(bytes);
  if (!sealed) return nullptr;
  io::ByteReader in(*sealed);
  in.skip(sizeof kMagic);
  std::uint64_t key = 0;
  double file_mx = 0.0, file_my = 0.0;
  Nodes e{};
  if (!in.get(&key) || !in.get(&file_mx) || !in.get(&file_my) || !in.get(&e)) return nullptr;
  // Bit for bit the roughness asked for (not merely equal: −0.0 and the like).
  if (key != key_of(mx, my) || std::bit_cast<std::uint64_t>(file_mx) != std::bit_cast<std::uint64_t>(mx) ||
      std::bit_cast<std::uint64_t>(file_my) != std::bit_cast<std::uint64_t>(my))
    return nullptr;
  return sim::glossy_energy_from_nodes(mx, my, e);
}

}  // namespace

std::string glossy_energy_cache_name(double mx, double my) {
  return io::cache_entry_name(io::CacheEntry::GlossyEnergy, key_of(mx, my));
}

std::shared_ptr<const sim::GlossyEnergy> read_cached_glossy_energy(double mx, double my, const std::string& cache_dir) {
  if (cache_dir.empty()) return nullptr;
  const std::string path = (std::filesystem::path(cache_dir) / glossy_energy_cache_name(mx, my)).string();
  Result<std::string> bytes = io::read_file(path, kFileBytes + 1);
  if (!bytes.ok()) return nullptr;
  std::shared_ptr<const sim::GlossyEnergy> t = deserialize(*bytes, mx, my);
  if (t) io::mark_cache_entry_used(path);
  return t;
}

bool store_glossy_energy(const sim::GlossyEnergy& table, const std::string& cache_dir) {
  if (cache_dir.empty()) return false;
  const std::string path = (std::filesystem::path(cache_dir) / glossy_energy_cache_name(table.mx, table.my)).string();
  return io::make_directories(cache_dir).ok() && io::write_file_atomic(path, serialize(table)).ok();
}

GlossyEnergySource load_glossy_energy_tables(const sim::SceneDesc& scene, const std::string& cache_dir) {
  GlossyEnergySource s;
  if (cache_dir.empty()) return s;  // built by Simulation::create, as before
  std::set<std::pair<double, double>> seen;
  for (const sim::Material& m : scene.materials) {
    // The lobes sim::prepare gives a table (sim/bsdfs/lobes.cpp).
    if (!(m.glossy > 0.0 && m.glossy_compensation && m.glossy_mx > 0.0 && m.glossy_my > 0.0)) continue;
    if (!seen.insert({m.glossy_mx, m.glossy_my}).second) continue;
    if (std::shared_ptr<const sim::GlossyEnergy> t = read_cached_glossy_energy(m.glossy_mx, m.glossy_my, cache_dir)) {
      sim::offer_glossy_energy(std::move(t));
      ++s.from_cache;
      continue;
    }
    // Built once per process (sim::glossy_energy shares it), then stored.
    std::shared_ptr<const sim::GlossyEnergy> built = sim::glossy_energy(m.glossy_mx, m.glossy_my);
    ++s.built;
    if (store_glossy_energy(*built, cache_dir)) ++s.stored;
  }
  return s;
}

}  // namespace gonio::app
