#include "sim/tracer/spectral.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "photometry/format.h"

namespace gonio::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A material spectrum outside its wavelengths holds its end values.
double held_at(const photometry::SampledSpectrum& s, double nm) {
  if (s.empty()) return 0.0;
  return s.at(std::clamp(nm, s.first_nm(), s.last_nm()));
}

Error spectral_error(const std::string& what, const Error& e) {
  return make_error(what + ": " + e.message);
}

}  // namespace

double ior_at(const Material& m, double wavelength_nm_) {
  if (!m.ior_nm.empty()) return held_at(m.ior_nm, wavelength_nm_);
  if (m.abbe_number > 0.0) {
    constexpr double kD = 587.56, kF = 486.13, kC = 656.27;  // Fraunhofer d, F, C lines [nm]
    const double b = (m.ior - 1.0) / (m.abbe_number * (1.0 / (kF * kF) - 1.0 / (kC * kC)));
    const double a = m.ior - b / (kD * kD);
    return a + b / (wavelength_nm_ * wavelength_nm_);
  }
  return m.ior;
}

Material at_wavelength(const Material& m, double nm) {
  Material r = m;
  r.spectral_reflectance = {};
  r.spectral_transmittance = {};
  r.ior_nm = {};
  r.abbe_number = 0.0;
  if (!m.spectral_reflectance.empty()) {
    const double rho = held_at(m.spectral_reflectance, nm);
    const double sum = m.diffuse_reflect + m.mirror + m.glossy + m.abg_reflect.tis;
    if (sum > 0.0) {
      const double f = rho / sum;
      r.diffuse_reflect *= f;
      r.mirror *= f;
      r.glossy *= f;
      r.abg_reflect.tis *= f;
    } else {
      r.diffuse_reflect = rho;
    }
  }
  if (!m.spectral_transmittance.empty()) {
    const double tau = held_at(m.spectral_transmittance, nm);
    const double sum = m.diffuse_transmit + m.dielectric + m.abg_transmit.tis;
    if (sum > 0.0) {
      const double f = tau / sum;
      r.diffuse_transmit *= f;
      r.dielectric *= f;
      r.abg_transmit.tis *= f;
    } else {
      r.diffuse_transmit = tau;
    }
  }
  r.ior = ior_at(m, nm);
  return r;
}

Status validate_spectral_material(const Material& m) {
  const std::string what = "material '" + m.name + "'";
  if (!m.spectral_reflectance.empty())
    if (Status s = photometry::validate_spectrum(m.spectral_reflectance, 1.0); !s.ok())
      return spectral_error(what + ": spectral_reflectance", s.error());
  if (!m.spectral_transmittance.empty())
    if (Status s = photometry::validate_spectrum(m.spectral_transmittance, 1.0); !s.ok())
      return spectral_error(what + ": spectral_transmittance", s.error());
  if (!m.ior_nm.empty()) {
    if (Status s = photometry::validate_spectrum(m.ior_nm); !s.ok())
      return spectral_error(what + ": ior_nm", s.error());
    for (std::size_t i = 0; i < m.ior_nm.values.size(); ++i)
      if (!(m.ior_nm.values[i] >= 1.0))
        return make_error(what + ": ior_nm value " + std::to_string(i) + " (" +
                          format_number(m.ior_nm.values[i]) + ") must be >= 1");
  }
  if (!std::isfinite(m.abbe_number) || m.abbe_number < 0.0)
    return make_error(what + ": abbe_number " + format_number(m.abbe_number) + " must be finite and >= 0");
  for (int k = 0; k < kWavelengthCount; ++k) {
    const Material a = at_wavelength(m, wavelength_nm(k));
    if (a.total() > 1.0 + 1e-9)
      return make_error(what + ": its weights sum to " + format_number(a.total()) + " > 1 at " +
                        format_number(wavelength_nm(k)) + " nm");
    if (!(a.ior >= 1.0))
      return make_error(what + ": refractive index " + format_number(a.ior) + " < 1 at " +
                        format_number(wavelength_nm(k)) + " nm");
  }
  return Ok{};
}

