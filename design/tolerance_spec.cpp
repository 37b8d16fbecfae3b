#include "design/tolerance_spec.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <numbers>
#include <set>

#include "io/support/file_io.h"
#include "io/support/text.h"
#include "photometry/error_at.h"
#include "photometry/format.h"
#include "sim/affine.h"

namespace gonio::design {
namespace {

constexpr const char* kEmitterQuantities[] = {"x", "y", "z", "tilt_x", "tilt_y", "flux"};
constexpr const char* kMaterialQuantities[] = {"reflectance", "transmittance", "roughness", "scattering"};
constexpr const char* kPartQuantities[] = {"x", "y", "z", "tilt_x", "tilt_y"};

template <std::size_t N>
bool one_of(const std::string& q, const char* const (&list)[N]) {
  return std::find_if(std::begin(list), std::end(list), [&](const char* s) { return q == s; }) != std::end(list);
}

template <std::size_t N>
std::string listed(const char* const (&list)[N]) {
  std::string s;
  for (const char* q : list) s += (s.empty() ? "" : ", ") + std::string(q);
  return s;
}

// A finite number of a law's table.
Result<double> number_of(const io::TomlNode& node, const std::string& key, const std::string& path) {
  const std::optional<double> v = node.number();
  if (!v || !std::isfinite(*v)) return make_error(path, node.line, key + " must be a finite number");
  return *v;
}

Result<ToleranceLaw> parse_law(const io::TomlNode& node, const std::string& what, const std::string& path) {
  if (!node.is_table())
    return make_error(path, node.line,
                      what + ": write a law as a table: { normal = SIGMA[, truncate = K] }, { uniform = HALF_WIDTH } or "
                             "{ values = [V1, V2, …] }");
  ToleranceLaw law;
  int laws = 0;
  bool truncate = false;
  for (const auto& [key, value] : node.table) {
    if (key == "normal") {
      Result<double> s = number_of(value, what + ".normal", path);
      if (!s.ok()) return s.error();
      if (!(*s >= 0.0)) return make_error(path, value.line, what + ".normal: σ must be ≥ 0");
      law.kind = ToleranceLaw::Kind::Normal;
      law.sigma = *s;
      ++laws;
    } else if (key == "uniform") {
      Result<double> a = number_of(value, what + ".uniform", path);
      if (!a.ok()) return a.error();
      if (!(*a >= 0.0)) return make_error(path, value.line, what + ".uniform: the half width must be ≥ 0");
      law.kind = ToleranceLaw::Kind::Uniform;
      law.half_width = *a;
      ++laws;
    } else if (key == "values") {
      if (!value.is_array() || value.array.empty())
        return make_error(path, value.line, what + ".values must be a non-empty array of numbers");
      law.kind = ToleranceLaw::Kind::Values;
      for (const io::TomlNode& v : value.array) {
        Result<double> x = number_of(v, what + ".values", path);
        if (!x.ok()) return x.error();
        law.values.push_back(*x);
      }
      ++laws;
    } else if (key == "truncate") {
      Result<double> k = number_of(value, what + ".truncate", path);
      if (!k.ok()) return k.error();
      if (!(*k > 0.0 && *k <= 10.0)) return make_error(path, value.line, what + ".truncate must lie in (0, 10] (σ)");
      law.truncate = *k;
      truncate = true;
    } else {
      return make_error(path, value.line, what + ": unknown key " + io::shown(key) + " (normal, truncate, uniform, values)");
    }
  }
  if (laws != 1) return make_error(path, node.line, what + ": give exactly one of normal, uniform, values");
  if (truncate && law.kind != ToleranceLaw::Kind::Normal)
    return make_error(path, node.line, what + ": truncate goes with normal only");
  return law;
}

// Rotates v about the unit axis a by angle t (Rodrigues).
Vec3 rotate(const Vec3& v, const Vec3& a, double t) {
  const double c = std::cos(t), s = std::sin(t);
  return c * v + s * cross(a, v) + (1.0 - c) * dot(a, v) * a;
}

const sim::Emitter* find_emitter(const sim::SceneDesc& scene, const std::string& name) {
  for (const sim::Emitter& e : scene.emitters)
    if (e.name == name) return &e;
  return nullptr;
}
const sim::Material* find_material(const sim::SceneDesc& scene, const std::string& name) {
  for (const sim::Material& m : scene.materials)
    if (m.name == name) return &m;
  return nullptr;
}

// A part's meshes: the name itself, or a node's name before a '/' of the
// mesh's name ("reflector" is "reflector/reflector/0", glTF's node/mesh/primitive).
bool in_part(const sim::Mesh& mesh, const std::string& name) {
  return mesh.name == name || (mesh.name.size() > name.size() && mesh.name.compare(0, name.size(), name) == 0 &&
                               mesh.name[name.size()] == '/');
}

// The instances a part names (docs/tolerance.md, "Instanced parts"): the
// name of an instanced mesh ("lens" or "lens/0", glTF's mesh/primitive; a
// CAD part's name) names each of its copies (`copies`: each moves about the
// centre of its own bounding box, all by the one value drawn); otherwise an
// instance is in the part where its placed name, "NODE/MESH" (its node's name
// or CAD path, then its mesh's: the name sim::flattened gives its copy),
// is in the part, or starts with "NAME[" (the copies of one
// EXT_mesh_gpu_instancing node, "array[3]"): one body with the part's world
// meshes, about the centre of their common bounding box.
struct PartInstances {
  std::vector<std::size_t> instances;
  bool copies = false;
};

PartInstances part_instances(const sim::SceneDesc& scene, const std::string& name) {
  PartInstances p;
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    const sim::Instance& inst = scene.instances[i];
    if (inst.mesh < scene.meshes.size() && in_part(scene.meshes[inst.mesh], name)) p.instances.push_back(i);
  }
  p.copies = !p.instances.empty();
  if (p.copies) return p;
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    const sim::Instance& inst = scene.instances[i];
    if (inst.mesh >= scene.meshes.size()) continue;
    sim::Mesh placed;
    placed.name = inst.name + "/" + scene.meshes[inst.mesh].name;
    if (in_part(placed, name) || placed.name.rfind(name + "[", 0) == 0) p.instances.push_back(i);
  }
  return p;
}

