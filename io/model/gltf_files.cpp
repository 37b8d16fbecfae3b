#include "io/model/gltf_files.h"

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string_view>

#include <nlohmann/json.hpp>

#include "io/support/file_io.h"
#include "io/model/gltf.h"

namespace gonio::io {
namespace {

std::uint32_t u32(std::string_view bytes, std::size_t at) {
  std::uint32_t v = 0;
  std::memcpy(&v, bytes.data() + at, 4);  // glTF is little-endian, as is every target we build for
  return v;
}

int hex(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

std::string percent_decoded(const std::string& uri) {
  std::string out;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && hex(uri[i + 1]) >= 0 && hex(uri[i + 2]) >= 0) {
      out += static_cast<char>(hex(uri[i + 1]) * 16 + hex(uri[i + 2]));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

}  // namespace

namespace fs = std::filesystem;

std::optional<std::string> outside_the_folder(const std::string& base_dir, const std::string& uri) {
  const fs::path ref(uri);
  if (ref.is_absolute() || ref.has_root_name() || ref.has_root_directory())
    return std::string("is an absolute path");
  const fs::path normal = ref.lexically_normal();
  if (!normal.empty() && *normal.begin() == "..") return std::string("climbs out with '..'");
  std::error_code ec;
  const fs::path base = fs::weakly_canonical(fs::path(base_dir), ec);
  if (ec) return std::nullopt;  // the folder itself is unreadable: opening the file fails anyway
  const fs::path target = fs::weakly_canonical(fs::path(base_dir) / ref, ec);
  if (ec) return std::nullopt;
  const fs::path inside = target.lexically_relative(base);
  if (inside.empty() || *inside.begin() == "..")
    return "resolves through a symbolic link to " + target.string();
  return std::nullopt;
}

std::string outside_message(const std::string& reference, const std::string& why) {
  return reference + " " + why + ", outside the model's folder: refused (a model names files " +
         "beside it; --allow-outside-paths reads it anyway)";
}

Result<std::vector<std::string>> gltf_files(const std::string& model) {
  Result<std::string> bytes = read_file(model, kMaxFileBytes);
  if (!bytes.ok()) return bytes.error();
  std::string_view text = bytes.value();
  if (text.size() >= 4 && text.substr(0, 4) == "glTF") {
    // GLB: 12-byte header, then the JSON chunk (length, type "JSON", bytes).
    if (text.size() < 20 || text.substr(16, 4) != "JSON")
      return make_error(model, "a .glb file without its JSON chunk (truncated or not glTF)");
    const std::uint32_t length = u32(text, 12);
    if (length > text.size() - 20) return make_error(model, "the .glb JSON chunk runs past the end of the file (truncated)");
    text = text.substr(20, length);
  }
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return make_error(model, "not valid glTF JSON");
  const std::filesystem::path folder = std::filesystem::path(model).parent_path();
  std::vector<std::string> files{model};
  auto add = [&](const nlohmann::json& entry) {
    if (!entry.is_object() || !entry.contains("uri") || !entry["uri"].is_string()) return;
    const std::string uri = entry["uri"].get<std::string>();
    if (uri.rfind("data:", 0) == 0 || uri.empty()) return;
    const std::string path = (folder / percent_decoded(uri)).string();
    for (const std::string& f : files)
      if (f == path) return;
    files.push_back(path);
  };
  for (const char* key : {"buffers", "images"})
    if (j.contains(key) && j[key].is_array())
      for (const auto& e : j[key]) add(e);
  if (j.contains("extensions") && j["extensions"].is_object()) {
    const auto& ext = j["extensions"];
    if (ext.contains("EXT_lights_ies") && ext["EXT_lights_ies"].is_object()) {
      const auto& ies = ext["EXT_lights_ies"];
      if (ies.contains("lights") && ies["lights"].is_array())
        for (const auto& e : ies["lights"]) add(e);
    }
  }
  return files;
}

}  // namespace gonio::io
