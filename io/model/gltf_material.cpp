#include "io/model/gltf_material.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <tuple>

#include "photometry/format.h"
#include "photometry/spectrum.h"

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

using nlohmann::json;

// A spectrum in extras.gonio: {"wavelengths_nm": [...], "values": [...]}
// or, where allowed, {"blackbody_k": T} (Planck's law, 360–830 nm in 1 nm).
Result<photometry::SampledSpectrum> spectrum_object(const json& j, const SourceLoc& where, const std::string& what,
                                                    double max_value, bool allow_blackbody) {
  constexpr std::size_t kMaxSamples = 100000;
  auto fail = [&](std::string message) { return Error{where, std::move(message)}; };
  if (!j.is_object()) return fail(what + " must be an object");
  if (allow_blackbody && j.contains("blackbody_k")) {
    if (j.contains("wavelengths_nm") || j.contains("values"))
      return fail(what + ": give either blackbody_k or wavelengths_nm and values, not both");
    Result<std::optional<double>> t = extras_number(j, "blackbody_k", where, what);
    if (!t.ok()) return t.error();
    if (!(**t >= 100.0 && **t <= 1e6)) return fail(what + ".blackbody_k = " + format_number(**t) + " must lie in [100, 1e6] K");
    return photometry::blackbody_spectrum(**t);
  }
  photometry::SampledSpectrum s;
  const std::pair<const char*, std::vector<double>*> arrays[] = {{"wavelengths_nm", &s.wavelengths_nm},
                                                                 {"values", &s.values}};
  for (const auto& [key, out] : arrays) {
    auto it = j.find(key);
    if (it == j.end())
      return fail(what + ": '" + key + "' is missing" +
                  (allow_blackbody ? " (or give blackbody_k)" : ""));
    if (!it->is_array() || it->size() > kMaxSamples)
      return fail(what + "." + key + " must be an array of at most " + std::to_string(kMaxSamples) + " numbers");
    for (std::size_t i = 0; i < it->size(); ++i) {
      const json& v = (*it)[i];
      if (!v.is_number()) return fail(what + "." + key + "[" + std::to_string(i) + "] is not a number");
      out->push_back(v.get<double>());
    }
  }
  if (Status st = photometry::validate_spectrum(s, max_value); !st.ok())
    return fail(what + ": " + st.error().message);
  return s;
}

Result<std::optional<photometry::SampledSpectrum>> spectrum_key(const json& obj, const char* key,
                                                                const SourceLoc& where, const std::string& what,
                                                                double max_value) {
  auto it = obj.find(key);
  if (it == obj.end()) return std::optional<photometry::SampledSpectrum>();
  Result<photometry::SampledSpectrum> s =
      spectrum_object(*it, where, what + " extras.gonio." + key, max_value, false);
  if (!s.ok()) return s.error();
  return std::optional<photometry::SampledSpectrum>(std::move(*s));
}

}  // namespace

Result<std::optional<double>> extras_number(const json& obj, const char* key, const SourceLoc& where,
                                            const std::string& what) {
  if (!obj.is_object()) return std::optional<double>();
  auto it = obj.find(key);
  if (it == obj.end()) return std::optional<double>();
  if (!it->is_number()) return Error{where, what + ": '" + key + "' must be a number"};
  const double v = it->get<double>();
  if (!std::isfinite(v)) return Error{where, what + ": '" + key + "' is not finite"};
  return std::optional<double>(v);
}

Result<sim::EmitterSpectrum> read_emitter_spectrum(const json& obj, const SourceLoc& where, const std::string& what) {
  auto fail = [&](std::string message) { return Error{where, std::move(message)}; };
  sim::EmitterSpectrum out;
  auto it = obj.find("spectrum");
  if (it == obj.end()) return out;
  const std::string w = what + " extras.gonio.spectrum";
  if (!it->is_object()) return fail(w + " must be an object");
  if (auto og = it->find("over_gamma"); og != it->end()) {
    if (it->size() != 1) return fail(w + ": over_gamma stands alone");
    if (!og->is_array() || og->empty() || og->size() > 1000)
      return fail(w + ".over_gamma must be an array of 1 to 1000 entries");
    for (std::size_t i = 0; i < og->size(); ++i) {
      const std::string wi = w + ".over_gamma[" + std::to_string(i) + "]";
      const json& entry = (*og)[i];
      Result<std::optional<double>> g = extras_number(entry, "gamma_deg", where, wi);
      if (!g.ok()) return g.error();
      if (!*g) return fail(wi + ": 'gamma_deg' is missing");
      json rest = entry;
      if (rest.is_object()) rest.erase("gamma_deg");
      Result<photometry::SampledSpectrum> s = spectrum_object(rest, where, wi, 1e300, true);
      if (!s.ok()) return s.error();
      out.over_gamma.push_back({**g, std::move(*s)});
    }
  } else {
    Result<photometry::SampledSpectrum> s = spectrum_object(*it, where, w, 1e300, true);
    if (!s.ok()) return s.error();
    out.over_gamma.push_back({0.0, std::move(*s)});
  }
  if (Status st = sim::validate_emitter_spectrum(out); !st.ok()) return fail(w + ": " + st.error().message);
  return out;
}