// Widens [lo, hi] by the placed vertices of instance `i`.
void add_instance_bounds(const sim::SceneDesc& scene, std::size_t i, Vec3& lo, Vec3& hi) {
  const sim::Instance& inst = scene.instances[i];
  for (const sim::Vec3f& p : scene.meshes[inst.mesh].positions) {
    const Vec3 q = inst.to_world.point(sim::to_double(p));
    lo = {std::min(lo.x, q.x), std::min(lo.y, q.y), std::min(lo.z, q.z)};
    hi = {std::max(hi.x, q.x), std::max(hi.y, q.y), std::max(hi.z, q.z)};
  }
}

// A part's move: along the luminaire's axes, or turned about its C0 (C90)
// axis through `centre`.
sim::Affine part_move(const photometry::PhotometricFrame& f, const std::string& quantity, double v,
                      const Vec3& centre) {
  if (quantity == "x") return sim::translation((v * 1e-3) * f.c0);
  if (quantity == "y") return sim::translation((v * 1e-3) * f.c90);
  if (quantity == "z") return sim::translation((v * 1e-3) * f.up);
  return sim::translation(centre) * sim::rotation(quantity == "tilt_x" ? f.c0 : f.c90, v * std::numbers::pi / 180.0) *
         sim::translation(-1.0 * centre);
}

// An area or ray-set emitter's reference point: a ray set's origin as
// placed (Emitter::position, the node's or sidecar's origin), an area
// emitter's mesh's bounding-box centre as placed.
Vec3 emitter_reference(const sim::SceneDesc& scene, const sim::Emitter& e) {
  if (e.kind == sim::Emitter::Kind::RaySet) return e.position;
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  if (e.instance != sim::kNoInstance) {
    add_instance_bounds(scene, e.instance, lo, hi);
  } else {
    for (const sim::Vec3f& p : scene.meshes[e.mesh].positions) {
      const Vec3 q = sim::to_double(p);
      lo = {std::min(lo.x, q.x), std::min(lo.y, q.y), std::min(lo.z, q.z)};
      hi = {std::max(hi.x, q.x), std::max(hi.y, q.y), std::max(hi.z, q.z)};
    }
  }
  return 0.5 * (lo + hi);
}

// Moves an area emitter's mesh (or its instance) or a ray set's rays
// (origins and directions, and its reference point) by `map`.
void move_extended_emitter(sim::SceneDesc& scene, sim::Emitter& e, const sim::Affine& map) {
  if (e.kind == sim::Emitter::Kind::Area) {
    if (e.instance != sim::kNoInstance)
      scene.instances[e.instance].to_world = map * scene.instances[e.instance].to_world;
    else
      sim::transform(scene.meshes[e.mesh], map);
    return;
  }
  auto rays = std::make_shared<sim::RaySet>(*e.rays);
  for (std::size_t i = 0; i < rays->size(); ++i) {
    rays->position_m[i] = sim::to_float(map.point(sim::to_double(rays->position_m[i])));
    rays->direction[i] = sim::to_float(normalize(map.linear(sim::to_double(rays->direction[i]))));
  }
  e.rays = std::move(rays);
  e.position = map.point(e.position);
}

// A part's form error, `form = { modes = K, rms_um = S }`: K tolerances
// form1 … formK, each the amplitude [µm RMS] of one orthonormal Legendre
// mode of the sag, N(0, S/√K) truncated at ±3σ, so that the sum's expected
// mean square is S².
Result<std::vector<Tolerance>> parse_form(const io::TomlNode& node, const std::string& name, const std::string& what,
                                          const std::string& path) {
  if (!node.is_table()) return make_error(path, node.line, what + ": write { modes = K, rms_um = S }");
  std::optional<double> modes, rms;
  for (const auto& [key, value] : node.table) {
    Result<double> v = number_of(value, what + "." + key, path);
    if (key != "modes" && key != "rms_um")
      return make_error(path, value.line, what + ": unknown key " + io::shown(key) + " (modes, rms_um)");
    if (!v.ok()) return v.error();
    if (key == "modes") {
      if (!(*v >= 1.0 && *v <= kMaxFormModes && *v == std::floor(*v)))
        return make_error(path, value.line, what + ".modes must be a whole number from 1 to " + std::to_string(kMaxFormModes));
      modes = *v;
    } else {
      if (!(*v >= 0.0)) return make_error(path, value.line, what + ".rms_um must be ≥ 0");
      rms = *v;
    }
  }
  if (!modes || !rms) return make_error(path, node.line, what + ": give both modes and rms_um");
  std::vector<Tolerance> out;
  for (int k = 1; k <= static_cast<int>(*modes); ++k) {
    Tolerance t;
    t.target = Tolerance::Target::Part;
    t.name = name;
    t.quantity = "form" + std::to_string(k);
    t.law.kind = ToleranceLaw::Kind::Normal;
    t.law.sigma = *rms / std::sqrt(*modes);
    t.line = node.line;
    out.push_back(std::move(t));
  }
  return out;
}

