// The only file that includes tinygltf. tinygltf parses the JSON, decodes
// buffers (GLB chunk, data URIs, external files through our size-checked
// file callbacks) and fills its Model; everything after that — bounds of
// accessors, indices, transforms, lights, materials, extras — is checked
// here, because tinygltf 2.7 validates little of it.
#include "io/model/gltf.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <set>
#include <string_view>
#include <utility>

#include "io/support/file_io.h"
#include "io/model/gltf_files.h"
#include "io/model/gltf_lights.h"
#include "io/materials/bsdf_file.h"
#include "io/model/gltf_material.h"
#include "io/model/material_extras.h"
#include "io/photometric/ies.h"
#include "io/photometric/ldt.h"
#include "io/photometric/tm25.h"
#include "photometry/format.h"
#include "photometry/flux.h"
#include "photometry/reflectance.h"
#include "sim/affine.h"

namespace gonio::io {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Three floats of an accessor (or a Vec3f) as a double vector.
Vec3 widen(float x, float y, float z) {
  return {static_cast<double>(x), static_cast<double>(y), static_cast<double>(z)};
}

// ---------------------------------------------------------------------------
// Light profiles: the one place that turns profile bytes into a distribution
// and a distribution into its flux.

// Reads an IES LM-63 (or, with `eulumdat`, an EULUMDAT) profile. `name` is
// the file name used in messages; `dir` resolves TILT=<file> references. The
// reader's own findings (with their file and line) are appended.
Result<photometry::Distribution> parse_profile(std::string_view bytes, const std::string& name,
                                               const std::string& dir, bool eulumdat,
                                               std::vector<Finding>& findings) {
  if (eulumdat) {
    Result<LdtFile> ldt = parse_ldt(bytes, name);
    if (!ldt.ok()) return ldt.error();
    findings.insert(findings.end(), ldt->findings.begin(), ldt->findings.end());
    return std::move(ldt->distribution);
  }
  Result<IesFile> ies = parse_ies(bytes, name, dir);
  if (!ies.ok()) return ies.error();
  findings.insert(findings.end(), ies->findings.begin(), ies->findings.end());
  return std::move(ies->distribution);
}

// Total luminous flux of a profile [lm] by solid-angle integration.
Result<double> profile_flux_lm(const photometry::Distribution& d, const std::string& name) {
  if (Status valid = photometry::validate(d); !valid.ok())
    return make_error(name, "invalid light profile: " + valid.error().message);
  const double flux = photometry::total_flux_lm(d);
  if (!(std::isfinite(flux) && flux > 0.0))
    return make_error(name, "the light profile emits no flux (" + format_number(flux) + " lm)");
  return flux;
}

// ---------------------------------------------------------------------------
// Bytes.

std::uint32_t read_u32le(const unsigned char* p) {
  return static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 |
         static_cast<std::uint32_t>(p[2]) << 16 | static_cast<std::uint32_t>(p[3]) << 24;
}

// Whether count elements of `elem` bytes at `stride` starting at `offset`
// fit in `limit` bytes, without overflowing.
bool fits(std::size_t offset, std::size_t count, std::size_t stride, std::size_t elem,
          std::size_t limit) {
  if (offset > limit) return false;
  if (count == 0) return true;
  if (elem > limit - offset) return false;
  return count - 1 <= (limit - offset - elem) / stride;
}

std::optional<std::string> base64_decode(std::string_view in) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+' || c == '-') return 62;
    if (c == '/' || c == '_') return 63;
    return -1;
  };
  std::string out;
  out.reserve(in.size() / 4 * 3);
  std::uint32_t acc = 0;
  int bits = 0;
  std::size_t i = 0;
  for (; i < in.size() && in[i] != '='; ++i) {
    const int v = value(in[i]);
    if (v < 0) return std::nullopt;
    acc = (acc << 6) | static_cast<std::uint32_t>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<char>((acc >> bits) & 0xFF));
    }
  }
  for (; i < in.size(); ++i)
    if (in[i] != '=') return std::nullopt;
  return out;
}

