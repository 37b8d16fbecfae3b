#include "io/model/model_check_cache.h"

#include <nlohmann/json.hpp>

#include <filesystem>

#include "io/support/cache_folder.h"
#include "io/support/content_hash.h"
#include "io/support/file_io.h"
#include "io/model/model_check.h"

namespace gonio::io {
namespace {

constexpr const char* kFormat = "gonio mesh check";
// An entry is a few hundred bytes with its findings; anything this large is
// not one of ours.
constexpr std::size_t kMaxEntryBytes = std::size_t{256} << 20;

std::optional<Severity> parse_severity(const std::string& s) {
  for (Severity v : {Severity::Info, Severity::Warning, Severity::Error})
    if (s == to_string(v)) return v;
  return std::nullopt;
}

bool has(const nlohmann::json& j, const char* key, nlohmann::json::value_t type) {
  if (!j.contains(key)) return false;
  const nlohmann::json& v = j.at(key);
  if (type == nlohmann::json::value_t::number_unsigned) return v.is_number_unsigned();
  return v.type() == type;
}

std::optional<std::vector<MeshFinding>> parse_mesh(const nlohmann::json& m, const sim::Mesh& mesh,
                                                   bool refractive) {
  using T = nlohmann::json::value_t;
  if (!m.is_object() || !has(m, "vertices", T::number_unsigned) || !has(m, "triangles", T::number_unsigned) ||
      !has(m, "refractive", T::boolean) || !has(m, "findings", T::array))
    return std::nullopt;
  if (m.at("vertices").get<std::uint64_t>() != mesh.positions.size() ||
      m.at("triangles").get<std::uint64_t>() != mesh.triangle_count() ||
      m.at("refractive").get<bool>() != refractive)
    return std::nullopt;
  std::vector<MeshFinding> findings;
  for (const nlohmann::json& f : m.at("findings")) {
    if (!f.is_object() || !has(f, "severity", T::string) || !has(f, "code", T::string) ||
        !has(f, "detail", T::string))
      return std::nullopt;
    const std::optional<Severity> severity = parse_severity(f.at("severity").get<std::string>());
    if (!severity || f.at("code").get<std::string>().empty()) return std::nullopt;
    findings.push_back({*severity, f.at("code").get<std::string>(), f.at("detail").get<std::string>()});
  }
  return findings;
}

}  // namespace

std::uint64_t check_group_key(const sim::SceneDesc& scene, const CheckGroup& group) {
  ContentHash h;
  h.value(kModelCheckRevision);
  h.value(group.meshes.size());
  for (std::size_t k = 0; k < group.meshes.size(); ++k) {
    const sim::Mesh& mesh = scene.meshes[group.meshes[k]];
    h.value(group.refractive[k]);
    h.values(mesh.positions);
    h.values(mesh.indices);
  }
  return h.digest();
}

std::string cached_checks_name(std::uint64_t key) { return cache_entry_name(CacheEntry::MeshCheck, key); }

std::optional<std::vector<std::vector<MeshFinding>>> read_cached_checks(const std::string& dir, std::uint64_t key,
                                                                        const sim::SceneDesc& scene,
                                                                        const CheckGroup& group) {
  using T = nlohmann::json::value_t;
  const std::string path = (std::filesystem::path(dir) / cached_checks_name(key)).string();
  Result<std::string> bytes = read_file(path, kMaxEntryBytes);
  if (!bytes.ok()) return std::nullopt;
  const nlohmann::json j = nlohmann::json::parse(bytes.value(), nullptr, /*allow_exceptions=*/false);
  if (!j.is_object() || !has(j, "format", T::string) || j.at("format").get<std::string>() != kFormat ||
      !j.contains("revision") || !j.at("revision").is_number_integer() ||
      j.at("revision").get<long long>() != kModelCheckRevision || !has(j, "meshes", T::array) ||
      j.at("meshes").size() != group.meshes.size())
    return std::nullopt;
  std::vector<std::vector<MeshFinding>> results;
  results.reserve(group.meshes.size());
  for (std::size_t k = 0; k < group.meshes.size(); ++k) {
    std::optional<std::vector<MeshFinding>> m =
        parse_mesh(j.at("meshes")[k], scene.meshes[group.meshes[k]], group.refractive[k] != 0);
    if (!m) return std::nullopt;
    results.push_back(std::move(*m));
  }
  mark_cache_entry_used(path);
  return results;
}

bool write_cached_checks(const std::string& dir, std::uint64_t key, const sim::SceneDesc& scene,
                         const CheckGroup& group, const std::vector<std::vector<MeshFinding>>& findings) {
  if (!make_directories(dir).ok()) return false;
  nlohmann::json meshes = nlohmann::json::array();
  for (std::size_t k = 0; k < group.meshes.size(); ++k) {
    const sim::Mesh& mesh = scene.meshes[group.meshes[k]];
    nlohmann::json list = nlohmann::json::array();
    for (const MeshFinding& f : findings[k])
      list.push_back({{"severity", to_string(f.severity)}, {"code", f.code}, {"detail", f.detail}});
    meshes.push_back({{"vertices", mesh.positions.size()},
                      {"triangles", mesh.triangle_count()},
                      {"refractive", group.refractive[k] != 0},
                      {"findings", std::move(list)}});
  }
  const nlohmann::json j = {{"format", kFormat}, {"revision", kModelCheckRevision}, {"meshes", std::move(meshes)}};
  return write_file_atomic((std::filesystem::path(dir) / cached_checks_name(key)).string(), j.dump() + "\n").ok();
}

}  // namespace gonio::io