double reflection(const sim::Material& m) { return m.diffuse_reflect + m.mirror + m.glossy + m.abg_reflect.tis; }
double transmission(const sim::Material& m) { return m.diffuse_transmit + m.dielectric + m.abg_transmit.tis; }
// The largest reflection (transmission) over wavelength: a spectral
// reflectance (transmittance) replaces the lobes' total at each wavelength
// (sim/tracer/spectral.h), so its largest value is what a tolerance scales.
double reflection_peak(const sim::Material& m) {
  if (m.spectral_reflectance.empty()) return reflection(m);
  return *std::max_element(m.spectral_reflectance.values.begin(), m.spectral_reflectance.values.end());
}
double transmission_peak(const sim::Material& m) {
  if (m.spectral_transmittance.empty()) return transmission(m);
  return *std::max_element(m.spectral_transmittance.values.begin(), m.spectral_transmittance.values.end());
}
// The largest sum of the lobes over wavelength (an upper bound: the largest
// reflection and transmission as if at one wavelength).
double total_peak(const sim::Material& m) {
  return m.total() - reflection(m) - transmission(m) + reflection_peak(m) + transmission_peak(m);
}

// An emitter's bins, `flux_bin = { factors = [...], probabilities = [...] }`
// or `colour_bin = { spectra = [FILE or { blackbody_k = K }, ...] | cct = [K, ...],
// probabilities = [...] }`: one tolerance whose value is the bin's number.
Result<Tolerance> parse_bins(const io::TomlNode& node, const std::string& name, const std::string& quantity,
                             const std::string& what, const std::string& path) {
  const bool flux = quantity == "flux_bin";
  const char* form = flux ? "{ factors = [F1, F2, …], probabilities = [P1, P2, …] }"
                          : "{ spectra = [\"FILE\", { blackbody_k = K }, …] or cct = [K1, K2, …], probabilities = "
                            "[P1, P2, …] }";
  if (!node.is_table()) return make_error(path, node.line, what + ": write " + std::string(form));
  Tolerance t;
  t.target = Tolerance::Target::Emitter;
  t.name = name;
  t.quantity = quantity;
  t.line = node.line;
  t.law.kind = ToleranceLaw::Kind::Bins;
  const io::TomlNode* probabilities = nullptr;
  int lists = 0;
  const auto numbers = [&](const io::TomlNode& list, const std::string& key) -> Result<std::vector<double>> {
    if (!list.is_array() || list.array.empty())
      return make_error(path, list.line, what + "." + key + " must be a non-empty array of numbers");
    std::vector<double> out;
    for (const io::TomlNode& v : list.array) {
      Result<double> x = number_of(v, what + "." + key, path);
      if (!x.ok()) return x.error();
      out.push_back(*x);
    }
    return out;
  };
  for (const auto& [key, value] : node.table) {
    if (key == "probabilities") {
      probabilities = &value;
    } else if (flux && key == "factors") {
      Result<std::vector<double>> f = numbers(value, key);
      if (!f.ok()) return f.error();
      for (double x : *f) {
        if (!(x > 0.0)) return make_error(path, value.line, what + ".factors: a factor must be > 0 (" + format_number(x) + ")");
        t.bin_factors.push_back(x);
        t.bin_names.push_back("×" + format_number(x));
      }
      ++lists;
    } else if (!flux && key == "cct") {
      Result<std::vector<double>> k = numbers(value, key);
      if (!k.ok()) return k.error();
      for (double x : *k) {
        if (!(x >= 1000.0 && x <= 25000.0))
          return make_error(path, value.line, what + ".cct: " + format_number(x) + " K is outside 1000 … 25000 K");
        t.bin_spectra.push_back(photometry::blackbody_spectrum(x));
        t.bin_names.push_back(format_number(x) + " K");
      }
      ++lists;
    } else if (!flux && key == "spectra") {
      if (!value.is_array() || value.array.empty())
        return make_error(path, value.line, what + ".spectra must be a non-empty array of file names or { blackbody_k = K }");
      for (const io::TomlNode& v : value.array) {
        if (v.is_string()) {
          // Relative to the tolerance file's folder.
          const std::filesystem::path file = std::filesystem::path(path).parent_path() / v.string;
          if (!std::filesystem::is_regular_file(file))
            return make_error(path, v.line, what + ".spectra: no spectrum file " + io::shown(file.string()));
          Result<photometry::SampledSpectrum> sp = read_spectrum_table(file.string());
          if (!sp.ok()) return sp.error();
          t.bin_spectra.push_back(std::move(sp.value()));
          t.bin_names.push_back(v.string);
          continue;
        }
        const io::TomlNode* k = v.is_table() && v.table.size() == 1 ? v.get("blackbody_k") : nullptr;
        const std::optional<double> kelvin = k ? k->number() : std::nullopt;
        if (!kelvin || !(*kelvin >= 1000.0 && *kelvin <= 25000.0))
          return make_error(path, v.line, what + ".spectra: each is a file name or { blackbody_k = K }, 1000 ≤ K ≤ 25000");
        t.bin_spectra.push_back(photometry::blackbody_spectrum(*kelvin));
        t.bin_names.push_back(format_number(*kelvin) + " K");
      }
      ++lists;
    } else {
      return make_error(path, value.line,
                        what + ": unknown key " + io::shown(key) + (flux ? " (factors, probabilities)" : " (spectra, cct, probabilities)"));
    }
  }
  if (lists != 1) return make_error(path, node.line, what + ": give exactly one list of bins: " + form);
  const std::size_t count = flux ? t.bin_factors.size() : t.bin_spectra.size();
  if (probabilities) {
    Result<std::vector<double>> p = numbers(*probabilities, "probabilities");
    if (!p.ok()) return p.error();
    if (p->size() != count)
      return make_error(path, probabilities->line, what + ".probabilities: " + std::to_string(p->size()) + " for " +
                                                       std::to_string(count) + " bins");
    double sum = 0.0;
    for (double x : *p) {
      if (!(x >= 0.0)) return make_error(path, probabilities->line, what + ".probabilities must be ≥ 0");
      sum += x;
    }
    if (!(std::abs(sum - 1.0) <= 1e-6))
      return make_error(path, probabilities->line,
                        what + ".probabilities sum to " + format_number(sum) + ", not 1");
    t.law.probabilities = std::move(p.value());
  } else {
    t.law.probabilities.assign(count, 1.0 / static_cast<double>(count));  // equally likely
  }
  for (std::size_t k = 1; k <= count; ++k) t.law.values.push_back(static_cast<double>(k));
  return t;
}

