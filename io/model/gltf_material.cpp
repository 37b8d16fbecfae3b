#include "io/model/gltf_material.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>
#include <string>

#include "photometry/format.h"
#include "sim/bsdfs/library.h"
#include "sim/bsdfs/slab.h"
#include "sim/bsdfs/tabulated_bsdf.h"

namespace gonio::io {
namespace {

// A glTF factor outside its range is a file defect, not a reason to refuse
// the model: clamp and say so.
double clamp_factor(double v, double lo, double hi, const char* key, const SourceLoc& where,
                    const std::string& what, std::vector<Finding>& findings) {
  if (std::isfinite(v) && v >= lo && v <= hi) return v;
  const double clamped = std::isfinite(v) ? std::clamp(v, lo, hi) : lo;
  findings.push_back({Severity::Warning, "material-factor-range",
                      what + ": " + key + " = " + format_number(v) + " outside " +
                          format_number(lo) + ".." + format_number(hi) + ", using " +
                          format_number(clamped),
                      where});
  return clamped;
}

Rgb clamp_rgb(const Rgb& c, const char* key, const SourceLoc& where, const std::string& what,
              std::vector<Finding>& findings) {
  const std::string k = key;
  return {clamp_factor(c.r, 0.0, 1.0, (k + "[0]").c_str(), where, what, findings),
          clamp_factor(c.g, 0.0, 1.0, (k + "[1]").c_str(), where, what, findings),
          clamp_factor(c.b, 0.0, 1.0, (k + "[2]").c_str(), where, what, findings)};
}

// Checks an extras value: present values must be finite and in [lo, hi].
Status check_extra(const std::optional<double>& v, double lo, double hi, const char* key,
                   const SourceLoc& where, const std::string& what) {
  if (!v) return Ok{};
  if (std::isfinite(*v) && *v >= lo && *v <= hi) return Ok{};
  return Error{where, what + ": extras.gonio." + key + " = " + format_number(*v) + " must lie in " +
                          format_number(lo) + ".." + format_number(hi)};
}

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

double luminance(const Rgb& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

namespace {

// A volume preset's sheet form (extras.gonio.volume_form "sheet"): the
// tabulated BSDF of its sheet at its thickness (sim::sheet_bsdf, 50,000
// photons per incidence, seed 3: ~1 s of CPU once per preset and process).
sim::Material sheet_form(const sim::MaterialPreset& p) {
  static std::mutex mutex;
  static std::map<std::string, std::shared_ptr<const sim::TabulatedBsdf>> tables;
  std::shared_ptr<const sim::TabulatedBsdf> table;
  {
    std::lock_guard<std::mutex> lock(mutex);
    if (auto it = tables.find(p.name); it != tables.end()) table = it->second;
  }
  if (!table) {
    sim::SlabMedium medium;
    medium.scattering_per_m = p.material.scattering_per_m;
    medium.absorption_per_m = p.material.attenuation_per_m;
    medium.g = p.material.scattering_g;
    medium.ior = p.material.ior;
    medium.thickness_m = p.thickness_m;
    auto built = std::make_shared<sim::TabulatedBsdf>(sim::sheet_bsdf(medium, 50000, 3));
    built->name = p.name + " (sheet form)";
    std::lock_guard<std::mutex> lock(mutex);
    table = tables.emplace(p.name, std::move(built)).first->second;
  }
  sim::Material m;
  m.tabulated = 1.0;
  m.table = std::move(table);
  return m;
}

}  // namespace

Result<sim::Material> map_material(const GltfMaterial& in, const MaterialExtras& x,
                                   const SourceLoc& where, const std::string& what,
                                   std::vector<Finding>& findings,
                                   std::shared_ptr<const sim::TabulatedBsdf> table) {
  // Extras are checked first: a typo there is the user's explicit intent gone
  // wrong and must stop the load.
  struct Range {
    const std::optional<double>* v;
    double lo, hi;
    const char* key;
  };
  const Range ranges[] = {
      {&x.kd, 0, 1, "kd"},
      {&x.ks, 0, 1, "ks"},
      {&x.diffuse_transmit, 0, 1, "diffuse_transmit"},
      {&x.mirror, 0, 1, "mirror"},
      {&x.dielectric, 0, 1, "dielectric"},
      {&x.mx, 1e-4, 10, "mx"},
      {&x.my, 1e-4, 10, "my"},
      {&x.f0, 0, 1, "f0"},
      {&x.ior, 1, 10, "ior"},
      {&x.attenuation_per_m, 0, 1e9, "attenuation_per_m"},
      {&x.reflectance, 0, 1, "reflectance"},
      {&x.diffuse_reflectance, 0, 1, "diffuse_reflectance"},
      {&x.transmittance, 0, 1, "transmittance"},
      {&x.diffusion, 0, 1, "diffusion"},
      {&x.luminance_cd_m2, 0, kInf, "luminance_cd_m2"},
      {&x.scattering_per_m, 0, 1e9, "scattering_per_m"},
      {&x.scattering_g, -0.999, 0.999, "scattering_g"},
      {&x.tabulated, 0, 1, "tabulated"},
  };
  for (const Range& r : ranges)
    if (Status s = check_extra(*r.v, r.lo, r.hi, r.key, where, what); !s.ok()) return s.error();
  if (x.has_lobe_weights() && x.has_datasheet())
    return Error{where, what + ": extras.gonio mixes lobe weights (kd, ks, diffuse_transmit, "
                               "mirror, dielectric) with datasheet values (reflectance, "
                               "transmittance, ...); use one form"};
  if (x.has_datasheet() && (x.f0 || x.attenuation_per_m))
    return Error{where, what + ": extras.gonio datasheet values take only ior, mx and my as "
                               "further parameters, not f0 or attenuation_per_m"};
  if (x.preset && (x.has_lobe_weights() || x.has_datasheet() || x.abg_reflect || x.abg_transmit || x.bsdf_file ||
                   x.mx || x.my || x.f0 || x.ior || x.attenuation_per_m || x.scattering_per_m || x.scattering_g))
    return Error{where, what + ": extras.gonio.preset stands alone: a preset's lobes and medium are its own "
                               "(only spectra, luminance, incidence tables and glossy_compensation may join it)"};

  sim::Material out;
  out.name = in.name;

  const Rgb base = clamp_rgb(in.base_color, "baseColorFactor", where, what, findings);
  const double metallic = clamp_factor(in.metallic, 0, 1, "metallicFactor", where, what, findings);
  const double roughness =
      clamp_factor(in.roughness, 0, 1, "roughnessFactor", where, what, findings);
  const double t = clamp_factor(in.transmission, 0, 1, "transmissionFactor", where, what, findings);
  const double dt = clamp_factor(in.diffuse_transmission, 0, 1, "diffuseTransmissionFactor", where,
                                 what, findings);
  const Rgb dt_color = clamp_rgb(in.diffuse_transmission_color, "diffuseTransmissionColorFactor",
                                 where, what, findings);
  const double spec = clamp_factor(in.specular, 0, 1, "specularFactor", where, what, findings);
  double ior = in.ior;
  if (!(std::isfinite(ior) && ior >= 1.0)) {
    findings.push_back({Severity::Warning, "material-factor-range",
                        what + ": ior = " + format_number(ior) + " is not >= 1, using 1.5", where});
    ior = 1.5;
  }

  const double rho = luminance(base);
  const double alpha = roughness * roughness;
  const double r0 = (ior - 1.0) / (ior + 1.0);
  const double f0_coat =
      std::min(1.0, r0 * r0 * std::max(0.0, luminance(in.specular_color))) * spec;

  const double specular = metallic * rho + (1.0 - metallic) * (1.0 - t) * f0_coat;
  const double base_rest = (1.0 - metallic) * (1.0 - t) * (1.0 - f0_coat);
  if (roughness < kMirrorRoughness) {
    out.mirror = specular;
  } else {
    out.glossy = specular;
    out.glossy_mx = out.glossy_my = alpha;
    out.glossy_f0 = 1.0;
  }
  out.dielectric = (1.0 - metallic) * t * rho;
  out.diffuse_transmit = base_rest * dt * luminance(dt_color);
  out.diffuse_reflect = base_rest * (1.0 - dt) * rho;
  out.ior = ior;

  if (in.has_volume) {
    const double d = in.attenuation_distance_m;
    const double c = luminance(clamp_rgb(in.attenuation_color, "attenuationColor", where, what,
                                         findings));
    if (!(d > 0.0)) {
      findings.push_back({Severity::Warning, "material-factor-range",
                          what + ": attenuationDistance must be > 0; no attenuation", where});
    } else if (std::isfinite(d) && c < 1.0) {
      out.attenuation_per_m = c > 0.0 ? -std::log(c) / d : 1e9;
    }
  }
  if (t > 0.0 && !x.has_lobe_weights() && !x.has_datasheet() &&
      !(in.has_volume && in.thickness_m > 0.0)) {
    findings.push_back(
        {Severity::Warning, "thin-walled-transmission",
         what + ": KHR_materials_transmission without a KHR_materials_volume thickness is "
                "thin-walled in glTF; Gonio traces it as a refracting interface, so the mesh "
                "must be a closed volume",
         where});
  }

  if (x.has_lobe_weights()) {
    out.diffuse_reflect = x.kd.value_or(0.0);
    out.glossy = x.ks.value_or(0.0);
    out.diffuse_transmit = x.diffuse_transmit.value_or(0.0);
    out.mirror = x.mirror.value_or(0.0);
    out.dielectric = x.dielectric.value_or(0.0);
    if (out.glossy > 0.0 && !(x.mx || x.my) && roughness < kMirrorRoughness) {
      // The derived lobe was a mirror; give the glossy lobe the file's roughness.
      out.glossy_mx = out.glossy_my = std::max(alpha, 1e-4);
    }
  } else if (x.has_datasheet()) {
    const double refl = x.reflectance.value_or(x.diffuse_reflectance.value_or(0.0));
    const double diffuse_refl = x.diffuse_reflectance.value_or(refl);
    const double trans = x.transmittance.value_or(0.0);
    const double diffusion = x.diffusion.value_or(1.0);
    if (diffuse_refl > refl)
      return Error{where, what + ": extras.gonio.diffuse_reflectance " +
                              format_number(diffuse_refl) + " exceeds reflectance " +
                              format_number(refl)};
    if (refl + trans > 1.0 + 1e-12)
      return Error{where, what + ": extras.gonio reflectance + transmittance = " +
                              format_number(refl + trans) + " exceeds 1"};
    out.diffuse_reflect = diffuse_refl;
    out.mirror = 0.0;
    out.glossy = 0.0;
    if (x.mx || x.my) {
      out.glossy = refl - diffuse_refl;
      out.glossy_f0 = 1.0;
    } else {
      out.mirror = refl - diffuse_refl;
    }
    out.diffuse_transmit = trans * diffusion;
    out.dielectric = trans * (1.0 - diffusion);
  }
  if (x.preset) {
    const std::string name = out.name;
    out = sim::find_preset(*x.preset)->material;
    out.name = name;
    if (x.volume_form && *x.volume_form == "sheet") {
      out = sheet_form(*sim::find_preset(*x.preset));
      out.name = name;
    }
  }
  if (x.abg_reflect) out.abg_reflect = *x.abg_reflect;
  if (x.abg_transmit) out.abg_transmit = *x.abg_transmit;
  if (x.scattering_per_m) out.scattering_per_m = *x.scattering_per_m;
  if (x.scattering_g) out.scattering_g = *x.scattering_g;
  if (x.glossy_compensation) out.glossy_compensation = *x.glossy_compensation;
  if (table) {
    // The measured BSDF is the surface, unless the extras give lobes beside it.
    if (!x.has_lobe_weights() && !x.has_datasheet() && !x.preset) {
      out.diffuse_reflect = out.diffuse_transmit = out.mirror = out.glossy = out.dielectric = 0.0;
    }
    out.table = std::move(table);
    out.tabulated = x.tabulated.value_or(1.0);
  }
  if (x.mx) out.glossy_mx = *x.mx;
  if (x.my) out.glossy_my = *x.my;
  if (x.mx && !x.my) out.glossy_my = *x.mx;
  if (x.my && !x.mx) out.glossy_mx = *x.my;
  if (x.f0) out.glossy_f0 = *x.f0;
  if (x.ior) out.ior = *x.ior;
  if (x.attenuation_per_m) out.attenuation_per_m = *x.attenuation_per_m;
  if (x.spectral_reflectance) out.spectral_reflectance = *x.spectral_reflectance;
  if (x.spectral_transmittance) out.spectral_transmittance = *x.spectral_transmittance;
  if (x.ior_nm) out.ior_nm = *x.ior_nm;
  if (x.abbe_number) out.abbe_number = *x.abbe_number;

  // Incidence tables, per lobe in sim::Lobe order from DiffuseReflect
  // (Material::over_incidence). R(θ) and T(θ) scale the reflection and
  // transmission lobes by R(θ) over their weight at normal incidence.
  enum : std::size_t { kDr, kDt, kMirror, kGlossy, kDielectric, kAbg, kAbgT, kTabulated };
  const double weights[] = {out.diffuse_reflect, out.diffuse_transmit, out.mirror,          out.glossy,
                            out.dielectric,      out.abg_reflect.tis,  out.abg_transmit.tis, out.tabulated};
  const std::pair<const std::optional<sim::IncidenceTable>*, std::vector<std::size_t>> groups[] = {
      {&x.reflectance_over_angle, {kDr, kMirror, kGlossy, kAbg}},
      {&x.transmittance_over_angle, {kDt, kDielectric, kAbgT}}};
  for (const auto& [table_of, lobes] : groups) {
    if (!*table_of) continue;
    double sum = 0.0;
    for (std::size_t l : lobes) sum += weights[l];
    const char* key = table_of == &x.reflectance_over_angle ? "reflectance_over_angle" : "transmittance_over_angle";
    if (!(sum > 0.0))
      return Error{where, what + ": extras.gonio." + key + " needs lobes to scale, and the material has none"};
    sim::IncidenceTable factor = **table_of;
    for (double& v : factor.factor) v /= sum;
    for (std::size_t l : lobes) out.over_incidence[l] = factor;
  }
  for (const auto& [name, table_of_lobe] : x.lobe_over_angle) {
    const std::pair<const char*, std::size_t> names[] = {
        {"diffuse_reflect", kDr}, {"diffuse_transmit", kDt}, {"mirror", kMirror}, {"glossy", kGlossy},
        {"dielectric", kDielectric}, {"abg", kAbg}, {"abg_transmit", kAbgT}, {"tabulated", kTabulated}};
    for (const auto& [n, l] : names)
      if (name == n) out.over_incidence[l] = table_of_lobe;
  }

  const double total = out.total();
  if (total > 1.0 + 1e-9)
    return Error{where, what + ": extras.gonio lobe weights sum to " + format_number(total) +
                            ", more than 1 (a surface cannot scatter more than it receives)"};
  // Over incidence the weights are linear between the tables' angles: their
  // sum is largest at one of them.
  for (const sim::IncidenceTable& angles : out.over_incidence)
    for (double a : angles.theta_deg) {
      const double c = std::cos(a * std::numbers::pi / 180.0);
      double sum = 0.0;
      for (std::size_t l = 0; l < out.over_incidence.size(); ++l) sum += weights[l] * out.over_incidence[l].at(c);
      if (sum > 1.0 + 1e-9)
        return Error{where, what + ": extras.gonio: at " + format_number(a) + " degrees of incidence the lobes scatter " +
                                format_number(sum) + ", more than 1"};
    }
  return out;
}

double emissive_luminance_cd_m2(const GltfMaterial& m, const MaterialExtras& extras) {
  if (extras.luminance_cd_m2) return *extras.luminance_cd_m2;
  const double strength = std::isfinite(m.emissive_strength) ? std::max(0.0, m.emissive_strength) : 0.0;
  const Rgb e{std::clamp(m.emissive.r, 0.0, 1.0), std::clamp(m.emissive.g, 0.0, 1.0),
              std::clamp(m.emissive.b, 0.0, 1.0)};
  return strength * luminance(e);
}

}  // namespace gonio::io