Result<WavelengthSampler> WavelengthSampler::create(const SceneDesc& scene) {
  WavelengthSampler w;
  for (int k = 0; k < kWavelengthCount; ++k) {
    const photometry::CmfValue c = photometry::cie1931_cmf_sample(k);
    if (c.y_bar > 0.0) {
      w.x_units_[static_cast<std::size_t>(k)] =
          static_cast<std::uint64_t>(std::llround(c.x_bar / c.y_bar * static_cast<double>(kColourUnits)));
      w.z_units_[static_cast<std::size_t>(k)] =
          static_cast<std::uint64_t>(std::llround(c.z_bar / c.y_bar * static_cast<double>(kColourUnits)));
    }
  }
  // Drawn wavelengths' bins: 1/(Km ȳ) W per lm in their own band.
  w.bin_radiant_.assign(kWavelengthCount, {});
  for (int k = 0; k < kWavelengthCount; ++k) {
    const double y_bar = photometry::cie1931_cmf_sample(k).y_bar;
    if (y_bar > 0.0)
      w.bin_radiant_[static_cast<std::size_t>(k)][static_cast<std::size_t>(k)] =
          1.0 / (photometry::kKm_lm_per_W * y_bar);
  }
  const auto make_table = [&w](double gamma_rad, const photometry::SampledSpectrum* s) {
    Table t;
    t.gamma_rad = gamma_rad;
    double sum = 0.0;
    std::array<double, kWavelengthCount> radiant{};
    for (int k = 0; k < kWavelengthCount; ++k) {
      const double power = s ? s->at(wavelength_nm(k)) : 1.0;
      radiant[static_cast<std::size_t>(k)] = power;
      sum += power * photometry::cie1931_cmf_sample(k).y_bar;
      t.cdf[static_cast<std::size_t>(k)] = sum;
    }
    // The table's bin: S(λ_k) / (Km Σ S ȳ) W per lm in band k.
    for (double& r : radiant) r /= photometry::kKm_lm_per_W * sum;
    t.bin = static_cast<std::uint32_t>(w.bin_radiant_.size());
    w.bin_radiant_.push_back(radiant);
    ++w.table_count_;
    for (double& c : t.cdf) c /= sum;
    t.cdf.back() = 1.0;
    t.x_per_y = t.z_per_y = 0.0;
    for (std::size_t k = 0; k < t.cdf.size(); ++k) {
      const double p = t.cdf[k] - (k > 0 ? t.cdf[k - 1] : 0.0);
      t.x_per_y += p * static_cast<double>(w.x_units_[k]) / static_cast<double>(kColourUnits);
      t.z_per_y += p * static_cast<double>(w.z_units_[k]) / static_cast<double>(kColourUnits);
    }
    return t;
  };
  for (std::size_t i = 0; i < scene.emitters.size(); ++i) {
    const Emitter& e = scene.emitters[i];
    PerEmitter pe;
    if (Status s = validate_emitter_spectrum(e.spectrum); !s.ok())
      return make_error("emitter " + std::to_string(i) + (e.name.empty() ? "" : " '" + e.name + "'") + ": " +
                        s.error().message);
    if (e.spectrum.empty()) pe.tables.push_back(make_table(0.0, nullptr));
    for (const EmitterSpectrum::AtGamma& a : e.spectrum.over_gamma)
      pe.tables.push_back(make_table(a.gamma_deg * kPi / 180.0, &a.spectrum));
    w.emitters_.push_back(std::move(pe));
  }
  return w;
}

int WavelengthSampler::draw(const Table& t, double u) const {
  const auto it = std::upper_bound(t.cdf.begin(), t.cdf.end(), u);
  return std::min(static_cast<int>(it - t.cdf.begin()), kWavelengthCount - 1);
}

namespace {
// The entries around γ and the weight of the upper one.
template <class Tables>
std::pair<std::size_t, double> bracket(const Tables& tables, double cos_gamma) {
  const double g = std::acos(std::clamp(cos_gamma, -1.0, 1.0));
  if (g <= tables.front().gamma_rad) return {0, 0.0};
  if (g >= tables.back().gamma_rad) return {tables.size() - 1, 0.0};
  std::size_t j = 0;
  while (j + 2 < tables.size() && g >= tables[j + 1].gamma_rad) ++j;
  return {j, (g - tables[j].gamma_rad) / (tables[j + 1].gamma_rad - tables[j].gamma_rad)};
}
}  // namespace