// Bin round(v) (clamped to 1 … K) of an emitter's bins applied to it.
void apply_bin(const Tolerance& t, double v, sim::Emitter& e) {
  const std::size_t count = t.law.probabilities.size();
  const auto k = static_cast<std::size_t>(std::clamp(std::llround(v), 1LL, static_cast<long long>(count)));
  if (t.quantity == "flux_bin") e.flux_lm *= t.bin_factors[k - 1];
  else e.spectrum.over_gamma = {{0.0, t.bin_spectra[k - 1]}};
}

}  // namespace

std::array<double, 2> legendre(int k, double t) {
  double p0 = 1.0, p1 = t, d0 = 0.0, d1 = 1.0;
  if (k == 0) return {1.0, 0.0};
  for (int n = 1; n < k; ++n) {
    const double p2 = ((2.0 * n + 1.0) * t * p1 - n * p0) / (n + 1.0);
    const double d2 = d0 + (2.0 * n + 1.0) * p1;  // P'_{n+1} = P'_{n−1} + (2n + 1) P_n
    p0 = p1;
    p1 = p2;
    d0 = d1;
    d1 = d2;
  }
  return {p1, d1};
}

void apply_form_mode(sim::SceneDesc& scene, const std::string& part, int mode, double amplitude_um,
                     const Vec3& centre) {
  const Vec3 up = scene.frame.up;
  const auto radial = [&](const Vec3& q) {
    const Vec3 r = q - centre;
    return r - dot(r, up) * up;
  };
  double rho_lo = 1e300, rho_hi = 0.0;
  for (const sim::Mesh& mesh : scene.meshes)
    if (in_part(mesh, part) && !mesh.instanced)
      for (const sim::Vec3f& p : mesh.positions) {
        const double rho = length(radial(sim::to_double(p)));
        rho_lo = std::min(rho_lo, rho);
        rho_hi = std::max(rho_hi, rho);
      }
  if (!(rho_hi > rho_lo)) return;  // no extent across the axis: no sag to shape
  const double a = amplitude_um * 1e-6 * std::sqrt(2.0 * mode + 1.0);  // [m]
  const double dt = 2.0 / (rho_hi - rho_lo);
  for (sim::Mesh& mesh : scene.meshes) {
    if (!in_part(mesh, part) || mesh.instanced) continue;
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
      const Vec3 q = sim::to_double(mesh.positions[i]);
      const Vec3 r = radial(q);
      const double rho = length(r);
      const std::array<double, 2> p = legendre(mode, std::clamp((rho - rho_lo) * dt - 1.0, -1.0, 1.0));
      mesh.positions[i] = sim::to_float(q + (a * p[0]) * up);
      if (i < mesh.normals.size() && rho > 0.0) {
        // z = s(ρ) + δ(ρ): the normal ∝ n − n_z·δ′(ρ)·ρ̂, its side kept.
        const Vec3 n = sim::to_double(mesh.normals[i]);
        const Vec3 m = n - (dot(n, up) * a * p[1] * dt / rho) * r;
        mesh.normals[i] = sim::to_float((1.0 / length(m)) * m);
      }
    }
  }
}

double ToleranceLaw::low() const {
  switch (kind) {
    case Kind::Normal: return -truncate * sigma;
    case Kind::Uniform: return -half_width;
    case Kind::Values: return *std::min_element(values.begin(), values.end());
    case Kind::Bins: return 1.0;
  }
  return 0.0;
}

double ToleranceLaw::high() const {
  switch (kind) {
    case Kind::Normal: return truncate * sigma;
    case Kind::Uniform: return half_width;
    case Kind::Values: return *std::max_element(values.begin(), values.end());
    case Kind::Bins: return static_cast<double>(probabilities.size());
  }
  return 0.0;
}