Result<MaterialExtrasRead> read_material_extras(const json& gj, const SourceLoc& where, const std::string& what,
                                                std::vector<Finding>& findings) {
  auto fail = [&](std::string message) { return Error{where, std::move(message)}; };
  if (!gj.is_object()) return fail(what + ": extras.gonio must be an object");
  static const char* const known[] = {
      "kd", "ks", "mx", "my", "f0", "diffuse_transmit", "mirror", "dielectric", "ior",
      "attenuation_per_m", "reflectance", "diffuse_reflectance", "transmittance", "diffusion",
      "luminance_cd_m2", "spectrum", "spectral_reflectance", "spectral_transmittance", "ior_nm",
      "abbe_number"};
  for (const auto& item : gj.items()) {
    const std::string& key = item.key();  // not a structured binding: clang 14 (fuzz build) cannot capture one
    if (std::none_of(std::begin(known), std::end(known), [&](const char* k) { return key == k; }))
      findings.push_back({Severity::Warning, "unknown-extras-key",
                          what + ": extras.gonio." + key + " is not a Gonio parameter here; ignored", where});
  }
  MaterialExtrasRead out;
  MaterialExtras& x = out.extras;
  const std::pair<const char*, std::optional<double>*> keys[] = {
      {"kd", &x.kd},
      {"ks", &x.ks},
      {"mx", &x.mx},
      {"my", &x.my},
      {"f0", &x.f0},
      {"diffuse_transmit", &x.diffuse_transmit},
      {"mirror", &x.mirror},
      {"dielectric", &x.dielectric},
      {"ior", &x.ior},
      {"attenuation_per_m", &x.attenuation_per_m},
      {"reflectance", &x.reflectance},
      {"diffuse_reflectance", &x.diffuse_reflectance},
      {"transmittance", &x.transmittance},
      {"diffusion", &x.diffusion},
      {"luminance_cd_m2", &x.luminance_cd_m2},
  };
  for (const auto& [key, target] : keys) {
    Result<std::optional<double>> v = extras_number(gj, key, where, what + " extras.gonio");
    if (!v.ok()) return v.error();
    *target = *v;
  }
  Result<std::optional<double>> abbe = extras_number(gj, "abbe_number", where, what + " extras.gonio");
  if (!abbe.ok()) return abbe.error();
  if (*abbe && !(**abbe > 0.0)) return fail(what + ": extras.gonio.abbe_number must be > 0");
  x.abbe_number = *abbe;
  const std::tuple<const char*, std::optional<photometry::SampledSpectrum>*, double> spectra[] = {
      {"spectral_reflectance", &x.spectral_reflectance, 1.0},
      {"spectral_transmittance", &x.spectral_transmittance, 1.0},
      {"ior_nm", &x.ior_nm, 1e300},
  };
  for (const auto& [key, target, max_value] : spectra) {
    Result<std::optional<photometry::SampledSpectrum>> v = spectrum_key(gj, key, where, what, max_value);
    if (!v.ok()) return v.error();
    *target = std::move(*v);
  }
  if (x.ior_nm)
    for (std::size_t i = 0; i < x.ior_nm->values.size(); ++i)
      if (!(x.ior_nm->values[i] >= 1.0))
        return fail(what + ": extras.gonio.ior_nm: value " + std::to_string(i) + " (" +
                    format_number(x.ior_nm->values[i]) + ") must be >= 1");
  Result<sim::EmitterSpectrum> es = read_emitter_spectrum(gj, where, what);
  if (!es.ok()) return es.error();
  out.emitted_spectrum = std::move(*es);
  return out;
}

double luminance(const Rgb& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

Result<sim::Material> map_material(const GltfMaterial& in, const MaterialExtras& x,
                                   const SourceLoc& where, const std::string& what,
                                   std::vector<Finding>& findings) {
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

  const double total = out.total();
  if (total > 1.0 + 1e-9)
    return Error{where, what + ": extras.gonio lobe weights sum to " + format_number(total) +
                            ", more than 1 (a surface cannot scatter more than it receives)"};
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