std::string percent_decode(std::string_view in) {
  std::string out;
  for (std::size_t i = 0; i < in.size(); ++i) {
    if (in[i] == '%' && i + 2 < in.size() && std::isxdigit(static_cast<unsigned char>(in[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(in[i + 2]))) {
      out.push_back(static_cast<char>(std::stoi(std::string(in.substr(i + 1, 2)), nullptr, 16)));
      i += 2;
    } else {
      out.push_back(in[i]);
    }
  }
  return out;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// The file an IES profile's TILT=<file> line names, if any (not NONE or
// INCLUDE): the first line that begins with "TILT" and an '='.
std::optional<std::string> tilt_file_of(std::string_view bytes) {
  auto trim = [](std::string_view t) {
    while (!t.empty() && std::isspace(static_cast<unsigned char>(t.front()))) t.remove_prefix(1);
    while (!t.empty() && std::isspace(static_cast<unsigned char>(t.back()))) t.remove_suffix(1);
    return t;
  };
  std::size_t start = 0;
  while (start < bytes.size()) {
    std::size_t end = bytes.find_first_of("\r\n", start);
    if (end == std::string_view::npos) end = bytes.size();
    const std::string_view line = trim(bytes.substr(start, end - start));
    start = end + 1;
    if (line.size() < 5 || lower(std::string(line.substr(0, 4))) != "tilt") continue;
    const std::string_view rest = trim(line.substr(4));
    if (rest.empty() || rest.front() != '=') continue;
    const std::string value(trim(rest.substr(1)));
    const std::string upper = lower(value);
    if (value.empty() || upper == "none" || upper == "include") return std::nullopt;
    return value;
  }
  return std::nullopt;
}

// The GLB container, checked completely before tinygltf sees it (its own
// check lets a BIN chunk header claim 8 bytes past the end).
Status validate_glb(std::string_view bytes, const std::string& path,
                    std::vector<Finding>& findings) {
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
  const std::size_t size = bytes.size();
  if (size < 12)
    return make_error(path, "truncated .glb: " + std::to_string(size) +
                             " bytes, shorter than the 12-byte header");
  const std::uint32_t version = read_u32le(p + 4);
  const std::uint32_t length = read_u32le(p + 8);
  if (version != 2)
    return make_error(path, "GLB container version " + std::to_string(version) +
                             "; only version 2 (glTF 2.0) is supported");
  if (length > size)
    return make_error(path, "truncated .glb: the header declares " + std::to_string(length) +
                             " bytes, the file has " + std::to_string(size));
  if (length < size)
    findings.push_back({Severity::Warning, "glb-trailing-bytes",
                        std::to_string(size - length) + " bytes after the declared end of the GLB",
                        {path}});
  std::size_t pos = 12;
  int chunk = 0;
  while (pos < length) {
    if (length - pos < 8)
      return make_error(path, "truncated .glb: chunk " + std::to_string(chunk) +
                               " header at byte " + std::to_string(pos) + " is incomplete");
    const std::uint32_t chunk_length = read_u32le(p + pos);
    const std::uint32_t chunk_type = read_u32le(p + pos + 4);
    if (chunk_length > length - pos - 8)
      return make_error(path, "truncated .glb: chunk " + std::to_string(chunk) + " declares " +
                               std::to_string(chunk_length) + " bytes, only " +
                               std::to_string(length - pos - 8) + " remain");
    if (chunk == 0 && chunk_type != 0x4E4F534Au)
      return make_error(path, "malformed .glb: the first chunk is not JSON");
    if (chunk == 0 && chunk_length == 0) return make_error(path, "malformed .glb: empty JSON chunk");
    pos += 8 + static_cast<std::size_t>(chunk_length);
    ++chunk;
  }
  if (chunk == 0) return make_error(path, "malformed .glb: no JSON chunk");
  return Ok{};
}

// ---------------------------------------------------------------------------
// tinygltf callbacks: file access limited to the model's folder and to
// kMaxFileBytes, no image decoding, no writing.

struct FsContext {
  std::string base_dir;  // absolute, without trailing '/'
  bool allow_outside = false;
  std::string refused;  // the first file reference refused, as a message
};

// tinygltf joins the model's folder and a buffer's or image's uri (also
// an absolute one); the part after the folder is the uri again. The file
// the uri names, or nothing where it is not the model's (tinygltf's second
// try, the working directory) or leaves the folder (the reason is kept).
std::optional<std::string> file_of(FsContext* ctx, const std::string& joined) {
  const std::string prefix = ctx->base_dir.back() == '/' ? ctx->base_dir : ctx->base_dir + "/";
  if (joined.rfind(prefix, 0) != 0) return std::nullopt;
  const std::string uri = joined.substr(prefix.size());
  if (!ctx->allow_outside) {
    if (const std::optional<std::string> why = outside_the_folder(ctx->base_dir, uri)) {
      if (ctx->refused.empty()) ctx->refused = outside_message("uri '" + uri + "'", *why);
      return std::nullopt;
    }
  }
  return fs::path(uri).is_absolute() ? uri : joined;
}

bool fs_exists(const std::string& path, void* user) {
  const std::optional<std::string> file = file_of(static_cast<FsContext*>(user), path);
  std::error_code ec;
  return file && fs::is_regular_file(*file, ec);
}

std::string fs_expand(const std::string& path, void*) { return path; }

bool fs_read(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
  const std::optional<std::string> file = file_of(static_cast<FsContext*>(user), path);
  if (!file) {
    if (err) *err += "not a file of the model's";
    return false;
  }
  Result<std::vector<unsigned char>> bytes = read_file_bytes(*file, kMaxFileBytes);
  if (!bytes.ok()) {
    if (err) *err += bytes.error().message;
    return false;
  }
  *out = std::move(bytes.value());
  return true;
}

bool fs_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err += "writing is disabled";
  return false;
}

bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                const unsigned char*, int, void*) {
  return true;  // images only texture the model; the simulation does not read them
}

// ---------------------------------------------------------------------------
// The loader.

constexpr double kPi = std::numbers::pi;

const std::set<std::string> kSupportedExtensions = {
    "KHR_lights_punctual",          "EXT_lights_ies",
    "KHR_materials_emissive_strength", "KHR_materials_transmission",
    "KHR_materials_ior",            "KHR_materials_specular",
    "KHR_materials_diffuse_transmission", "KHR_materials_volume",
    "KHR_texture_transform",  // textures are not read, so their transform is moot
    "EXT_mesh_gpu_instancing",
};
const std::set<std::string> kGeometryExtensions = {
    "KHR_draco_mesh_compression", "EXT_meshopt_compression", "KHR_mesh_quantization"};

struct IesLight {
  json def;
  std::string what;
  std::shared_ptr<const photometry::Distribution> profile;
  std::optional<double> flux_lm;  // integrated, cached
};

// Where an accessor's elements lie, checked against their bufferView before
// anything is allocated for them: the count must be backed by bytes.
struct ElementSource {
  const unsigned char* data = nullptr;  // null: zeros (no bufferView)
  std::size_t stride = 0;
};

// An accessor's float elements, read in place from the buffer where they are
// plain (a bufferView and no sparse substitution), else gathered once: a
// large part's positions and normals are not copied before they are used.
class FloatView {
 public:
  FloatView(ElementSource in_place, std::size_t count)
      : data_(in_place.data), stride_(in_place.stride), count_(count) {}
  FloatView(std::vector<float> gathered, std::size_t comps)
      : gathered_(std::move(gathered)),
        data_(reinterpret_cast<const unsigned char*>(gathered_.data())),
        stride_(4 * comps),
        count_(gathered_.size() / comps) {}
  FloatView(const FloatView&) = delete;
  FloatView& operator=(const FloatView&) = delete;
  FloatView(FloatView&&) = default;  // the vector's storage, and data_ into it, move along
  FloatView& operator=(FloatView&&) = default;

  std::size_t count() const { return count_; }  // elements
  float at(std::size_t element, std::size_t component) const {
    float f;
    std::memcpy(&f, data_ + element * stride_ + 4 * component, 4);
    return f;
  }

 private:
  std::vector<float> gathered_;
  const unsigned char* data_ = nullptr;
  std::size_t stride_ = 0;
  std::size_t count_ = 0;
};

// One placement of a glTF mesh: a node, or one copy of an
// EXT_mesh_gpu_instancing node.
struct Copy {
  sim::Affine world;
  std::string name;
};

class Loader {
 public:
  Loader(std::string path, std::vector<Finding>& findings, const GltfLoadOptions& options)
      : path_(std::move(path)), options_(options), findings_(findings) {}

  Result<sim::SceneDesc> load();

 private:
  Error fail(std::string message) const { return make_error(path_, std::move(message)); }
  void note(Severity s, const char* code, std::string message) {
    findings_.push_back({s, code, std::move(message), {path_}});
  }

  Status parse_file();
  Result<json> parse_blob(const std::string& text, const std::string& what) const;
  Result<const json*> gonio_extras(const json& extras, const std::string& what,
                                   std::initializer_list<const char*> known);
  Result<std::optional<double>> number(const json& obj, const char* key,
                                       const std::string& what) const;
  Result<std::optional<Vec3>> vec3(const json& obj, const char* key, const std::string& what) const;
  Result<std::optional<Rgb>> rgb(const json& obj, const char* key, const std::string& what) const;
  // extras.gonio.spectrum of a light (io/model/material_extras.h).
  Result<sim::EmitterSpectrum> emitter_spectrum(const json& obj, const std::string& what) const {
    return read_emitter_spectrum(obj, {path_}, what);
  }

  Status check_extensions();
  Status read_model_extras();
  Status read_root_lights();
  Result<std::vector<int>> root_nodes();
  Result<sim::Affine> local_transform(const tinygltf::Node& node, const std::string& what);
  void count_mesh_uses(const std::vector<int>& roots);
  Result<std::vector<Copy>> gpu_instances(const json& ext, const sim::Affine& world,
                                          const std::string& node_name, const std::string& what);
  Status visit_node(int index, const sim::Affine& world);
  Result<std::optional<sim::Mesh>> primitive_mesh(const tinygltf::Primitive& prim,
                                                  const std::string& what,
                                                  const sim::Affine& world);
  Status add_primitive(const tinygltf::Node& node, int node_index, int mesh_index, int prim_index,
                       const sim::Affine& world, std::vector<std::size_t>& area_emitters,
                       const std::vector<Copy>* copies);
  void add_area_emitter(std::uint32_t mesh_id, std::uint32_t instance, const sim::Mesh& world_mesh,
                        const std::string& name, const std::string& what,
                        std::vector<std::size_t>& area_emitters);
  Status add_khr_light(const json& ext, const sim::Affine& world, const std::string& node_what,
                       std::optional<double> node_flux, std::vector<std::size_t>& emitters);
  Status add_ray_set(const std::string& uri, const sim::Affine& world, const std::string& node_what,
                     std::optional<double> node_flux, std::vector<std::size_t>& emitters);
  Status add_ies_light(const json& ext, const sim::Affine& world, const std::string& node_what,
                       std::optional<double> node_flux, std::vector<std::size_t>& emitters);
  Status load_ies_profile(IesLight& light);
  Result<std::uint32_t> material(int index);
  // A spectral scene: coloured base colours become reflectance spectra
  // (photometry/reflectance.h) where extras give none.
  void colour_base_colours();

  Result<FloatView> read_floats(int accessor, int type, const std::string& what);
  Result<std::vector<std::uint32_t>> read_indices(int accessor, const std::string& what);
  Result<std::pair<const unsigned char*, std::size_t>> view_bytes(int view,
                                                                  const std::string& what) const;
  Result<ElementSource> source(const tinygltf::Accessor& a, std::size_t elem,
                               const std::string& what) const;
  Status read_elements(const tinygltf::Accessor& a, std::size_t elem, const std::string& what,
                       unsigned char* out);

  std::string node_what(int i) const {
    const auto& n = model_.nodes[static_cast<std::size_t>(i)];
    return n.name.empty() ? "node #" + std::to_string(i)
                          : "node '" + n.name + "' (#" + std::to_string(i) + ")";
  }

  std::string path_;
  GltfLoadOptions options_;
  std::string base_dir_;
  std::vector<Finding>& findings_;
  tinygltf::Model model_;
  sim::SceneDesc scene_;
  double unit_m_ = 1.0;
  sim::Affine root_;  // scales model units to metres
  struct Emission {
    double luminance_cd_m2;
    bool two_sided;
    sim::EmitterSpectrum spectrum;  // extras.gonio.spectrum; empty: none
  };
  std::vector<Emission> emission_;  // per scene material
  std::vector<Rgb> base_colours_;   // per scene material: baseColorFactor (RGB), as clamped
  std::vector<json> khr_lights_;
  std::vector<IesLight> ies_lights_;
  std::map<int, std::uint32_t> materials_;  // glTF material (−1 default) → scene material
  std::vector<char> visited_;
  std::size_t triangles_ = 0;  // unique: each instanced primitive once
  // Instancing: how often each glTF mesh is placed in the scene (nodes, and
  // EXT_mesh_gpu_instancing copies); the scene mesh made of each primitive
  // of a mesh placed more than once (nullopt: the primitive has no triangles).
  std::vector<std::size_t> mesh_uses_;
  std::map<std::pair<int, int>, std::optional<std::uint32_t>> prototypes_;
};

Result<json> Loader::parse_blob(const std::string& text, const std::string& what) const {
  if (text.empty()) return json();
  json j = json::parse(text, nullptr, false);
  if (j.is_discarded()) return fail(what + ": unreadable JSON");
  return j;
}

Result<const json*> Loader::gonio_extras(const json& extras, const std::string& what,
                                         std::initializer_list<const char*> known) {
  if (!extras.is_object()) return static_cast<const json*>(nullptr);
  auto it = extras.find("gonio");
  if (it == extras.end()) return static_cast<const json*>(nullptr);
  if (!it->is_object()) return fail(what + ": extras.gonio must be an object");
  for (const auto& item : it->items()) {
    const std::string& key = item.key();  // not a structured binding: clang 14 (fuzz build) cannot capture one
    if (std::none_of(known.begin(), known.end(), [&](const char* k) { return key == k; }))
      note(Severity::Warning, "unknown-extras-key",
           what + ": extras.gonio." + key + " is not a Gonio parameter here; ignored");
  }
  return &*it;
}

Result<std::optional<double>> Loader::number(const json& obj, const char* key,
                                             const std::string& what) const {
  return extras_number(obj, key, {path_}, what);
}

Result<std::optional<Vec3>> Loader::vec3(const json& obj, const char* key,
                                         const std::string& what) const {
  if (!obj.is_object()) return std::optional<Vec3>();
  auto it = obj.find(key);
  if (it == obj.end()) return std::optional<Vec3>();
  if (!it->is_array() || it->size() != 3 ||
      !std::all_of(it->begin(), it->end(), [](const json& v) { return v.is_number(); }))
    return fail(what + ": '" + key + "' must be an array of three numbers");
  const Vec3 v{(*it)[0].get<double>(), (*it)[1].get<double>(), (*it)[2].get<double>()};
  if (!(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)))
    return fail(what + ": '" + key + "' is not finite");
  return std::optional<Vec3>(v);
}

Result<std::optional<Rgb>> Loader::rgb(const json& obj, const char* key,
                                       const std::string& what) const {
  Result<std::optional<Vec3>> v = vec3(obj, key, what);
  if (!v.ok()) return v.error();
  if (!*v) return std::optional<Rgb>();
  return std::optional<Rgb>(Rgb{(*v)->x, (*v)->y, (*v)->z});
}

// The reflection lobes of a material from a coloured base colour share the
// base colour's Jakob–Hanika spectrum, scaled to the luminous reflectance
// map_material gave them (values clamped to 1). Grey base colours, materials
// without reflection and materials with extras.gonio.spectral_reflectance
// keep what they have; a grey scene is left alone.
void Loader::colour_base_colours() {
  if (!scene_.spectral()) return;
  for (std::size_t i = 0; i < scene_.materials.size() && i < base_colours_.size(); ++i) {
    sim::Material& m = scene_.materials[i];
    const Rgb& c = base_colours_[i];
    const double reflect = m.diffuse_reflect + m.mirror + m.glossy;
    const double lum = luminance(c);
    if (!m.spectral_reflectance.empty() || !(reflect > 0.0) || !(lum > 0.0) ||
        (std::abs(c.r - c.g) < 1e-9 && std::abs(c.g - c.b) < 1e-9))
      continue;
    const photometry::ReflectanceFit fit = photometry::fit_reflectance(c.r, c.g, c.b);
    photometry::SampledSpectrum s = photometry::sampled(fit.coefficients);
    const double scale = reflect / photometry::tristimulus_under_d65(s).Y;
    for (double& v : s.values) v = std::min(1.0, v * scale);
    m.spectral_reflectance = std::move(s);
    if (fit.delta_e > 1.0)
      note(Severity::Info, "colour-outside-gamut",
           "material '" + m.name + "': its base colour is matched by a reflectance spectrum only to ΔE " +
               format_number(fit.delta_e, 3));
  }
}