double ToleranceLaw::quantile(double u) const {
  u = std::clamp(u, 0.0, 1.0);
  switch (kind) {
    case Kind::Uniform: return -half_width + 2.0 * half_width * u;
    case Kind::Values: {
      const std::size_t i = std::min(values.size() - 1, static_cast<std::size_t>(u * static_cast<double>(values.size())));
      return values[i];
    }
    case Kind::Bins: {
      // The bin whose cumulative interval holds u (the last where rounding
      // leaves u at or above the sum).
      double cumulative = 0.0;
      for (std::size_t k = 0; k + 1 < probabilities.size(); ++k) {
        cumulative += probabilities[k];
        if (u < cumulative) return static_cast<double>(k + 1);
      }
      return static_cast<double>(probabilities.size());
    }
    case Kind::Normal: {
      if (sigma == 0.0) return 0.0;
      // Φ(x) = erfc(−x/√2)/2; the truncated law's u maps to Φ(−k) + u·(Φ(k) − Φ(−k)).
      const auto phi = [](double x) { return 0.5 * std::erfc(-x / std::numbers::sqrt2); };
      const double p = phi(-truncate) + u * (phi(truncate) - phi(-truncate));
      double lo = -truncate, hi = truncate;
      for (int i = 0; i < 100; ++i) {
        const double mid = 0.5 * (lo + hi);
        (phi(mid) < p ? lo : hi) = mid;
      }
      return sigma * 0.5 * (lo + hi);
    }
  }
  return 0.0;
}

std::string ToleranceLaw::text() const {
  switch (kind) {
    case Kind::Normal: return "N(0, " + format_number(sigma) + ") ±" + format_number(truncate) + "σ";
    case Kind::Uniform: return "U(±" + format_number(half_width) + ")";
    case Kind::Values: {
      std::string s = "{";
      for (std::size_t i = 0; i < values.size(); ++i) s += (i ? ", " : "") + format_number(values[i]);
      return s + "}";
    }
    case Kind::Bins: {
      std::string s = "bins {";
      for (std::size_t i = 0; i < probabilities.size(); ++i) s += (i ? ", " : "") + format_number(probabilities[i]);
      return s + "}";
    }
  }
  return {};
}

const char* Tolerance::unit() const {
  if (law.kind == ToleranceLaw::Kind::Bins) return "bin";
  if (quantity == "x" || quantity == "y" || quantity == "z") return "mm";
  if (quantity == "tilt_x" || quantity == "tilt_y") return "deg";
  if (quantity.rfind("form", 0) == 0) return "µm";
  if (target == Target::Variable) return "(design units)";
  return "%";
}

Result<ToleranceSpec> parse_tolerances(std::string_view text, const std::string& path) {
  Result<io::TomlNode> root = io::parse_toml(text, path);
  if (!root.ok()) return root.error();
  return parse_tolerance_tree(*root, path);
}

Result<ToleranceSpec> parse_tolerance_tree(const io::TomlNode& root, const std::string& path, bool design) {
  ToleranceSpec spec;
  spec.path = path;
  const auto variable = [&](const std::string& name, const io::TomlNode& law_node) -> Status {
    Result<ToleranceLaw> law = parse_law(law_node, name, path);
    if (!law.ok()) return law.error();
    Tolerance t;
    t.target = Tolerance::Target::Variable;
    t.name = name;
    t.law = std::move(law.value());
    t.line = law_node.line;
    spec.tolerances.push_back(std::move(t));
    return Ok{};
  };
  for (const auto& [section, node] : root.table) {
    const bool emitter = section == "emitter", part = section == "part";
    if (section == "variable") {
      if (!node.is_table()) return make_error(path, node.line, "variable must be a table: NAME = { law }");
      for (const auto& [name, law_node] : node.table)
        if (Status st = variable(name, law_node); !st.ok()) return st.error();
      continue;
    }
    if (design && !emitter && !part && section != "material") {
      if (Status st = variable(section, node); !st.ok()) return st.error();
      continue;
    }
    if (!emitter && !part && section != "material")
      return make_error(path, node.line, "unknown section " + io::shown(section) + " (emitter, part, material, variable)");
    if (!node.is_table())
      return make_error(path, node.line, section + " must be tables by name: [" + section + ".NAME]");
    for (const auto& [name, quantities] : node.table) {
      if (!quantities.is_table())
        return make_error(path, quantities.line, "[" + section + "." + name + "] must be a table of values");
      // [part.NAME] independent = true: each copy of an instanced mesh draws its own values.
      const io::TomlNode* independent = part ? quantities.get("independent") : nullptr;
      if (independent && independent->type != io::TomlNode::Type::Boolean)
        return make_error(path, independent->line, section + "." + name + ".independent must be true or false");
      for (const auto& [quantity, law_node] : quantities.table) {
        if (independent && quantity == "independent") continue;
        const std::string what = section + "." + name + "." + quantity;
        if (part && quantity == "form") {
          Result<std::vector<Tolerance>> modes = parse_form(law_node, name, what, path);
          if (!modes.ok()) return modes.error();
          for (Tolerance& t : *modes) spec.tolerances.push_back(std::move(t));
          continue;
        }
        if (emitter && (quantity == "flux_bin" || quantity == "colour_bin")) {
          Result<Tolerance> bins = parse_bins(law_node, name, quantity, what, path);
          if (!bins.ok()) return bins.error();
          spec.tolerances.push_back(std::move(bins.value()));
          continue;
        }
        const bool known = emitter ? one_of(quantity, kEmitterQuantities)
                           : part  ? one_of(quantity, kPartQuantities)
                                   : one_of(quantity, kMaterialQuantities);
        if (!known)
          return make_error(path, law_node.line,
                            "unknown " + section + " value " + io::shown(quantity) + " (" +
                                (emitter ? listed(kEmitterQuantities) + ", flux_bin, colour_bin"
                                 : part  ? listed(kPartQuantities) + ", form"
                                         : listed(kMaterialQuantities)) +
                                ")");
        Result<ToleranceLaw> law = parse_law(law_node, what, path);
        if (!law.ok()) return law.error();
        Tolerance t;
        t.target = emitter ? Tolerance::Target::Emitter
                   : part  ? Tolerance::Target::Part
                           : Tolerance::Target::Material;
        t.name = name;
        t.quantity = quantity;
        t.law = std::move(law.value());
        t.line = law_node.line;
        t.independent = independent && independent->boolean;
        if (t.unit() == std::string("%") && t.law.low() <= -100.0)
          return make_error(path, t.line, what + ": a change of −100 % or less leaves nothing (" + t.law.text() + ")");
        spec.tolerances.push_back(std::move(t));
      }
    }
  }
  if (spec.tolerances.empty())
    return design ? make_error(path, root.line, "no tolerances in [tolerances]: give variables or [tolerances.emitter.NAME], "
                                                "[tolerances.part.NAME], [tolerances.material.NAME] tables")
                  : make_error(path, "no tolerances: give [emitter.NAME], [part.NAME] or [material.NAME] tables");
  return spec;
}

