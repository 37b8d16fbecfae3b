#include "io/model_check_cache.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "io/file_io.h"
#include "io/content_hash.h"
#include "io/model_check.h"

namespace gonio::io {
namespace {

constexpr const char* kFormat = "gonio model check";
// An entry is a few hundred bytes per mesh with findings; anything this
// large is not one of ours.
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

std::uint64_t model_check_key(const sim::SceneDesc& scene, const RefractiveFlags& refractive) {
  ContentHash h;
  h.value(kModelCheckRevision);
  h.value(scene.meshes.size());
  for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
    h.value(refractive[i]);
    h.values(scene.meshes[i].positions);
    h.values(scene.meshes[i].indices);
  }
  return h.digest();
}

std::string cached_checks_name(std::uint64_t key) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "model-check-%016llx.json", static_cast<unsigned long long>(key));
  return buf;
}

std::optional<ModelCheckResults> read_cached_checks(const std::string& dir, std::uint64_t key,
                                                    const sim::SceneDesc& scene,
                                                    const RefractiveFlags& refractive) {
  using T = nlohmann::json::value_t;
  const std::string path = (std::filesystem::path(dir) / cached_checks_name(key)).string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return std::nullopt;
  Result<std::string> bytes = read_file(path, kMaxEntryBytes);
  if (!bytes.ok()) return std::nullopt;
  const nlohmann::json j = nlohmann::json::parse(bytes.value(), nullptr, /*allow_exceptions=*/false);
  if (!j.is_object() || !has(j, "format", T::string) || j.at("format").get<std::string>() != kFormat ||
      !j.contains("revision") || !j.at("revision").is_number_integer() ||
      j.at("revision").get<long long>() != kModelCheckRevision || !has(j, "meshes", T::array) ||
      j.at("meshes").size() != scene.meshes.size())
    return std::nullopt;
  ModelCheckResults results;
  results.reserve(scene.meshes.size());
  for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
    std::optional<std::vector<MeshFinding>> m = parse_mesh(j.at("meshes")[i], scene.meshes[i], refractive[i] != 0);
    if (!m) return std::nullopt;
    results.push_back(std::move(*m));
  }
  return results;
}

bool write_cached_checks(const std::string& dir, std::uint64_t key, const sim::SceneDesc& scene,
                         const RefractiveFlags& refractive, const ModelCheckResults& results) {
  if (!make_directories(dir).ok()) return false;
  nlohmann::json meshes = nlohmann::json::array();
  for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
    nlohmann::json list = nlohmann::json::array();
    for (const MeshFinding& f : results[i])
      list.push_back({{"severity", to_string(f.severity)}, {"code", f.code}, {"detail", f.detail}});
    meshes.push_back({{"vertices", scene.meshes[i].positions.size()},
                      {"triangles", scene.meshes[i].triangle_count()},
                      {"refractive", refractive[i] != 0},
                      {"findings", std::move(list)}});
  }
  const nlohmann::json j = {{"format", kFormat}, {"revision", kModelCheckRevision}, {"meshes", std::move(meshes)}};
  return write_file_atomic((std::filesystem::path(dir) / cached_checks_name(key)).string(), j.dump() + "\n").ok();
}

std::string default_cache_dir() {
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
    return (std::filesystem::path(xdg) / "gonio").string();
  if (const char* home = std::getenv("HOME"); home && *home)
    return (std::filesystem::path(home) / ".cache" / "gonio").string();
  return "";
}

}  // namespace gonio::io