Status Loader::parse_file() {
  Result<std::string> bytes = read_file(path_, kMaxFileBytes);
  if (!bytes.ok()) return bytes.error();
  std::error_code ec;
  fs::path base = fs::absolute(fs::path(path_), ec).parent_path();
  if (ec) return fail("cannot resolve the model's folder: " + ec.message());
  base_dir_ = base.lexically_normal().string();
  while (base_dir_.size() > 1 && base_dir_.back() == '/') base_dir_.pop_back();

  const bool binary = bytes->size() >= 4 && bytes->compare(0, 4, "glTF") == 0;
  if (binary) {
    if (Status s = validate_glb(*bytes, path_, findings_); !s.ok()) return s;
  } else if (bytes->empty()) {
    return fail("empty file");
  }

  FsContext ctx{base_dir_, options_.allow_outside_paths, {}};
  tinygltf::TinyGLTF parser;
  parser.SetFsCallbacks({&fs_exists, &fs_expand, &fs_read, &fs_write, &ctx});
  parser.SetImageLoader(&skip_image, nullptr);
  parser.SetStoreOriginalJSONForExtrasAndExtensions(true);
  std::string err, warn;
  bool ok = false;
  try {
    const auto* data = reinterpret_cast<const unsigned char*>(bytes->data());
    const auto size = static_cast<unsigned int>(bytes->size());
    ok = binary ? parser.LoadBinaryFromMemory(&model_, &err, &warn, data, size, base_dir_)
                : parser.LoadASCIIFromString(&model_, &err, &warn, bytes->data(), size, base_dir_);
  } catch (const std::exception& e) {
    err += e.what();
    ok = false;
  }
  auto lines = [](const std::string& text) {
    std::vector<std::string> out;
    std::size_t start = 0;
    while (start < text.size()) {
      std::size_t end = text.find('\n', start);
      if (end == std::string::npos) end = text.size();
      if (end > start) out.push_back(text.substr(start, end - start));
      start = end + 1;
    }
    return out;
  };
  // A buffer or image outside the model's folder is an error of its own,
  // whatever tinygltf made of the file it was not given.
  if (!ctx.refused.empty()) return fail(ctx.refused);
  for (const std::string& w : lines(warn)) note(Severity::Warning, "gltf-parser", w);
  if (!ok) {
    std::string message;
    for (const std::string& e : lines(err)) message += (message.empty() ? "" : "; ") + e;
    return fail("not a readable glTF 2.0 " + std::string(binary ? "binary" : "JSON") +
                " file: " + (message.empty() ? "parse failed" : message));
  }
  for (const std::string& e : lines(err)) note(Severity::Warning, "gltf-parser", e);
  return Ok{};
}

Status Loader::check_extensions() {
  for (const std::string& ext : model_.extensionsRequired) {
    if (kGeometryExtensions.count(ext))
      return fail("the model requires " + ext + ", which Gonio does not read");
    if (!kSupportedExtensions.count(ext))
      note(Severity::Warning, "unsupported-extension",
           "required extension " + ext + " is not supported; loaded without it");
  }
  for (const std::string& ext : model_.extensionsUsed) {
    if (kGeometryExtensions.count(ext) &&
        std::find(model_.extensionsRequired.begin(), model_.extensionsRequired.end(), ext) ==
            model_.extensionsRequired.end())
      note(Severity::Warning, "unsupported-extension",
           "extension " + ext + " is not supported; the model's fallback geometry is used");
    else if (!kSupportedExtensions.count(ext) && !kGeometryExtensions.count(ext) &&
             std::find(model_.extensionsRequired.begin(), model_.extensionsRequired.end(), ext) ==
                 model_.extensionsRequired.end())
      note(Severity::Info, "unsupported-extension", "extension " + ext + " is ignored");
  }
  return Ok{};
}

Status Loader::read_model_extras() {
  // Scene extras win over asset extras.
  json extras;
  std::string what;
  if (model_.defaultScene >= 0 && static_cast<std::size_t>(model_.defaultScene) < model_.scenes.size()) {
    const auto& s = model_.scenes[static_cast<std::size_t>(model_.defaultScene)];
    Result<json> j = parse_blob(s.extras_json_string, "scene extras");
    if (!j.ok()) return j.error();
    if (j->is_object() && j->contains("gonio")) {
      extras = std::move(*j);
      what = "scene #" + std::to_string(model_.defaultScene);
    }
  }
  if (extras.is_null()) {
    Result<json> j = parse_blob(model_.asset.extras_json_string, "asset extras");
    if (!j.ok()) return j.error();
    extras = std::move(*j);
    what = "asset";
  }
  Result<const json*> g = gonio_extras(extras, what, {"frame", "unit_m"});
  if (!g.ok()) return g.error();
  if (!*g) return Ok{};
  const json& gonio = **g;

  Result<std::optional<double>> unit = number(gonio, "unit_m", what + " extras.gonio");
  if (!unit.ok()) return unit.error();
  if (*unit) {
    if (!(**unit > 0.0)) return fail(what + ": extras.gonio.unit_m must be > 0");
    unit_m_ = **unit;
  }
  if (auto it = gonio.find("frame"); it != gonio.end()) {
    const std::string fw = what + " extras.gonio.frame";
    if (!it->is_object()) return fail(fw + " must be an object with 'up' and 'c0'");
    for (const auto& [key, value] : it->items()) {
      (void)value;
      if (key != "up" && key != "c0")
        note(Severity::Warning, "unknown-extras-key", fw + "." + key + " is not a frame key; ignored");
    }
    Result<std::optional<Vec3>> up = vec3(*it, "up", fw);
    if (!up.ok()) return up.error();
    Result<std::optional<Vec3>> c0 = vec3(*it, "c0", fw);
    if (!c0.ok()) return c0.error();
    if (!*up || !*c0) return fail(fw + " needs both 'up' and 'c0'");
    const Vec3 u = **up, c = **c0;
    if (!(length(u) > 0.0) || !(length(c) > 0.0)) return fail(fw + ": zero-length direction");
    const Vec3 un = normalize(u);
    if (!(length(c - dot(c, un) * un) > 1e-9 * length(c)))
      return fail(fw + ": 'c0' must not be parallel to 'up'");
    scene_.frame = photometry::make_frame(u, c);
  }
  return Ok{};
}

Status Loader::read_root_lights() {
  Result<json> root = parse_blob(model_.extensions_json_string, "extensions");
  if (!root.ok()) return root.error();
  if (!root->is_object()) return Ok{};
  if (auto it = root->find("KHR_lights_punctual"); it != root->end()) {
    if (!it->is_object() || !it->contains("lights") || !(*it)["lights"].is_array())
      return fail("extensions.KHR_lights_punctual needs a 'lights' array");
    for (const json& l : (*it)["lights"]) khr_lights_.push_back(l);
  }
  if (auto it = root->find("EXT_lights_ies"); it != root->end()) {
    if (!it->is_object() || !it->contains("lights") || !(*it)["lights"].is_array())
      return fail("extensions.EXT_lights_ies needs a 'lights' array");
    std::size_t i = 0;
    for (const json& l : (*it)["lights"]) {
      IesLight light;
      light.def = l;
      std::string name = l.is_object() && l.contains("name") && l["name"].is_string()
                             ? l["name"].get<std::string>()
                             : std::string();
      light.what = "EXT_lights_ies light " +
                   (name.empty() ? "#" + std::to_string(i) : "'" + name + "' (#" + std::to_string(i) + ")");
      ies_lights_.push_back(std::move(light));
      ++i;
    }
  }
  return Ok{};
}

Result<std::vector<int>> Loader::root_nodes() {
  const int n = static_cast<int>(model_.nodes.size());
  for (int i = 0; i < n; ++i)
    for (int c : model_.nodes[static_cast<std::size_t>(i)].children)
      if (c < 0 || c >= n)
        return fail(node_what(i) + ": child index " + std::to_string(c) + " out of range (" +
                    std::to_string(n) + " nodes)");
  if (model_.defaultScene >= 0) {
    if (static_cast<std::size_t>(model_.defaultScene) >= model_.scenes.size())
      return fail("default scene " + std::to_string(model_.defaultScene) + " does not exist (" +
                  std::to_string(model_.scenes.size()) + " scenes)");
    const auto& nodes = model_.scenes[static_cast<std::size_t>(model_.defaultScene)].nodes;
    for (int i : nodes)
      if (i < 0 || i >= n)
        return fail("scene #" + std::to_string(model_.defaultScene) + ": node index " +
                    std::to_string(i) + " out of range (" + std::to_string(n) + " nodes)");
    return nodes;
  }
  if (!model_.scenes.empty())
    note(Severity::Info, "no-default-scene",
         "the file names no default scene; every root node is loaded");
  std::vector<char> has_parent(model_.nodes.size(), 0);
  for (const auto& node : model_.nodes)
    for (int c : node.children) has_parent[static_cast<std::size_t>(c)] = 1;
  std::vector<int> roots;
  for (int i = 0; i < n; ++i)
    if (!has_parent[static_cast<std::size_t>(i)]) roots.push_back(i);
  return roots;
}

Result<sim::Affine> Loader::local_transform(const tinygltf::Node& node, const std::string& what) {
  sim::Affine m;
  if (!node.matrix.empty()) {
    if (node.matrix.size() != 16)
      return fail(what + ": 'matrix' has " + std::to_string(node.matrix.size()) +
                  " numbers, expected 16");
    // Column-major, as glTF stores it: matrix[column * 4 + row].
    const std::vector<double>& a = node.matrix;
    if (!std::all_of(a.begin(), a.end(), [](double v) { return std::isfinite(v); }))
      return fail(what + ": 'matrix' is not finite");
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 3; ++col) m.m[row][col] = a[static_cast<std::size_t>(col * 4 + row)];
    m.offset = {a[12], a[13], a[14]};
    if (std::abs(a[3]) > 1e-9 || std::abs(a[7]) > 1e-9 || std::abs(a[11]) > 1e-9 ||
        std::abs(a[15] - 1.0) > 1e-9)
      return fail(what + ": 'matrix' is not affine (its last row must be 0 0 0 1)");
    if (!node.translation.empty() || !node.rotation.empty() || !node.scale.empty())
      note(Severity::Warning, "matrix-and-trs",
           what + " has both 'matrix' and TRS properties; 'matrix' is used");
    return m;
  }
  auto check = [&](const std::vector<double>& v, std::size_t size, const char* key) -> Status {
    if (v.empty()) return Ok{};
    if (v.size() != size)
      return fail(what + ": '" + key + "' has " + std::to_string(v.size()) +
                  " numbers, expected " + std::to_string(size));
    if (!std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); }))
      return fail(what + ": '" + key + "' is not finite");
    return Ok{};
  };
  if (Status s = check(node.translation, 3, "translation"); !s.ok()) return s.error();
  if (Status s = check(node.rotation, 4, "rotation"); !s.ok()) return s.error();
  if (Status s = check(node.scale, 3, "scale"); !s.ok()) return s.error();

  double qx = 0, qy = 0, qz = 0, qw = 1;
  if (!node.rotation.empty()) {
    qx = node.rotation[0];
    qy = node.rotation[1];
    qz = node.rotation[2];
    qw = node.rotation[3];
    const double len = std::sqrt(qx * qx + qy * qy + qz * qz + qw * qw);
    if (!(len > 1e-12)) return fail(what + ": 'rotation' is a zero quaternion");
    if (std::abs(len - 1.0) > 1e-3)
      note(Severity::Warning, "rotation-not-unit",
           what + ": 'rotation' quaternion has length " + format_number(len) + "; normalised");
    qx /= len;
    qy /= len;
    qz /= len;
    qw /= len;
  }
  const double r[3][3] = {
      {1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)},
      {2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)},
      {2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)}};
  const double s[3] = {node.scale.empty() ? 1.0 : node.scale[0],
                       node.scale.empty() ? 1.0 : node.scale[1],
                       node.scale.empty() ? 1.0 : node.scale[2]};
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col) m.m[row][col] = r[row][col] * s[col];
  if (!node.translation.empty())
    m.offset = {node.translation[0], node.translation[1], node.translation[2]};
  return m;
}