Result<ToleranceSpec> read_tolerances(const std::string& path) {
  Result<std::string> text = io::read_file(path, std::size_t{16} << 20);
  if (!text.ok()) return text.error();
  return parse_tolerances(*text, path);
}

Result<photometry::SampledSpectrum> read_spectrum_table(const std::string& path) {
  Result<std::string> text = io::read_file(path, std::size_t{16} << 20);
  if (!text.ok()) return text.error();
  photometry::SampledSpectrum s;
  std::size_t start = 0;
  int line = 0;
  bool header_allowed = true;
  while (start <= text->size()) {
    std::size_t end = text->find('\n', start);
    if (end == std::string::npos) end = text->size();
    std::string l = text->substr(start, end - start);
    start = end + 1;
    ++line;
    if (const std::size_t hash = l.find('#'); hash != std::string::npos) l.erase(hash);
    for (char& c : l)
      if (c == ',' || c == ';' || c == '\t' || c == '\r') c = ' ';
    if (l.find_first_not_of(' ') == std::string::npos) {
      if (end == text->size()) break;
      continue;
    }
    double nm = 0.0, value = 0.0;
    char rest = 0;
    const int read = std::sscanf(l.c_str(), "%lf %lf %c", &nm, &value, &rest);
    if (read != 2 || !std::isfinite(nm) || !std::isfinite(value)) {
      if (header_allowed && s.empty() && read == 0) {  // one header line of text
        header_allowed = false;
        continue;
      }
      return make_error(path, line, "write two numbers per line: wavelength [nm] and value");
    }
    header_allowed = false;
    if (!s.wavelengths_nm.empty() && !(nm > s.wavelengths_nm.back()))
      return make_error(path, line, "wavelengths must increase (" + format_number(nm) + " nm after " +
                                        format_number(s.wavelengths_nm.back()) + " nm)");
    s.wavelengths_nm.push_back(nm);
    s.values.push_back(value);
    if (end == text->size()) break;
  }
  if (Status st = photometry::validate_spectrum(s); !st.ok()) return make_error(path, st.error().message);
  return s;
}