int WavelengthSampler::sample(std::uint32_t emitter, double cos_gamma, PhotonRandom& rng) const {
  const std::vector<Table>& tables = emitters_[emitter].tables;
  if (tables.size() == 1) return draw(tables[0], rng.uniform());
  const auto [j, t] = bracket(tables, cos_gamma);
  const std::size_t pick = t > 0.0 && rng.uniform() < t ? j + 1 : j;
  return draw(tables[pick], rng.uniform());
}

std::pair<std::uint64_t, std::uint64_t> WavelengthSampler::expected_units(std::uint32_t emitter,
                                                                          double cos_gamma) const {
  const std::vector<Table>& tables = emitters_[emitter].tables;
  double x = tables[0].x_per_y, z = tables[0].z_per_y;
  if (tables.size() > 1) {
    const auto [j, t] = bracket(tables, cos_gamma);
    x = tables[j].x_per_y;
    z = tables[j].z_per_y;
    if (t > 0.0) {
      x += t * (tables[j + 1].x_per_y - x);
      z += t * (tables[j + 1].z_per_y - z);
    }
  }
  const double u = static_cast<double>(kColourUnits);
  return {static_cast<std::uint64_t>(std::llround(x * u)), static_cast<std::uint64_t>(std::llround(z * u))};
}

WavelengthSampler::BinShare WavelengthSampler::bins(const PhotonColour& colour,
                                                    std::uint64_t power_units) const {
  BinShare b;
  b.units[0] = power_units;
  const std::vector<Table>& tables = emitters_[colour.emitter].tables;
  if (tables.size() == 1) {
    b.bin[0] = b.bin[1] = tables[0].bin;
    return b;
  }
  const auto [j, t] = bracket(tables, colour.cos_gamma);
  b.bin[0] = tables[j].bin;
  b.bin[1] = t > 0.0 ? tables[j + 1].bin : tables[j].bin;
  if (t > 0.0) {
    b.units[1] = static_cast<std::uint64_t>(std::llround(static_cast<double>(power_units) * t));
    b.units[1] = std::min(b.units[1], power_units);
    b.units[0] = power_units - b.units[1];
  }
  return b;
}

std::pair<std::uint64_t, std::uint64_t> WavelengthSampler::hero_units(const PhotonColour& colour) const {
  double x = 0.0, z = 0.0, sum = 0.0;
  for (int j = 0; j < kHeroCount; ++j) {
    const double w = colour.hero_weight[static_cast<std::size_t>(j)];
    if (w == 0.0 && j > 0) continue;
    const int k = hero_companion(colour.wavelength, j);
    const double q = w * pmf(colour.emitter, colour.cos_gamma, k);
    sum += q;
    x += q * static_cast<double>(x_units_[static_cast<std::size_t>(k)]);
    z += q * static_cast<double>(z_units_[static_cast<std::size_t>(k)]);
  }
  if (!(sum > 0.0)) {
    const auto k = static_cast<std::size_t>(colour.wavelength);
    return {x_units_[k], z_units_[k]};
  }
  return {static_cast<std::uint64_t>(std::llround(x / sum)), static_cast<std::uint64_t>(std::llround(z / sum))};
}

double WavelengthSampler::pmf(std::uint32_t emitter, double cos_gamma, int k) const {
  const std::vector<Table>& tables = emitters_[emitter].tables;
  const auto p = [k](const Table& t) {
    const auto i = static_cast<std::size_t>(k);
    return t.cdf[i] - (k > 0 ? t.cdf[i - 1] : 0.0);
  };
  if (tables.size() == 1) return p(tables[0]);
  const auto [j, t] = bracket(tables, cos_gamma);
  return t > 0.0 ? (1.0 - t) * p(tables[j]) + t * p(tables[j + 1]) : p(tables[j]);
}

}  // namespace gonio::sim