Result<std::pair<const unsigned char*, std::size_t>> Loader::view_bytes(
    int view, const std::string& what) const {
  if (view < 0 || static_cast<std::size_t>(view) >= model_.bufferViews.size())
    return fail(what + ": bufferView " + std::to_string(view) + " does not exist (" +
                std::to_string(model_.bufferViews.size()) + " bufferViews)");
  const auto& bv = model_.bufferViews[static_cast<std::size_t>(view)];
  if (bv.buffer < 0 || static_cast<std::size_t>(bv.buffer) >= model_.buffers.size())
    return fail(what + ": bufferView " + std::to_string(view) + " names buffer " +
                std::to_string(bv.buffer) + ", which does not exist");
  const auto& data = model_.buffers[static_cast<std::size_t>(bv.buffer)].data;
  if (!fits(bv.byteOffset, 1, 1, bv.byteLength, data.size()) && bv.byteLength > 0)
    return fail(what + ": bufferView " + std::to_string(view) + " (bytes " +
                std::to_string(bv.byteOffset) + " + " + std::to_string(bv.byteLength) +
                ") reaches past the end of buffer " + std::to_string(bv.buffer) + " (" +
                std::to_string(data.size()) + " bytes)");
  if (bv.byteOffset > data.size())
    return fail(what + ": bufferView " + std::to_string(view) + " starts past its buffer");
  return std::make_pair(data.data() + bv.byteOffset, static_cast<std::size_t>(bv.byteLength));
}

std::size_t component_size(int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_INT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
  }
}

std::uint32_t read_index(const unsigned char* p, int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return p[0];
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      std::uint16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    default: {
      std::uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
  }
}

// Copies accessor `a`'s elements (tightly packed, `elem` bytes each) into
// `out`, which holds a.count * elem bytes, applying sparse substitution.
Status Loader::read_elements(const tinygltf::Accessor& a, std::size_t elem,
                             const std::string& what, unsigned char* out) {
  Result<ElementSource> src = source(a, elem, what);
  if (!src.ok()) return src.error();
  if (src->data) {
    for (std::size_t i = 0; i < a.count; ++i)
      std::memcpy(out + i * elem, src->data + i * src->stride, elem);
  } else if (a.count > 0) {  // no elements: `out` may be null (a fuzz finding)
    std::memset(out, 0, a.count * elem);
  }
  if (!a.sparse.isSparse) return Ok{};

  const int n = a.sparse.count;
  if (n < 1 || static_cast<std::size_t>(n) > a.count)
    return fail(what + ": sparse count " + std::to_string(n) + " outside 1.." +
                std::to_string(a.count));
  const int itype = a.sparse.indices.componentType;
  if (itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
      itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
    return fail(what + ": sparse indices must be unsigned byte, short or int");
  const std::size_t isize = component_size(itype);
  auto ib = view_bytes(a.sparse.indices.bufferView, what + " sparse indices");
  if (!ib.ok()) return ib.error();
  auto vb = view_bytes(a.sparse.values.bufferView, what + " sparse values");
  if (!vb.ok()) return vb.error();
  const auto ioff = static_cast<std::size_t>(std::max(0, a.sparse.indices.byteOffset));
  const auto voff = static_cast<std::size_t>(std::max(0, a.sparse.values.byteOffset));
  const auto count = static_cast<std::size_t>(n);
  if (!fits(ioff, count, isize, isize, ib->second) || !fits(voff, count, elem, elem, vb->second))
    return fail(what + ": sparse indices or values reach past their bufferViews");
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint32_t target = read_index(ib->first + ioff + i * isize, itype);
    if (target >= a.count)
      return fail(what + ": sparse index " + std::to_string(target) + " out of range (" +
                  std::to_string(a.count) + " elements)");
    std::memcpy(out + target * elem, vb->first + voff + i * elem, elem);
  }
  return Ok{};
}

Result<ElementSource> Loader::source(const tinygltf::Accessor& a, std::size_t elem,
                                     const std::string& what) const {
  if (a.bufferView < 0) {
    // Not backed by data (zeros, perhaps with sparse values): bound the count.
    if (a.count > 3 * kMaxTriangles)
      return fail(what + ": count " + std::to_string(a.count) + " is absurd");
    return ElementSource{};
  }
  auto bytes = view_bytes(a.bufferView, what);
  if (!bytes.ok()) return bytes.error();
  const auto& bv = model_.bufferViews[static_cast<std::size_t>(a.bufferView)];
  const std::size_t stride = bv.byteStride ? bv.byteStride : elem;
  if (stride < elem)
    return fail(what + ": bufferView " + std::to_string(a.bufferView) + " has byteStride " +
                std::to_string(stride) + ", less than the element size " + std::to_string(elem));
  if (!fits(a.byteOffset, a.count, stride, elem, bytes->second))
    return fail(what + ": " + std::to_string(a.count) + " elements of " + std::to_string(elem) +
                " bytes (stride " + std::to_string(stride) + ", offset " +
                std::to_string(a.byteOffset) + ") do not fit in bufferView " +
                std::to_string(a.bufferView) + " (" + std::to_string(bytes->second) + " bytes)");
  return ElementSource{bytes->first + a.byteOffset, stride};
}

const char* type_name(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return "SCALAR";
    case TINYGLTF_TYPE_VEC2: return "VEC2";
    case TINYGLTF_TYPE_VEC3: return "VEC3";
    case TINYGLTF_TYPE_VEC4: return "VEC4";
    case TINYGLTF_TYPE_MAT2: return "MAT2";
    case TINYGLTF_TYPE_MAT3: return "MAT3";
    case TINYGLTF_TYPE_MAT4: return "MAT4";
    default: return "?";
  }
}

Result<FloatView> Loader::read_floats(int index, int type, const std::string& what_in) {
  const std::string what = what_in + " (accessor #" + std::to_string(index) + ")";
  if (index < 0 || static_cast<std::size_t>(index) >= model_.accessors.size())
    return fail(what_in + ": accessor " + std::to_string(index) + " does not exist (" +
                std::to_string(model_.accessors.size()) + " accessors)");
  const auto& a = model_.accessors[static_cast<std::size_t>(index)];
  if (a.type != type)
    return fail(what + " is " + type_name(a.type) + ", expected " + type_name(type));
  if (a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
    return fail(what + " has component type " + std::to_string(a.componentType) +
                "; Gonio reads float vertex data only (no KHR_mesh_quantization)");
  const std::size_t comps = static_cast<std::size_t>(tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(type)));
  const std::size_t elem = comps * 4;
  Result<ElementSource> src = source(a, elem, what);
  if (!src.ok()) return src.error();
  Result<FloatView> view = [&]() -> Result<FloatView> {
    if (src->data && !a.sparse.isSparse) return FloatView(*src, a.count);
    std::vector<float> out(a.count * comps);
    if (Status s = read_elements(a, elem, what, reinterpret_cast<unsigned char*>(out.data())); !s.ok())
      return s.error();
    return FloatView(std::move(out), comps);
  }();
  if (!view.ok()) return view.error();
  for (std::size_t i = 0; i < view->count(); ++i)
    for (std::size_t c = 0; c < comps; ++c)
      if (!std::isfinite(view->at(i, c)))
        return fail(what + ": element " + std::to_string(i) + " is not finite (" +
                    format_number(static_cast<double>(view->at(i, c))) + ")");
  return view;
}