Status check_tolerances(const ToleranceSpec& spec, const sim::SceneDesc& scene) {
  for (const Tolerance& t : spec.tolerances) {
    if (t.target == Tolerance::Target::Variable) continue;  // check_variables; the design is built with them
    if (t.target == Tolerance::Target::Emitter) {
      const sim::Emitter* e = find_emitter(scene, t.name);
      if (!e) {
        std::string names;
        for (const sim::Emitter& x : scene.emitters) names += (names.empty() ? "" : ", ") + io::shown(x.name);
        return make_error(spec.path, t.line, "the model has no emitter " + io::shown(t.name) + " (it has " +
                                                 (names.empty() ? "none" : names) + ")");
      }
      if (t.quantity == "colour_bin" && e->spectrum.empty())
        return make_error(spec.path, t.line, t.label() + ": " + io::shown(t.name) +
                                                 " has no spectrum in the model: give it one (extras.gonio.spectrum, the "
                                                 "sidecar's spectrum) so that the nominal is a spectral run to compare with");
      if (t.quantity != "flux" && t.law.kind != ToleranceLaw::Kind::Bins && e->kind == sim::Emitter::Kind::RaySet &&
          !e->rays)
        return make_error(spec.path, t.line, t.label() + ": " + io::shown(t.name) + " is a ray-set emitter without rays");
      continue;
    }
    if (t.target == Tolerance::Target::Part) {
      bool world = false;
      for (const sim::Mesh& mesh : scene.meshes)
        if (in_part(mesh, t.name) && !mesh.instanced) world = true;
      const bool instanced = !part_instances(scene, t.name).instances.empty();
      if (!world && !instanced)
        for (const sim::Mesh& mesh : scene.meshes)
          if (in_part(mesh, t.name) && mesh.instanced)
            return make_error(spec.path, t.line, t.label() + ": " + io::shown(t.name) +
                                                     " is an instanced mesh placed nowhere (it has no instances)");
      if (instanced && t.quantity.rfind("form", 0) == 0)
        return make_error(spec.path, t.line, t.label() + ": " + io::shown(t.name) +
                                                 " is instanced (placed by its instances); form errors shape world meshes "
                                                 "only (load it with its copies un-instanced)");
      if (!world && !instanced) {
        std::string names;
        for (const sim::Mesh& x : scene.meshes)
          if (names.find(io::shown(x.name)) == std::string::npos) names += (names.empty() ? "" : ", ") + io::shown(x.name);
        return make_error(spec.path, t.line, "the model has no part " + io::shown(t.name) + " (it has " +
                                                 (names.empty() ? "none" : names) + ")");
      }
      continue;
    }
    const sim::Material* m = find_material(scene, t.name);
    if (!m) {
      std::string names;
      for (const sim::Material& x : scene.materials) names += (names.empty() ? "" : ", ") + io::shown(x.name);
      return make_error(spec.path, t.line, "the model has no material " + io::shown(t.name) + " (it has " +
                                               (names.empty() ? "none" : names) + ")");
    }
    const double r = reflection_peak(*m), tr = transmission_peak(*m);
    if (t.quantity == "reflectance" && !(r > 0.0))
      return make_error(spec.path, t.line, t.label() + ": the material reflects nothing (no reflection lobe)");
    if (t.quantity == "transmittance" && !(tr > 0.0))
      return make_error(spec.path, t.line, t.label() + ": the material transmits nothing (no transmission lobe)");
    if (t.quantity == "roughness" && !(m->glossy > 0.0))
      return make_error(spec.path, t.line, t.label() + ": the material has no glossy lobe to roughen");
    if (t.quantity == "scattering" && !(m->scattering_per_m > 0.0))
      return make_error(spec.path, t.line, t.label() + ": the material does not scatter in volume (its scattering "
                                                       "coefficient is 0: a clear or surface-only material)");
    const double grow = 1.0 + t.law.high() / 100.0;
    const double total = t.quantity == "reflectance"     ? total_peak(*m) + r * (grow - 1.0)
                         : t.quantity == "transmittance" ? total_peak(*m) + tr * (grow - 1.0)
                                                         : m->total();
    if (total > 1.0 + 1e-12)
      return make_error(spec.path, t.line,
                        t.label() + " at +" + format_number(t.law.high()) + " % would make the material's lobes sum to " +
                            format_number(total) + " > 1");
  }
  return Ok{};
}

Status expand_independent_copies(ToleranceSpec& spec, const sim::SceneDesc& scene) {
  std::vector<Tolerance> out;
  for (Tolerance& t : spec.tolerances) {
    if (!t.independent) {
      out.push_back(std::move(t));
      continue;
    }
    const PartInstances copies = part_instances(scene, t.name);
    if (!copies.copies)
      return make_error(spec.path, t.line, t.label() + ": independent = true needs the name of an instanced mesh (its copies "
                                                       "draw their own values); " + io::shown(t.name) + " is not one");
    std::set<std::string> placed;
    for (std::size_t k : copies.instances) {
      Tolerance each = t;
      each.independent = false;
      each.name = scene.instances[k].name + "/" + scene.meshes[scene.instances[k].mesh].name;
      // A copy's tolerance names it by its placed name: two copies of one
      // name could not be told apart (each tolerance would move both).
      if (!placed.insert(each.name).second)
        return make_error(spec.path, t.line, t.label() + ": independent = true: two copies of " + io::shown(t.name) +
                                                 " are placed as " + io::shown(each.name) +
                                                 " (the same node name): give their nodes distinct names");
      out.push_back(std::move(each));
    }
  }
  spec.tolerances = std::move(out);
  return Ok{};
}

