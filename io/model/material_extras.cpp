#include "io/model/material_extras.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <tuple>
#include <utility>

#include "photometry/format.h"
#include "sim/bsdfs/abg_integral.h"
#include "sim/bsdfs/library.h"

namespace gonio::io {

using nlohmann::json;

namespace {

Error error_at(const SourceLoc& where, std::string message) { return Error{where, std::move(message)}; }

}  // namespace

Result<std::optional<double>> extras_number(const json& obj, const char* key, const SourceLoc& where,
                                            const std::string& what) {
  if (!obj.is_object()) return std::optional<double>();
  auto it = obj.find(key);
  if (it == obj.end()) return std::optional<double>();
  if (!it->is_number()) return error_at(where, what + ": '" + key + "' must be a number");
  const double v = it->get<double>();
  if (!std::isfinite(v)) return error_at(where, what + ": '" + key + "' is not finite");
  return std::optional<double>(v);
}

namespace {

// A spectrum: {"wavelengths_nm": [...], "values": [...]} or, where allowed,
// {"blackbody_k": T} (Planck's law, 360–830 nm in 1 nm).
Result<photometry::SampledSpectrum> spectrum_object(const json& j, const SourceLoc& where, const std::string& what,
                                                    double max_value, bool allow_blackbody) {
  constexpr std::size_t kMaxSamples = 100000;
  const auto fail = [&](const std::string& m) { return error_at(where, m); };
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
      return fail(what + ": '" + key + "' is missing" + (allow_blackbody ? " (or give blackbody_k)" : ""));
    if (!it->is_array() || it->size() > kMaxSamples)
      return fail(what + "." + key + " must be an array of at most " + std::to_string(kMaxSamples) + " numbers");
    for (std::size_t i = 0; i < it->size(); ++i) {
      const json& v = (*it)[i];
      if (!v.is_number()) return fail(what + "." + key + "[" + std::to_string(i) + "] is not a number");
      out->push_back(v.get<double>());
    }
  }
  if (Status st = photometry::validate_spectrum(s, max_value); !st.ok()) return fail(what + ": " + st.error().message);
  return s;
}

// {"angles_deg": [...], "values": [...]}: angles increasing within 0..90,
// values within 0..max_value.
Result<sim::IncidenceTable> incidence_table(const json& j, const SourceLoc& where, const std::string& what,
                                            double max_value) {
  const auto fail = [&](const std::string& m) { return error_at(where, m); };
  if (!j.is_object()) return fail(what + " must be an object with angles_deg and values");
  sim::IncidenceTable t;
  const std::pair<const char*, std::vector<double>*> arrays[] = {{"angles_deg", &t.theta_deg}, {"values", &t.factor}};
  for (const auto& [key, out] : arrays) {
    auto it = j.find(key);
    if (it == j.end() || !it->is_array() || it->empty() || it->size() > 1000)
      return fail(what + "." + key + " must be an array of 1 to 1000 numbers");
    for (std::size_t i = 0; i < it->size(); ++i) {
      if (!(*it)[i].is_number()) return fail(what + "." + key + "[" + std::to_string(i) + "] is not a number");
      out->push_back((*it)[i].get<double>());
    }
  }
  if (t.theta_deg.size() != t.factor.size()) return fail(what + ": angles_deg and values differ in length");
  for (std::size_t i = 0; i < t.theta_deg.size(); ++i) {
    if (!(t.theta_deg[i] >= 0.0 && t.theta_deg[i] <= 90.0) || (i > 0 && !(t.theta_deg[i] > t.theta_deg[i - 1])))
      return fail(what + ".angles_deg must increase within 0..90");
    if (!(t.factor[i] >= 0.0 && t.factor[i] <= max_value))
      return fail(what + ".values[" + std::to_string(i) + "] = " + format_number(t.factor[i]) + " must lie in 0.." +
                  format_number(max_value));
  }
  return t;
}

Result<sim::AbgScatter> abg_object(const json& j, const SourceLoc& where, const std::string& what) {
  const auto fail = [&](const std::string& m) { return error_at(where, m); };
  if (!j.is_object()) return fail(what + " must be an object with B, g and tis or A");
  for (const auto& item : j.items()) {
    const std::string& key = item.key();
    if (key != "A" && key != "B" && key != "g" && key != "tis") return fail(what + "." + key + " is not A, B, g or tis");
  }
  Result<std::optional<double>> a = extras_number(j, "A", where, what);
  Result<std::optional<double>> b = extras_number(j, "B", where, what);
  Result<std::optional<double>> g = extras_number(j, "g", where, what);
  Result<std::optional<double>> tis = extras_number(j, "tis", where, what);
  for (const auto* r : {&a, &b, &g, &tis})
    if (!r->ok()) return r->error();
  if (!*b || !*g) return fail(what + ": B and g are needed");
  if (!(**b > 0.0 && **b <= 1e6)) return fail(what + ".B = " + format_number(**b) + " must lie in (0, 1e6]");
  if (!(**g >= 0.0 && **g <= 6.0)) return fail(what + ".g = " + format_number(**g) + " must lie in 0..6");
  if (a->has_value() == tis->has_value()) return fail(what + ": give either tis or A");
  sim::AbgScatter s;
  s.b = **b;
  s.g = **g;
  s.tis = *tis ? **tis : **a * sim::abg_i0(s.b, s.g);
  if (!(s.tis >= 0.0 && s.tis <= 1.0))
    return fail(what + ": the total integrated scatter " + format_number(s.tis) + (a->has_value() ? " (A · I0)" : "") +
                " must lie in 0..1");
  return s;
}

}  // namespace