Result<std::vector<std::uint32_t>> Loader::read_indices(int index, const std::string& what_in) {
  const std::string what = what_in + " (accessor #" + std::to_string(index) + ")";
  if (index < 0 || static_cast<std::size_t>(index) >= model_.accessors.size())
    return fail(what_in + ": accessor " + std::to_string(index) + " does not exist (" +
                std::to_string(model_.accessors.size()) + " accessors)");
  const auto& a = model_.accessors[static_cast<std::size_t>(index)];
  if (a.type != TINYGLTF_TYPE_SCALAR)
    return fail(what + " is " + type_name(a.type) + ", expected SCALAR");
  const int ct = a.componentType;
  if (ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
    return fail(what + ": indices must be unsigned byte, short or int, found component type " +
                std::to_string(ct));
  const std::size_t size = component_size(ct);
  Result<ElementSource> src = source(a, size, what);
  if (!src.ok()) return src.error();
  std::vector<std::uint32_t> out(a.count);
  if (src->data && !a.sparse.isSparse) {  // in place, as read_floats
    for (std::size_t i = 0; i < a.count; ++i) out[i] = read_index(src->data + i * src->stride, ct);
    return out;
  }
  std::vector<unsigned char> raw(a.count * size);
  if (Status s = read_elements(a, size, what, raw.data()); !s.ok()) return s.error();
  for (std::size_t i = 0; i < a.count; ++i) out[i] = read_index(raw.data() + i * size, ct);
  return out;
}

Result<std::uint32_t> Loader::material(int index) {
  if (auto it = materials_.find(index); it != materials_.end()) return it->second;
  GltfMaterial m;
  MaterialExtras x;
  sim::EmitterSpectrum emitted_spectrum;
  std::shared_ptr<const sim::TabulatedBsdf> table;
  std::string what = "default material";
  if (index >= 0) {
    if (static_cast<std::size_t>(index) >= model_.materials.size())
      return fail("material " + std::to_string(index) + " does not exist (" +
                  std::to_string(model_.materials.size()) + " materials)");
    const auto& g = model_.materials[static_cast<std::size_t>(index)];
    what = g.name.empty() ? "material #" + std::to_string(index)
                          : "material '" + g.name + "' (#" + std::to_string(index) + ")";
    m.name = g.name.empty() ? "material-" + std::to_string(index) : g.name;
    const auto& pbr = g.pbrMetallicRoughness;
    if (pbr.baseColorFactor.size() != 4)
      return fail(what + ": baseColorFactor must have 4 numbers");
    m.base_color = {pbr.baseColorFactor[0], pbr.baseColorFactor[1], pbr.baseColorFactor[2]};
    m.metallic = pbr.metallicFactor;
    m.roughness = pbr.roughnessFactor;
    if (g.emissiveFactor.size() != 3) return fail(what + ": emissiveFactor must have 3 numbers");
    m.emissive = {g.emissiveFactor[0], g.emissiveFactor[1], g.emissiveFactor[2]};
    m.double_sided = g.doubleSided;
    bool textured = pbr.baseColorTexture.index >= 0 || pbr.metallicRoughnessTexture.index >= 0 ||
                    g.emissiveTexture.index >= 0;

    Result<json> ext = parse_blob(g.extensions_json_string, what + " extensions");
    if (!ext.ok()) return ext.error();
    if (ext->is_object()) {
      for (const auto& item : ext->items()) {
        const std::string& name = item.key();
        const json& e = item.value();  // not a structured binding: clang 14 cannot capture one
        const std::string ew = what + " " + name;
        if (e.is_object())
          for (const auto& [key, value] : e.items())
            if (key.size() > 7 && key.compare(key.size() - 7, 7, "Texture") == 0) textured = true;
        auto get = [&](const char* key, double& target) -> Status {
          Result<std::optional<double>> v = number(e, key, ew);
          if (!v.ok()) return v.error();
          if (*v) target = **v;
          return Ok{};
        };
        auto get_rgb = [&](const char* key, Rgb& target) -> Status {
          Result<std::optional<Rgb>> v = rgb(e, key, ew);
          if (!v.ok()) return v.error();
          if (*v) target = **v;
          return Ok{};
        };
        Status s = Ok{};
        if (name == "KHR_materials_emissive_strength") {
          s = get("emissiveStrength", m.emissive_strength);
        } else if (name == "KHR_materials_transmission") {
          s = get("transmissionFactor", m.transmission);
        } else if (name == "KHR_materials_ior") {
          s = get("ior", m.ior);
        } else if (name == "KHR_materials_specular") {
          s = get("specularFactor", m.specular);
          if (s.ok()) s = get_rgb("specularColorFactor", m.specular_color);
        } else if (name == "KHR_materials_diffuse_transmission") {
          s = get("diffuseTransmissionFactor", m.diffuse_transmission);
          if (s.ok()) s = get_rgb("diffuseTransmissionColorFactor", m.diffuse_transmission_color);
        } else if (name == "KHR_materials_volume") {
          m.has_volume = true;
          s = get("thicknessFactor", m.thickness_m);
          if (s.ok()) s = get("attenuationDistance", m.attenuation_distance_m);
          if (s.ok()) s = get_rgb("attenuationColor", m.attenuation_color);
        } else {
          note(Severity::Warning, "unsupported-material-extension",
               what + ": " + name + " is not part of Gonio's material model; ignored");
        }
        if (!s.ok()) return s.error();
      }
    }
    if (m.emissive_strength < 0.0) {
      note(Severity::Warning, "material-factor-range",
           what + ": emissiveStrength " + format_number(m.emissive_strength) + " < 0, using 0");
      m.emissive_strength = 0.0;
    }
    if (textured)
      note(Severity::Info, "textures-ignored",
           what + ": textures are not read; the material's constant factors are used");
    if (g.alphaMode == "BLEND" || (g.alphaMode == "MASK" && pbr.baseColorFactor[3] < g.alphaCutoff))
      note(Severity::Info, "alpha-ignored",
           what + ": alphaMode " + g.alphaMode + " is ignored (the surface is opaque)");

    Result<json> extras = parse_blob(g.extras_json_string, what + " extras");
    if (!extras.ok()) return extras.error();
    if (extras->is_object() && extras->contains("gonio")) {
      Result<MaterialExtras> read = read_material_extras(extras->at("gonio"), {path_}, what, findings_);
      if (!read.ok()) return read.error();
      x = std::move(*read);
      emitted_spectrum = x.spectrum;
    }
    if (x.bsdf_file) {
      // Beside the model, like its buffers and light profiles.
      if (!options_.allow_outside_paths)
        if (const std::optional<std::string> why = outside_the_folder(base_dir_, *x.bsdf_file))
          return fail(outside_message(what + " extras.gonio.bsdf_file '" + *x.bsdf_file + "'", *why));
      const std::string bsdf_path = (std::filesystem::path(base_dir_) / *x.bsdf_file).string();
      Result<std::shared_ptr<const sim::TabulatedBsdf>> t = read_bsdf_file(bsdf_path, findings_);
      if (!t.ok()) return Error{t.error().where, what + ": extras.gonio.bsdf_file: " + t.error().message};
      table = std::move(*t);
    }
  } else {
    m.name = "default";
    note(Severity::Warning, "default-material",
         "a primitive has no material: glTF's default (white, rough, metallic; reflectance 1) "
         "is used");
  }

  Result<sim::Material> mapped = map_material(m, x, {path_}, what, findings_, std::move(table));
  if (!mapped.ok()) return mapped.error();
  const auto id = static_cast<std::uint32_t>(scene_.materials.size());
  scene_.materials.push_back(std::move(*mapped));
  materials_[index] = id;
  emission_.push_back({emissive_luminance_cd_m2(m, x), m.double_sided, std::move(emitted_spectrum)});
  base_colours_.push_back(m.base_color);
  return id;
}

// The primitive's triangles as a scene mesh in the frame `world` takes
// its vertices to (the world, or the glTF mesh's own frame for instancing);
// nullopt when it has none. Name left empty.
Result<std::optional<sim::Mesh>> Loader::primitive_mesh(const tinygltf::Primitive& prim,
                                                        const std::string& what,
                                                        const sim::Affine& world) {

  switch (prim.mode) {
    case TINYGLTF_MODE_POINTS:
    case TINYGLTF_MODE_LINE:
    case TINYGLTF_MODE_LINE_LOOP:
    case TINYGLTF_MODE_LINE_STRIP:
      return fail(what + ": mode " + std::to_string(prim.mode) + " (" +
                  (prim.mode == TINYGLTF_MODE_POINTS ? "points" : "lines") +
                  ") has no surface; only triangles can be simulated");
    case TINYGLTF_MODE_TRIANGLES:
    case TINYGLTF_MODE_TRIANGLE_STRIP:
    case TINYGLTF_MODE_TRIANGLE_FAN: break;
    default: return fail(what + ": unknown primitive mode " + std::to_string(prim.mode));
  }

  auto pos_it = prim.attributes.find("POSITION");
  if (pos_it == prim.attributes.end()) return fail(what + ": no POSITION attribute");
  Result<FloatView> positions = read_floats(pos_it->second, TINYGLTF_TYPE_VEC3, what + " POSITION");
  if (!positions.ok()) return positions.error();
  const std::size_t vertex_count = positions->count();

  std::vector<std::uint32_t> index;
  if (prim.indices >= 0) {
    Result<std::vector<std::uint32_t>> read = read_indices(prim.indices, what + " indices");
    if (!read.ok()) return read.error();
    index = std::move(*read);
    for (std::size_t i = 0; i < index.size(); ++i)
      if (index[i] >= vertex_count)
        return fail(what + ": index " + std::to_string(index[i]) + " (entry " + std::to_string(i) +
                    ") out of range: the primitive has " + std::to_string(vertex_count) +
                    " vertices");
  } else {
    index.resize(vertex_count);
    for (std::size_t i = 0; i < vertex_count; ++i) index[i] = static_cast<std::uint32_t>(i);
  }

  std::vector<std::uint32_t> tri;
  if (prim.mode == TINYGLTF_MODE_TRIANGLES) {
    if (index.size() % 3 != 0)
      return fail(what + ": " + std::to_string(index.size()) +
                  " vertex indices do not make whole triangles");
    tri = std::move(index);
  } else if (index.size() >= 3) {
    // glTF's orders: strip triangle i = (v[i], v[i+1+i%2], v[i+2-i%2]),
    // fan triangle i = (v[i+1], v[i+2], v[0]). Triangles with a repeated
    // vertex are how strips are stitched; they cover nothing and are dropped.
    tri.reserve(3 * (index.size() - 2));
    for (std::size_t i = 0; i + 2 < index.size(); ++i) {
      std::uint32_t a, b, c;
      if (prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        a = index[i];
        b = index[i + 1 + i % 2];
        c = index[i + 2 - i % 2];
      } else {
        a = index[i + 1];
        b = index[i + 2];
        c = index[0];
      }
      if (a == b || b == c || a == c) continue;
      tri.insert(tri.end(), {a, b, c});
    }
  }
  if (tri.empty()) {
    note(Severity::Warning, "empty-primitive", what + " has no triangles");
    return std::optional<sim::Mesh>();
  }
  triangles_ += tri.size() / 3;
  if (triangles_ > kMaxTriangles)
    return fail(what + ": the model has more than " + std::to_string(kMaxTriangles) +
                " triangles, more than Gonio loads");

  sim::Mesh mesh;

  const double det = world.determinant();
  const bool singular = !(std::abs(det) > 1e-300);
  if (singular)
    note(Severity::Warning, "singular-transform",
         what + ": the node's transform is singular; the primitive is flat or a point");
  // Keep only the vertices the triangles use, in order of first use: many
  // primitives may share one large vertex accessor.
  std::vector<std::uint32_t> remap(vertex_count, UINT32_MAX);
  std::vector<std::uint32_t> used;
  for (std::uint32_t& i : tri) {
    if (remap[i] == UINT32_MAX) {
      remap[i] = static_cast<std::uint32_t>(used.size());
      used.push_back(i);
    }
    i = remap[i];
  }
  mesh.positions.resize(used.size());
  for (std::size_t k = 0; k < used.size(); ++k) {
    const std::size_t v = used[k];
    const Vec3 p =
        world.point(widen(positions->at(v, 0), positions->at(v, 1), positions->at(v, 2)));
    const sim::Vec3f f = sim::to_float(p);
    if (!(std::isfinite(f.x) && std::isfinite(f.y) && std::isfinite(f.z)))
      return fail(what + ": vertex " + std::to_string(v) + " is not finite in world space");
    mesh.positions[k] = f;
  }
  if (det < 0.0)
    for (std::size_t k = 0; k < tri.size(); k += 3) std::swap(tri[k + 1], tri[k + 2]);
  mesh.indices = std::move(tri);

  if (auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) {
    Result<FloatView> normals = read_floats(it->second, TINYGLTF_TYPE_VEC3, what + " NORMAL");
    if (!normals.ok()) return normals.error();
    if (normals->count() != vertex_count)
      return fail(what + ": NORMAL has " + std::to_string(normals->count()) +
                  " elements, POSITION " + std::to_string(vertex_count));
    bool usable = !singular;
    if (usable) {
      mesh.normals.resize(used.size());
      for (std::size_t k = 0; k < used.size() && usable; ++k) {
        const std::size_t v = used[k];
        const Vec3 n =
            world.normal(widen(normals->at(v, 0), normals->at(v, 1), normals->at(v, 2)));
        const double len = length(n);
        if (!(len > 0.0) || !std::isfinite(len)) {
          usable = false;
          note(Severity::Warning, "bad-normals",
               what + ": normal " + std::to_string(v) + " has zero length; normals dropped");
          break;
        }
        mesh.normals[k] = {static_cast<float>(n.x / len), static_cast<float>(n.y / len),
                           static_cast<float>(n.z / len)};
      }
    }
    if (!usable) mesh.normals.clear();
  }
  if (auto it = prim.attributes.find("TANGENT"); it != prim.attributes.end()) {
    Result<FloatView> tangents = read_floats(it->second, TINYGLTF_TYPE_VEC4, what + " TANGENT");
    if (!tangents.ok()) return tangents.error();
    if (tangents->count() != vertex_count)
      return fail(what + ": TANGENT has " + std::to_string(tangents->count()) +
                  " elements, POSITION " + std::to_string(vertex_count));
    mesh.tangents.resize(used.size());
    for (std::size_t k = 0; k < used.size(); ++k) {
      const std::size_t v = used[k];
      const Vec3 t =
          world.linear(widen(tangents->at(v, 0), tangents->at(v, 1), tangents->at(v, 2)));
      const double len = length(t);
      if (!(len > 0.0) || !std::isfinite(len)) {
        note(Severity::Warning, "bad-tangents",
             what + ": tangent " + std::to_string(v) + " has zero length; tangents dropped");
        mesh.tangents.clear();
        break;
      }
      mesh.tangents[k] = {static_cast<float>(t.x / len), static_cast<float>(t.y / len),
                          static_cast<float>(t.z / len)};
    }
  }
  if (!prim.targets.empty())
    note(Severity::Info, "morph-targets-ignored",
         what + ": morph targets are ignored; the base shape is used");

  Result<std::uint32_t> mat = material(prim.material);
  if (!mat.ok()) return mat.error();
  mesh.material = *mat;

  return std::optional<sim::Mesh>(std::move(mesh));
}

void Loader::add_area_emitter(std::uint32_t mesh_id, std::uint32_t instance, const sim::Mesh& world_mesh,
                              const std::string& name, const std::string& what,
                              std::vector<std::size_t>& area_emitters) {
  const Emission emission = emission_[world_mesh.material];
  if (!(emission.luminance_cd_m2 > 0.0)) return;
  double area = 0.0;
  for (std::size_t k = 0; k < world_mesh.indices.size(); k += 3) {
    auto p = [&](std::size_t j) {
      const sim::Vec3f& f = world_mesh.positions[world_mesh.indices[k + j]];
      return widen(f.x, f.y, f.z);
    };
    area += 0.5 * length(cross(p(1) - p(0), p(2) - p(0)));
  }
  if (!(area > 0.0)) {
    note(Severity::Warning, "emitter-without-area",
         what + ": emissive primitive has zero area and emits nothing");
    return;
  }
  sim::Emitter e;
  e.kind = sim::Emitter::Kind::Area;
  e.name = name;
  e.mesh = mesh_id;
  e.instance = instance;
  e.two_sided = emission.two_sided;
  e.spectrum = emission.spectrum;
  e.flux_lm = kPi * emission.luminance_cd_m2 * area * (e.two_sided ? 2.0 : 1.0);
  area_emitters.push_back(scene_.emitters.size());
  scene_.emitters.push_back(std::move(e));
}

Status Loader::add_primitive(const tinygltf::Node& node, int node_index, int mesh_index,
                             int prim_index, const sim::Affine& world,
                             std::vector<std::size_t>& area_emitters,
                             const std::vector<Copy>* copies) {
  const auto& gm = model_.meshes[static_cast<std::size_t>(mesh_index)];
  const auto& prim = gm.primitives[static_cast<std::size_t>(prim_index)];
  const std::string mesh_what = gm.name.empty()
                                    ? "mesh #" + std::to_string(mesh_index)
                                    : "mesh '" + gm.name + "' (#" + std::to_string(mesh_index) + ")";
  const std::string what =
      node_what(node_index) + ", " + mesh_what + ", primitive " + std::to_string(prim_index);
  const std::string mesh_name =
      (gm.name.empty() ? "mesh-" + std::to_string(mesh_index) : gm.name) + "/" + std::to_string(prim_index);

  if (!copies) {
    // Placed once: world geometry.
    Result<std::optional<sim::Mesh>> mesh = primitive_mesh(prim, what, world);
    if (!mesh.ok()) return mesh.error();
    if (!*mesh) return Ok{};
    sim::Mesh& m = **mesh;
    m.name = (node.name.empty() ? "node-" + std::to_string(node_index) : node.name) + "/" + mesh_name;
    const auto mesh_id = static_cast<std::uint32_t>(scene_.meshes.size());
    add_area_emitter(mesh_id, sim::kNoInstance, m, m.name, what, area_emitters);
    scene_.meshes.push_back(std::move(m));
    return Ok{};
  }

  // Placed several times: the primitive is read once, in the glTF mesh's
  // own frame (times the model's unit), and each copy is an instance.
  const auto key = std::make_pair(mesh_index, prim_index);
  auto it = prototypes_.find(key);
  if (it == prototypes_.end()) {
    Result<std::optional<sim::Mesh>> mesh = primitive_mesh(prim, mesh_what + ", primitive " + std::to_string(prim_index), sim::Affine{});
    if (!mesh.ok()) return mesh.error();
    std::optional<std::uint32_t> id;
    if (*mesh) {
      (*mesh)->name = mesh_name;
      (*mesh)->instanced = true;
      id = static_cast<std::uint32_t>(scene_.meshes.size());
      scene_.meshes.push_back(std::move(**mesh));
    }
    it = prototypes_.emplace(key, id).first;
  }
  if (!it->second) return Ok{};
  const std::uint32_t proto = *it->second;
  for (const Copy& c : *copies) {
    const double det = c.world.determinant();
    if (!(std::abs(det) > 1e-300)) {
      note(Severity::Warning, "singular-transform",
           what + " (" + c.name + "): the transform is singular; this copy is flat and left out");
      continue;
    }
    if (scene_.instances.size() >= kMaxInstances)
      return fail(what + ": the model places meshes more than " + std::to_string(kMaxInstances) +
                  " times, more than Gonio loads");
    const auto instance = static_cast<std::uint32_t>(scene_.instances.size());
    scene_.instances.push_back({proto, c.world, c.name});
    if (emission_[scene_.meshes[proto].material].luminance_cd_m2 > 0.0) {
      sim::Mesh copy = scene_.meshes[proto];
      sim::transform(copy, c.world);
      add_area_emitter(proto, instance, copy, c.name + "/" + mesh_name, what, area_emitters);
    }
  }
  return Ok{};
}

// Position and frame of a light on a node; a transform that collapses the
// node's axes is an error (the light would have no direction).
struct LightPlacement {
  Vec3 position;
  photometry::PhotometricFrame frame;
  bool mirrored;
};

std::optional<LightPlacement> place_light(const sim::Affine& world) {
  const Vec3 x = world.linear({1, 0, 0});
  const Vec3 z = world.linear({0, 0, 1});
  const double lx = length(x), lz = length(z);
  if (!(lx > 0.0) || !(lz > 0.0)) return std::nullopt;
  const Vec3 zn = z / lz;
  if (!(length(x - dot(x, zn) * zn) > 1e-9 * lx)) return std::nullopt;
  return LightPlacement{world.offset, light_frame(x, z), world.determinant() < 0.0};
}

Status Loader::add_khr_light(const json& ext, const sim::Affine& world,
                             const std::string& node_what, std::optional<double> node_flux,
                             std::vector<std::size_t>& emitters) {
  auto li = ext.is_object() ? ext.find("light") : ext.end();
  if (!ext.is_object() || li == ext.end() || !li->is_number_integer())
    return fail(node_what + ": KHR_lights_punctual needs an integer 'light'");
  const auto idx = li->get<std::int64_t>();
  if (idx < 0 || static_cast<std::size_t>(idx) >= khr_lights_.size())
    return fail(node_what + ": KHR_lights_punctual light " + std::to_string(idx) +
                " does not exist (" + std::to_string(khr_lights_.size()) + " lights)");
  const json& l = khr_lights_[static_cast<std::size_t>(idx)];
  std::string name;
  if (l.is_object())
    if (auto n = l.find("name"); n != l.end() && n->is_string()) name = n->get<std::string>();
  const std::string what = "KHR_lights_punctual light " +
                           (name.empty() ? "#" + std::to_string(idx)
                                         : "'" + name + "' (#" + std::to_string(idx) + ")") +
                           " on " + node_what;
  if (!l.is_object()) return fail(what + " is not an object");
  auto t = l.find("type");
  if (t == l.end() || !t->is_string()) return fail(what + ": 'type' is missing");
  const std::string type = t->get<std::string>();

  Result<std::optional<double>> intensity = number(l, "intensity", what);
  if (!intensity.ok()) return intensity.error();
  const double I = intensity->value_or(1.0);
  if (I < 0.0) return fail(what + ": intensity " + format_number(I) + " is negative");
  Result<std::optional<Rgb>> color = rgb(l, "color", what);
  if (!color.ok()) return color.error();
  if (*color && ((*color)->r != 1.0 || (*color)->g != 1.0 || (*color)->b != 1.0))
    note(Severity::Info, "light-color-ignored",
         what + ": 'color' is ignored; photometry is luminous (candela, lumens)");
  if (l.contains("range"))
    note(Severity::Info, "light-range-ignored",
         what + ": 'range' is ignored; the far field is the infinite-distance limit");

  if (type == "directional") {
    note(Severity::Warning, "directional-light-ignored",
         what + ": a directional light is not part of a luminaire; ignored");
    return Ok{};
  }
  if (type != "point" && type != "spot")
    return fail(what + ": unknown light type '" + type + "'");

  const std::optional<LightPlacement> place = place_light(world);
  if (!place) return fail(what + ": the node's transform collapses its axes");

  sim::Emitter e;
  e.kind = sim::Emitter::Kind::Point;
  e.name = name.empty() ? node_what : name;
  e.position = place->position;
  e.frame = place->frame;
  if (type == "point") {
    e.flux_lm = isotropic_flux_lm(I);
  } else {
    double inner = 0.0, outer = kPi / 4.0;
    if (auto s = l.find("spot"); s != l.end()) {
      if (!s->is_object()) return fail(what + ": 'spot' must be an object");
      Result<std::optional<double>> in = number(*s, "innerConeAngle", what);
      if (!in.ok()) return in.error();
      Result<std::optional<double>> out = number(*s, "outerConeAngle", what);
      if (!out.ok()) return out.error();
      inner = in->value_or(inner);
      outer = out->value_or(outer);
    }
    if (!(outer > 0.0 && outer <= kPi / 2.0 + 1e-9))
      return fail(what + ": outerConeAngle " + format_number(outer) + " rad must lie in (0, pi/2]");
    outer = std::min(outer, kPi / 2.0);
    if (inner < 0.0) return fail(what + ": innerConeAngle " + format_number(inner) + " rad is negative");
    if (inner >= outer)
      note(Severity::Warning, "spot-cone",
           what + ": innerConeAngle >= outerConeAngle; the cone has a hard edge at the outer angle");
    e.profile = std::make_shared<const photometry::Distribution>(
        khr_spot_distribution(I, inner, outer));
    e.flux_lm = khr_spot_flux_lm(I, inner, outer);
  }

  Result<json> extras = parse_blob(l.contains("extras") ? l.at("extras").dump() : std::string(), what);
  if (!extras.ok()) return extras.error();
  Result<const json*> gx = gonio_extras(*extras, what, {"flux_lm", "spectrum"});
  if (!gx.ok()) return gx.error();
  if (*gx) {
    Result<std::optional<double>> f = number(**gx, "flux_lm", what + " extras.gonio");
    if (!f.ok()) return f.error();
    if (*f) {
      if (**f < 0.0) return fail(what + ": extras.gonio.flux_lm is negative");
      e.flux_lm = **f;
    }
    Result<sim::EmitterSpectrum> es = emitter_spectrum(**gx, what);
    if (!es.ok()) return es.error();
    e.spectrum = std::move(*es);
  }
  if (node_flux) e.flux_lm = *node_flux;
  emitters.push_back(scene_.emitters.size());
  scene_.emitters.push_back(std::move(e));
  return Ok{};
}

// extras.gonio.ray_file: an IES TM-25 ray set placed by the node. Its
// positions are millimetres: p_model = p_mm · 10⁻³ / unit_m, then the node's
// world transform (which includes unit_m) makes metres; directions are the
// node's linear map of the file's, normalised. Flux: the node's flux_lm, else
// the rays' luminous flux.
Status Loader::add_ray_set(const std::string& u, const sim::Affine& world, const std::string& node_what,
                           std::optional<double> node_flux, std::vector<std::size_t>& emitters) {
  const std::string what = node_what + ": extras.gonio.ray_file '" + u + "'";
  if (u.rfind("data:", 0) == 0 || u.find("://") != std::string::npos)
    return fail(what + " is not a relative file reference");
  const std::string relative = percent_decode(u);
  if (!options_.allow_outside_paths)
    if (std::optional<std::string> why = outside_the_folder(base_dir_, relative))
      return fail(outside_message(what, *why));
  const fs::path file = fs::path(base_dir_) / relative;
  Result<Tm25RaySet> set = read_tm25_file(file.string());
  if (!set.ok()) return fail(what + ": " + to_string(set.error()));
  for (const Finding& f : set->findings) findings_.push_back(f);
  if (!node_flux && !set->has_luminous_flux())
    return fail(what + ": the rays carry radiant flux only and the file does not state both total fluxes; "
                       "give the node extras.gonio.flux_lm");
  auto rays = std::make_shared<sim::RaySet>();
  const std::size_t n = set->ray_count();
  rays->position_m.reserve(n);
  rays->direction.reserve(n);
  rays->flux_lm.reserve(n);
  const double mm = 1e-3 / unit_m_;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 d = world.linear(set->direction(i));
    const double len = length(d);
    if (!(len > 0.0)) return fail(what + ": the node's transform collapses the rays' directions");
    rays->position_m.push_back(sim::to_float(world.point(set->position_mm(i) * mm)));
    rays->direction.push_back(sim::to_float(d / len));
    rays->flux_lm.push_back(static_cast<float>(set->has_luminous_flux() ? set->luminous_flux_lm(i)
                                                                        : set->radiant_flux_w(i)));
  }
  sim::Emitter e;
  e.kind = sim::Emitter::Kind::RaySet;
  e.name = node_what + " (" + fs::path(relative).filename().string() + ")";
  e.position = world.offset;
  e.flux_lm = node_flux ? *node_flux : set->total_luminous_flux_lm();
  e.rays = std::move(rays);
  emitters.push_back(scene_.emitters.size());
  scene_.emitters.push_back(std::move(e));
  return Ok{};
}