void apply_tolerances(const ToleranceSpec& spec, std::span<const double> values, sim::SceneDesc& scene) {
  GONIO_CHECK(values.size() == spec.tolerances.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    const Tolerance& t = spec.tolerances[i];
    const double v = values[i];
    if (v == 0.0) continue;  // bit for bit the nominal
    const double scale = 1.0 + v / 100.0;
    if (t.target == Tolerance::Target::Variable) continue;  // design_with
    if (t.target == Tolerance::Target::Emitter) {
      for (sim::Emitter& e : scene.emitters) {
        if (e.name != t.name) continue;
        const photometry::PhotometricFrame& f = scene.frame;
        if (e.kind != sim::Emitter::Kind::Point && t.quantity != "flux" && t.law.kind != ToleranceLaw::Kind::Bins) {
          move_extended_emitter(scene, e, part_move(f, t.quantity, v, emitter_reference(scene, e)));
          continue;
        }
        if (t.quantity == "x") e.position = e.position + (v * 1e-3) * f.c0;
        else if (t.quantity == "y") e.position = e.position + (v * 1e-3) * f.c90;
        else if (t.quantity == "z") e.position = e.position + (v * 1e-3) * f.up;
        else if (t.law.kind == ToleranceLaw::Kind::Bins) apply_bin(t, v, e);
        else if (t.quantity == "flux") e.flux_lm *= scale;
        else {
          const Vec3 axis = t.quantity == "tilt_x" ? f.c0 : f.c90;
          const double angle = v * std::numbers::pi / 180.0;
          e.frame.c0 = rotate(e.frame.c0, axis, angle);
          e.frame.c90 = rotate(e.frame.c90, axis, angle);
          e.frame.up = rotate(e.frame.up, axis, angle);
        }
      }
      continue;
    }
    if (t.target == Tolerance::Target::Part) {
      // Every mesh of that name, moved along or turned about the luminaire's
      // axes through the centre of their common bounding box.
      const photometry::PhotometricFrame& f = scene.frame;
      Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
      for (const sim::Mesh& mesh : scene.meshes)
        if (in_part(mesh, t.name) && !mesh.instanced)
          for (const sim::Vec3f& p : mesh.positions) {
            const Vec3 q = sim::to_double(p);
            lo = {std::min(lo.x, q.x), std::min(lo.y, q.y), std::min(lo.z, q.z)};
            hi = {std::max(hi.x, q.x), std::max(hi.y, q.y), std::max(hi.z, q.z)};
          }
      const PartInstances moved = part_instances(scene, t.name);
      if (!moved.copies)
        for (std::size_t k : moved.instances) add_instance_bounds(scene, k, lo, hi);
      const Vec3 centre = 0.5 * (lo + hi);
      if (t.quantity.rfind("form", 0) == 0) {
        apply_form_mode(scene, t.name, std::stoi(t.quantity.substr(4)), v, centre);
        continue;
      }
      sim::Affine map;
      if (t.quantity == "x") map = sim::translation((v * 1e-3) * f.c0);
      else if (t.quantity == "y") map = sim::translation((v * 1e-3) * f.c90);
      else if (t.quantity == "z") map = sim::translation((v * 1e-3) * f.up);
      else
        map = sim::translation(centre) *
              sim::rotation(t.quantity == "tilt_x" ? f.c0 : f.c90, v * std::numbers::pi / 180.0) *
              sim::translation(-1.0 * centre);
      for (sim::Mesh& mesh : scene.meshes)
        if (in_part(mesh, t.name) && !mesh.instanced) sim::transform(mesh, map);
      for (std::size_t k : moved.instances) {
        Vec3 own_lo{1e300, 1e300, 1e300}, own_hi{-1e300, -1e300, -1e300};
        if (moved.copies) add_instance_bounds(scene, k, own_lo, own_hi);
        sim::Instance& inst = scene.instances[k];
        inst.to_world = (moved.copies ? part_move(f, t.quantity, v, 0.5 * (own_lo + own_hi)) : map) * inst.to_world;
      }
      continue;
    }
    for (sim::Material& m : scene.materials) {
      if (m.name != t.name) continue;
      if (t.quantity == "reflectance") {
        m.diffuse_reflect *= scale;
        m.mirror *= scale;
        m.glossy *= scale;
        m.abg_reflect.tis *= scale;
        for (double& x : m.spectral_reflectance.values) x *= scale;  // it replaces the lobes' total per wavelength
      } else if (t.quantity == "transmittance") {
        m.diffuse_transmit *= scale;
        m.dielectric *= scale;
        m.abg_transmit.tis *= scale;
        for (double& x : m.spectral_transmittance.values) x *= scale;
      } else if (t.quantity == "scattering") {
        m.scattering_per_m *= scale;  // μs alone: the absorption coefficient stays as it is
      } else {
        m.glossy_mx *= scale;
        m.glossy_my *= scale;
      }
      m.tables = nullptr;  // sim::prepare derives them again
    }
  }
}

double largest_scale(const Tolerance& t, const sim::SceneDesc& scene) {
  double k = std::numeric_limits<double>::infinity();
  if (std::string(t.unit()) == "%" && t.law.low() < 0.0) k = 0.999 * 100.0 / -t.law.low();
  if (t.target == Tolerance::Target::Material && t.law.high() > 0.0)
    if (const sim::Material* m = find_material(scene, t.name)) {
      const double part =
          t.quantity == "reflectance" ? reflection_peak(*m) : t.quantity == "transmittance" ? transmission_peak(*m) : 0.0;
      if (part > 0.0) k = std::min(k, (1.0 - total_peak(*m)) / (part * t.law.high() / 100.0));
    }
  return k;
}

Status check_variables(const ToleranceSpec& spec, const Design* design) {
  for (const Tolerance& t : spec.tolerances) {
    if (t.target != Tolerance::Target::Variable) continue;
    if (!design)
      return make_error(spec.path, t.line, io::shown(t.name) + ": a tolerance on a variable needs a design file as the model");
    if (design->variable(t.name)) continue;
    std::string names;
    for (const Variable& v : design->variables) names += (names.empty() ? "" : ", ") + io::shown(v.name);
    return make_error(spec.path, t.line, "the design " + design->path + " has no variable " + io::shown(t.name) + " (it has " +
                                             (names.empty() ? "none: write a number as { value = … } to make it one" : names) +
                                             ")");
  }
  return Ok{};
}

bool changes_variables(const ToleranceSpec& spec, std::span<const double> values) {
  for (std::size_t i = 0; i < values.size() && i < spec.tolerances.size(); ++i)
    if (spec.tolerances[i].target == Tolerance::Target::Variable && values[i] != 0.0) return true;
  return false;
}

Design design_with(const Design& base, const ToleranceSpec& spec, std::span<const double> values) {
  GONIO_CHECK(values.size() == spec.tolerances.size());
  Design d = base;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const Tolerance& t = spec.tolerances[i];
    if (t.target != Tolerance::Target::Variable || values[i] == 0.0) continue;
    for (Variable& v : d.variables)
      if (v.name == t.name) {
        v.min.reset();  // an optimiser's bounds, not the part's
        v.max.reset();
        const Status s = set_variable(d, t.name, v.value + values[i]);
        GONIO_CHECK_MSG(s.ok(), "design_with: a variable checked by check_variables");
      }
  }
  return d;
}

}  // namespace gonio::design