Result<sim::EmitterSpectrum> read_emitter_spectrum(const json& obj, const SourceLoc& where, const std::string& what) {
  sim::EmitterSpectrum out;
  if (!obj.is_object()) return out;
  auto it = obj.find("spectrum");
  if (it == obj.end()) return out;
  const std::string w = what + " extras.gonio.spectrum";
  const auto fail = [&](const std::string& m) { return error_at(where, m); };
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

Result<MaterialExtras> read_material_extras(const json& gj, const SourceLoc& where, const std::string& what,
                                            std::vector<Finding>& findings) {
  MaterialExtras x;
  const auto fail = [&](const std::string& m) { return error_at(where, m); };
  if (!gj.is_object()) return fail(what + ": extras.gonio must be an object");
  static const std::initializer_list<const char*> known = {
      "kd", "ks", "mx", "my", "f0", "diffuse_transmit", "mirror", "dielectric", "ior", "attenuation_per_m",
      "reflectance", "diffuse_reflectance", "transmittance", "diffusion", "luminance_cd_m2", "spectrum",
      "spectral_reflectance", "spectral_transmittance", "ior_nm", "abbe_number", "preset", "abg", "abg_transmit",
      "scattering_per_m", "scattering_g", "bsdf_file", "tabulated", "reflectance_over_angle",
      "transmittance_over_angle", "lobe_over_angle", "glossy_compensation", "volume_form"};
  for (const auto& item : gj.items()) {
    const std::string& key = item.key();  // not a structured binding: clang 14 (fuzz build) cannot capture one
    if (std::none_of(known.begin(), known.end(), [&](const char* k) { return key == k; }))
      findings.push_back({Severity::Warning, "unknown-extras-key",
                          what + ": extras.gonio." + key + " is not a Gonio parameter here; ignored", where});
  }
  const std::string w = what + " extras.gonio";
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
      {"scattering_per_m", &x.scattering_per_m},
      {"scattering_g", &x.scattering_g},
      {"tabulated", &x.tabulated},
  };
  for (const auto& [key, target] : keys) {
    Result<std::optional<double>> v = extras_number(gj, key, where, w);
    if (!v.ok()) return v.error();
    *target = *v;
  }
  Result<std::optional<double>> abbe = extras_number(gj, "abbe_number", where, w);
  if (!abbe.ok()) return abbe.error();
  if (*abbe && !(**abbe > 0.0)) return fail(what + ": extras.gonio.abbe_number must be > 0");
  x.abbe_number = *abbe;
  const std::tuple<const char*, std::optional<photometry::SampledSpectrum>*, double> spectra[] = {
      {"spectral_reflectance", &x.spectral_reflectance, 1.0},
      {"spectral_transmittance", &x.spectral_transmittance, 1.0},
      {"ior_nm", &x.ior_nm, 1e300},
  };
  for (const auto& [key, target, max_value] : spectra) {
    auto it = gj.find(key);
    if (it == gj.end()) continue;
    Result<photometry::SampledSpectrum> s = spectrum_object(*it, where, what + " extras.gonio." + key, max_value, false);
    if (!s.ok()) return s.error();
    *target = std::move(*s);
  }
  if (x.ior_nm)
    for (std::size_t i = 0; i < x.ior_nm->values.size(); ++i)
      if (!(x.ior_nm->values[i] >= 1.0))
        return fail(what + ": extras.gonio.ior_nm: value " + std::to_string(i) + " (" +
                    format_number(x.ior_nm->values[i]) + ") must be >= 1");
  Result<sim::EmitterSpectrum> es = read_emitter_spectrum(gj, where, what);
  if (!es.ok()) return es.error();
  x.spectrum = std::move(*es);

  if (auto it = gj.find("preset"); it != gj.end()) {
    if (!it->is_string()) return fail(w + ": 'preset' must be a string");
    const std::string name = it->get<std::string>();
    if (!sim::find_preset(name)) {
      std::string names;
      for (const sim::MaterialPreset& p : sim::material_library()) names += (names.empty() ? "'" : ", '") + p.name + "'";
      return fail(w + ".preset '" + name + "' is not in the library (" + names + ")");
    }
    x.preset = name;
  }
  if (auto it = gj.find("volume_form"); it != gj.end()) {
    if (!it->is_string() || (it->get<std::string>() != "walk" && it->get<std::string>() != "sheet"))
      return fail(w + ": 'volume_form' must be \"walk\" or \"sheet\"");
    x.volume_form = it->get<std::string>();
    if (*x.volume_form == "sheet" && !(x.preset && sim::find_preset(*x.preset)->thickness_m > 0.0))
      return fail(w + ": volume_form \"sheet\" needs a volume preset (its medium and thickness), e.g. "
                      "\"opal PMMA 3 mm\"");
  }
  for (auto [key, target] : {std::pair{"abg", &x.abg_reflect}, std::pair{"abg_transmit", &x.abg_transmit}}) {
    auto it = gj.find(key);
    if (it == gj.end()) continue;
    Result<sim::AbgScatter> a = abg_object(*it, where, w + "." + key);
    if (!a.ok()) return a.error();
    *target = *a;
  }
  if (auto it = gj.find("bsdf_file"); it != gj.end()) {
    if (!it->is_string() || it->get<std::string>().empty()) return fail(w + ": 'bsdf_file' must be a file name");
    x.bsdf_file = it->get<std::string>();
  }
  if (x.tabulated && !x.bsdf_file) return fail(w + ": 'tabulated' weighs a bsdf_file, and there is none");
  for (auto [key, target] : {std::pair{"reflectance_over_angle", &x.reflectance_over_angle},
                             std::pair{"transmittance_over_angle", &x.transmittance_over_angle}}) {
    auto it = gj.find(key);
    if (it == gj.end()) continue;
    Result<sim::IncidenceTable> t = incidence_table(*it, where, w + "." + key, 1.0);
    if (!t.ok()) return t.error();
    *target = std::move(*t);
  }
  if (auto it = gj.find("lobe_over_angle"); it != gj.end()) {
    if (!it->is_object()) return fail(w + ".lobe_over_angle must be an object of lobes");
    static const char* lobes[] = {"diffuse_reflect", "diffuse_transmit", "mirror", "glossy",
                                  "dielectric",      "abg",              "abg_transmit", "tabulated"};
    for (const auto& item : it->items()) {
      const std::string& key = item.key();
      if (std::none_of(std::begin(lobes), std::end(lobes), [&](const char* l) { return key == l; }))
        return fail(w + ".lobe_over_angle." + key + " is not a lobe (diffuse_reflect, diffuse_transmit, mirror, "
                                                    "glossy, dielectric, abg, abg_transmit, tabulated)");
      Result<sim::IncidenceTable> t = incidence_table(item.value(), where, w + ".lobe_over_angle." + key, 1e3);
      if (!t.ok()) return t.error();
      x.lobe_over_angle.emplace_back(key, std::move(*t));
    }
  }
  if (auto it = gj.find("glossy_compensation"); it != gj.end()) {
    if (!it->is_boolean()) return fail(w + ": 'glossy_compensation' must be true or false");
    x.glossy_compensation = it->get<bool>();
  }
  return x;
}

}  // namespace gonio::io