Status Loader::load_ies_profile(IesLight& light) {
  if (light.profile) return Ok{};
  const json& def = light.def;
  if (!def.is_object()) return fail(light.what + " is not an object");
  std::string bytes, name, dir = base_dir_;
  bool eulumdat = false;
  auto uri = def.find("uri");
  auto view = def.find("bufferView");
  if (uri != def.end() && view != def.end())
    return fail(light.what + ": has both 'uri' and 'bufferView'");
  if (uri != def.end()) {
    if (!uri->is_string()) return fail(light.what + ": 'uri' must be a string");
    const std::string u = uri->get<std::string>();
    if (u.rfind("data:", 0) == 0) {
      const std::size_t comma = u.find(',');
      if (comma == std::string::npos) return fail(light.what + ": malformed data URI");
      const std::string header = lower(u.substr(5, comma - 5));
      const bool b64 = header.size() >= 7 && header.compare(header.size() - 7, 7, ";base64") == 0;
      const std::string mime = b64 ? header.substr(0, header.size() - 7) : header;
      eulumdat = mime == "application/x-eulumdat";
      if (b64) {
        std::optional<std::string> decoded = base64_decode(std::string_view(u).substr(comma + 1));
        if (!decoded) return fail(light.what + ": the data URI is not valid base64");
        bytes = std::move(*decoded);
      } else {
        bytes = percent_decode(std::string_view(u).substr(comma + 1));
      }
      name = path_ + " (" + light.what + " data URI)";
    } else {
      if (u.find("://") != std::string::npos)
        return fail(light.what + ": uri '" + u + "' is not a relative file reference or data URI");
      const std::string relative = percent_decode(u);
      if (!options_.allow_outside_paths) {
        if (std::optional<std::string> why = outside_the_folder(base_dir_, relative))
          return fail(outside_message(light.what + ": light profile uri '" + u + "'", *why));
      }
      const fs::path file = fs::path(base_dir_) / relative;
      name = file.string();
      dir = file.parent_path().string();
      eulumdat = lower(file.extension().string()) == ".ldt";
      Result<std::string> read = read_file(name, kMaxFileBytes);
      if (!read.ok())
        return fail(light.what + ": light profile '" + u + "': " + to_string(read.error()));
      bytes = std::move(*read);
    }
  } else if (view != def.end()) {
    if (!view->is_number_integer()) return fail(light.what + ": 'bufferView' must be an integer");
    std::string mime;
    if (auto m = def.find("mimeType"); m != def.end() && m->is_string()) mime = m->get<std::string>();
    if (mime == "application/x-eulumdat") {
      eulumdat = true;
    } else if (mime != "application/x-ies-lm-63") {
      if (!mime.empty())
        return fail(light.what + ": mimeType '" + mime +
                    "' is neither application/x-ies-lm-63 nor application/x-eulumdat");
      note(Severity::Warning, "profile-mime-type",
           light.what + ": 'mimeType' is missing; the profile is read as IES LM-63");
    }
    Result<std::pair<const unsigned char*, std::size_t>> b =
        view_bytes(static_cast<int>(std::clamp<std::int64_t>(view->get<std::int64_t>(), -1, 1 << 30)),
                   light.what);
    if (!b.ok()) return b.error();
    bytes.assign(reinterpret_cast<const char*>(b->first), b->second);
    name = path_ + " (" + light.what + " bufferView)";
  } else {
    return fail(light.what + ": needs a 'uri' or a 'bufferView'");
  }
  // An IES profile's TILT=<file> is a path from the model as well.
  if (!eulumdat && !options_.allow_outside_paths) {
    if (std::optional<std::string> tilt = tilt_file_of(bytes)) {
      const fs::path file = (fs::path(dir) / *tilt).lexically_normal();
      const std::string relative = file.lexically_relative(fs::path(base_dir_)).string();
      const std::optional<std::string> why =
          fs::path(*tilt).is_absolute() ? std::optional<std::string>("is an absolute path")
                                        : outside_the_folder(base_dir_, relative);
      if (why) return fail(outside_message(light.what + ": the profile's TILT file '" + *tilt + "'", *why));
    }
  }
  Result<photometry::Distribution> d = parse_profile(bytes, name, dir, eulumdat, findings_);
  if (!d.ok()) return fail(light.what + ": " + to_string(d.error()));
  if (d->tilt.kind != photometry::Tilt::Kind::None)
    note(Severity::Info, "tilt-ignored",
         light.what + ": the profile's TILT data is not applied (EXT_lights_ies does not "
                      "require it); the profile is used as measured");
  light.profile = std::make_shared<const photometry::Distribution>(std::move(*d));
  return Ok{};
}

Status Loader::add_ies_light(const json& ext, const sim::Affine& world,
                             const std::string& node_what, std::optional<double> node_flux,
                             std::vector<std::size_t>& emitters) {
  auto li = ext.is_object() ? ext.find("light") : ext.end();
  if (!ext.is_object() || li == ext.end() || !li->is_number_integer())
    return fail(node_what + ": EXT_lights_ies needs an integer 'light'");
  const auto idx = li->get<std::int64_t>();
  if (idx < 0 || static_cast<std::size_t>(idx) >= ies_lights_.size())
    return fail(node_what + ": EXT_lights_ies light " + std::to_string(idx) + " does not exist (" +
                std::to_string(ies_lights_.size()) + " lights)");
  IesLight& light = ies_lights_[static_cast<std::size_t>(idx)];
  const std::string what = light.what + " on " + node_what;

  Result<std::optional<double>> mult = number(ext, "multiplier", what);
  if (!mult.ok()) return mult.error();
  const double multiplier = mult->value_or(1.0);
  if (multiplier < 0.0) return fail(what + ": multiplier " + format_number(multiplier) + " is negative");
  Result<std::optional<Rgb>> color = rgb(ext, "color", what);
  if (!color.ok()) return color.error();
  if (*color && ((*color)->r != 1.0 || (*color)->g != 1.0 || (*color)->b != 1.0))
    note(Severity::Info, "light-color-ignored",
         what + ": 'color' is ignored; photometry is luminous (candela, lumens)");

  const std::optional<LightPlacement> place = place_light(world);
  if (!place) return fail(what + ": the node's transform collapses its axes");
  if (place->mirrored)
    note(Severity::Warning, "mirrored-light",
         what + ": the node's transform mirrors; the profile is placed by rotation and is "
                "not mirrored");

  if (Status s = load_ies_profile(light); !s.ok()) return s;
  if (light.profile->type == photometry::PhotometricType::A)
    note(Severity::Warning, "type-a-profile",
         what + ": a Type A profile; EXT_lights_ies leaves Type A optional and Gonio places it "
                "with its own Type A frame about the node's axes (photometric zero at the node's "
                "-Z, horizontal (0°, 0°) at +X), which other viewers may not share");

  sim::Emitter e;
  e.kind = sim::Emitter::Kind::Point;
  e.name = node_what;
  if (light.def.is_object())
    if (auto n = light.def.find("name"); n != light.def.end() && n->is_string() &&
                                         !n->get<std::string>().empty())
      e.name = n->get<std::string>();
  e.position = place->position;
  e.frame = place->frame;
  e.profile = light.profile;
  {
    Result<json> extras = parse_blob(
        light.def.contains("extras") ? light.def.at("extras").dump() : std::string(), light.what);
    if (!extras.ok()) return extras.error();
    if (extras->is_object() && extras->contains("gonio") && extras->at("gonio").is_object()) {
      Result<sim::EmitterSpectrum> es = emitter_spectrum(extras->at("gonio"), light.what);
      if (!es.ok()) return es.error();
      e.spectrum = std::move(*es);
    }
  }

  if (node_flux) {
    e.flux_lm = *node_flux;
  } else {
    std::optional<double> profile_flux;
    Result<json> extras = parse_blob(
        light.def.contains("extras") ? light.def.at("extras").dump() : std::string(), light.what);
    if (!extras.ok()) return extras.error();
    Result<const json*> gx = gonio_extras(*extras, light.what, {"flux_lm", "spectrum"});
    if (!gx.ok()) return gx.error();
    if (*gx) {
      Result<std::optional<double>> f = number(**gx, "flux_lm", light.what + " extras.gonio");
      if (!f.ok()) return f.error();
      if (*f && **f < 0.0) return fail(light.what + ": extras.gonio.flux_lm is negative");
      profile_flux = *f;
    }
    if (!profile_flux) {
      if (!light.flux_lm) {
        Result<double> f = profile_flux_lm(*light.profile, light.what);
        if (!f.ok()) return fail(light.what + ": " + f.error().message);
        light.flux_lm = *f;
      }
      profile_flux = light.flux_lm;
    }
    e.flux_lm = *profile_flux * multiplier;
  }
  emitters.push_back(scene_.emitters.size());
  scene_.emitters.push_back(std::move(e));
  return Ok{};
}

// How often each mesh is placed by the scene's nodes (an
// EXT_mesh_gpu_instancing node places it once per copy). Nodes reached twice
// are left to the main walk, which names the cycle.
void Loader::count_mesh_uses(const std::vector<int>& roots) {
  mesh_uses_.assign(model_.meshes.size(), 0);
  std::vector<char> seen(model_.nodes.size(), 0);
  std::vector<int> stack(roots.rbegin(), roots.rend());
  while (!stack.empty()) {
    const int i = stack.back();
    stack.pop_back();
    if (seen[static_cast<std::size_t>(i)]) continue;
    seen[static_cast<std::size_t>(i)] = 1;
    const auto& node = model_.nodes[static_cast<std::size_t>(i)];
    if (node.mesh >= 0 && static_cast<std::size_t>(node.mesh) < mesh_uses_.size())
      mesh_uses_[static_cast<std::size_t>(node.mesh)] += 1;
    for (int c : node.children) stack.push_back(c);
  }
  if (!options_.instancing) std::fill(mesh_uses_.begin(), mesh_uses_.end(), std::size_t{1});
}

// The copies of an EXT_mesh_gpu_instancing node: world × T·R·S of each,
// from the TRANSLATION, ROTATION (unit quaternion) and SCALE accessors
// (float; any of them may be absent, the others' counts must agree).
Result<std::vector<Copy>> Loader::gpu_instances(const json& ext, const sim::Affine& world,
                                                const std::string& node_name, const std::string& what) {
  const std::string ew = what + " EXT_mesh_gpu_instancing";
  if (!ext.is_object() || !ext.contains("attributes") || !ext["attributes"].is_object())
    return fail(ew + " needs an 'attributes' object");
  const json& attributes = ext["attributes"];
  std::optional<FloatView> t, r, sc;
  std::optional<std::size_t> count;
  auto read = [&](const char* key, int type, std::optional<FloatView>& out) -> Status {
    auto it = attributes.find(key);
    if (it == attributes.end()) return Ok{};
    if (!it->is_number_integer()) return fail(ew + ": attribute " + key + " must be an accessor index");
    Result<FloatView> v = read_floats(it->get<int>(), type, ew + " " + key);
    if (!v.ok()) return v.error();
    const std::size_t n = v->count();
    if (count && *count != n)
      return fail(ew + ": attribute " + key + " has " + std::to_string(n) + " elements, another " +
                  std::to_string(*count));
    count = n;
    out.emplace(std::move(*v));
    return Ok{};
  };
  if (Status st = read("TRANSLATION", TINYGLTF_TYPE_VEC3, t); !st.ok()) return st.error();
  if (Status st = read("ROTATION", TINYGLTF_TYPE_VEC4, r); !st.ok()) return st.error();
  if (Status st = read("SCALE", TINYGLTF_TYPE_VEC3, sc); !st.ok()) return st.error();
  for (const auto& item : attributes.items()) {
    const std::string& key = item.key();
    if (key != "TRANSLATION" && key != "ROTATION" && key != "SCALE")
      note(Severity::Info, "instancing-attribute-ignored",
           ew + ": attribute " + key + " is not a transform; ignored");
  }
  if (!count) return fail(ew + " has none of TRANSLATION, ROTATION and SCALE");
  if (*count > kMaxInstances)
    return fail(ew + ": " + std::to_string(*count) + " copies, more than Gonio loads (" +
                std::to_string(kMaxInstances) + ")");
  std::vector<Copy> copies;
  copies.reserve(*count);
  for (std::size_t i = 0; i < *count; ++i) {
    tinygltf::Node trs;
    // glTF's TRS, for local_transform's checks and conventions.
    const auto take = [i](const FloatView& v, std::size_t n) {
      std::vector<double> out(n);
      for (std::size_t c = 0; c < n; ++c) out[c] = static_cast<double>(v.at(i, c));
      return out;
    };
    if (t) trs.translation = take(*t, 3);
    if (r) trs.rotation = take(*r, 4);
    if (sc) trs.scale = take(*sc, 3);
    const std::string name = node_name + "[" + std::to_string(i) + "]";
    Result<sim::Affine> local = local_transform(trs, ew + " copy " + std::to_string(i));
    if (!local.ok()) return local.error();
    const sim::Affine w = world * *local;
    if (!w.finite()) return fail(ew + " copy " + std::to_string(i) + ": the world transform is not finite");
    copies.push_back({w, name});
  }
  return copies;
}

Status Loader::visit_node(int index, const sim::Affine& world) {
  const auto& node = model_.nodes[static_cast<std::size_t>(index)];
  const std::string what = node_what(index);

  std::optional<double> node_flux;
  std::optional<std::string> ray_file;
  Result<json> extras = parse_blob(node.extras_json_string, what + " extras");
  if (!extras.ok()) return extras.error();
  Result<const json*> gx = gonio_extras(*extras, what, {"flux_lm", "ray_file"});
  if (!gx.ok()) return gx.error();
  if (*gx) {
    Result<std::optional<double>> f = number(**gx, "flux_lm", what + " extras.gonio");
    if (!f.ok()) return f.error();
    if (*f && **f < 0.0) return fail(what + ": extras.gonio.flux_lm is negative");
    node_flux = *f;
    if (auto rf = (**gx).find("ray_file"); rf != (**gx).end()) {
      if (!rf->is_string()) return fail(what + ": extras.gonio.ray_file must be a string (a relative uri)");
      ray_file = rf->get<std::string>();
    }
  }

  Result<json> ext = parse_blob(node.extensions_json_string, what + " extensions");
  if (!ext.ok()) return ext.error();

  std::vector<std::size_t> area;
  if (node.mesh >= 0) {
    if (static_cast<std::size_t>(node.mesh) >= model_.meshes.size())
      return fail(what + ": mesh " + std::to_string(node.mesh) + " does not exist (" +
                  std::to_string(model_.meshes.size()) + " meshes)");
    const std::string node_name = node.name.empty() ? "node-" + std::to_string(index) : node.name;
    // A mesh placed more than once is instanced; so are the copies of
    // EXT_mesh_gpu_instancing (the node itself then places none).
    std::optional<std::vector<Copy>> copies;
    if (ext->is_object() && ext->contains("EXT_mesh_gpu_instancing")) {
      Result<std::vector<Copy>> gpu = gpu_instances(ext->at("EXT_mesh_gpu_instancing"), world, node_name, what);
      if (!gpu.ok()) return gpu.error();
      copies = std::move(*gpu);
    } else if (mesh_uses_[static_cast<std::size_t>(node.mesh)] > 1) {
      copies = std::vector<Copy>{{world, node_name}};
    }
    const auto& gm = model_.meshes[static_cast<std::size_t>(node.mesh)];
    for (std::size_t p = 0; p < gm.primitives.size(); ++p)
      if (Status s = add_primitive(node, index, node.mesh, static_cast<int>(p), world, area,
                                   copies ? &*copies : nullptr);
          !s.ok())
        return s;
  } else if (ext->is_object() && ext->contains("EXT_mesh_gpu_instancing")) {
    note(Severity::Warning, "instancing-without-mesh",
         what + ": EXT_mesh_gpu_instancing on a node without a mesh; ignored");
  }
  if (node.skin >= 0)
    note(Severity::Warning, "skin-ignored",
         what + ": skinning is ignored; the mesh is placed by the node's transform");

  const bool has_khr = ext->is_object() && ext->contains("KHR_lights_punctual");
  const bool has_ies = ext->is_object() && ext->contains("EXT_lights_ies");
  if (ray_file && (has_khr || has_ies))
    return fail(what + ": extras.gonio.ray_file and a light on one node: the ray set is the node's light; "
                       "remove the light or put the ray file on its own node");
  if (node_flux && (int{has_khr} + int{has_ies} + int{!area.empty()} + int{ray_file.has_value()}) > 1)
    return fail(what + ": extras.gonio.flux_lm is ambiguous: the node carries more than one kind "
                       "of emitter; put flux_lm on the light or split the node");
  std::vector<std::size_t> lights;
  if (has_khr)
    if (Status s = add_khr_light(ext->at("KHR_lights_punctual"), world, what, node_flux, lights);
        !s.ok())
      return s;
  if (has_ies)
    if (Status s = add_ies_light(ext->at("EXT_lights_ies"), world, what, node_flux, lights); !s.ok())
      return s;
  if (ray_file)
    if (Status s = add_ray_set(*ray_file, world, what, node_flux, lights); !s.ok()) return s;

  if (node_flux && !area.empty()) {
    double total = 0.0;
    for (std::size_t e : area) total += scene_.emitters[e].flux_lm;
    for (std::size_t e : area) scene_.emitters[e].flux_lm *= *node_flux / total;
  }
  if (node_flux && area.empty() && lights.empty())
    note(Severity::Warning, "flux-without-emitter",
         what + ": extras.gonio.flux_lm is set but the node carries no emitter; ignored");
  return Ok{};
}

Result<sim::SceneDesc> Loader::load() {
  if (Status s = parse_file(); !s.ok()) return s.error();
  if (Status s = check_extensions(); !s.ok()) return s.error();
  if (Status s = read_model_extras(); !s.ok()) return s.error();
  if (Status s = read_root_lights(); !s.ok()) return s.error();
  scene_.name = fs::path(path_).filename().string();
  root_ = sim::scaling(unit_m_, unit_m_, unit_m_);

  Result<std::vector<int>> roots = root_nodes();
  if (!roots.ok()) return roots.error();
  count_mesh_uses(*roots);
  visited_.assign(model_.nodes.size(), 0);
  std::vector<std::pair<int, sim::Affine>> stack;
  for (auto it = roots->rbegin(); it != roots->rend(); ++it) stack.emplace_back(*it, root_);
  while (!stack.empty()) {
    auto [index, parent] = stack.back();
    stack.pop_back();
    if (visited_[static_cast<std::size_t>(index)])
      return fail(node_what(index) +
                  " is reached twice from the scene: the node graph has a cycle or a node "
                  "with two parents");
    visited_[static_cast<std::size_t>(index)] = 1;
    const auto& node = model_.nodes[static_cast<std::size_t>(index)];
    Result<sim::Affine> local = local_transform(node, node_what(index));
    if (!local.ok()) return local.error();
    const sim::Affine world = parent * *local;
    if (!world.finite()) return fail(node_what(index) + ": the world transform is not finite");
    if (Status s = visit_node(index, world); !s.ok()) return s.error();
    for (auto it = node.children.rbegin(); it != node.children.rend(); ++it)
      stack.emplace_back(*it, world);
  }

  std::vector<sim::Emitter> kept;
  for (sim::Emitter& e : scene_.emitters) {
    if (e.flux_lm > 0.0) {
      kept.push_back(std::move(e));
    } else {
      note(Severity::Warning, "emitter-without-flux",
           "emitter '" + e.name + "' has zero flux and is left out");
    }
  }
  scene_.emitters = std::move(kept);
  if (scene_.emitters.empty() && options_.require_emitters)
    return fail("no emitter: the scene has no EXT_lights_ies light, no KHR_lights_punctual point "
                "or spot light and no emissive material with flux; nothing would shine");
  if (scene_.meshes.empty())
    note(Severity::Info, "no-geometry", "the model has no triangles: bare emitters only");
  colour_base_colours();
  if (!options_.instancing) return sim::flattened(scene_);
  return std::move(scene_);
}

}  // namespace

Result<sim::SceneDesc> load_gltf(const std::string& path, std::vector<Finding>* findings,
                                 const GltfLoadOptions& options) {
  std::vector<Finding> local;
  Loader loader(path, findings ? *findings : local, options);
  try {
    return loader.load();
  } catch (const std::bad_alloc&) {
    return make_error(path, "out of memory while loading the model");
  } catch (const std::exception& e) {
    return make_error(path, std::string("unexpected failure while loading the model: ") + e.what());
  }
}

}  // namespace gonio::io
