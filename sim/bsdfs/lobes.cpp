#include "sim/bsdfs/lobes.h"

#include <algorithm>
#include <cmath>

#include "sim/bsdfs/tabulated_bsdf.h"
#include "sim/samplers/sampling.h"

namespace gonio::sim {

void prepare(Material& m) {
  auto t = std::make_shared<MaterialTables>();
  if (m.glossy > 0.0 && m.glossy_compensation && m.glossy_mx > 0.0 && m.glossy_my > 0.0) {
    t->glossy = glossy_energy(m.glossy_mx, m.glossy_my);
    t->glossy_kappa = multiple_scattering_factor(m.glossy_f0, t->glossy->e_avg);
  }
  if (m.abg_reflect.tis > 0.0 && abg_parameters_valid(m.abg_reflect.b, m.abg_reflect.g))
    t->abg_reflect = abg_table(m.abg_reflect.b, m.abg_reflect.g);
  if (m.abg_transmit.tis > 0.0 && abg_parameters_valid(m.abg_transmit.b, m.abg_transmit.g))
    t->abg_transmit = abg_table(m.abg_transmit.b, m.abg_transmit.g);
  m.tables = std::move(t);
}

bool is_delta(Lobe lobe) { return lobe == Lobe::Mirror || lobe == Lobe::Dielectric; }

namespace {

const AbgTable* abg_of(const Material& m, Lobe lobe) {
  if (!m.tables) return nullptr;
  return (lobe == Lobe::AbgTransmit ? m.tables->abg_transmit : m.tables->abg_reflect).get();
}

// The compensated glossy lobe's mixture: the second lobe's share of the
// samples, its energy κ (1 − E(wi)) (any share in (0, 1) would do).
double ms_share(const Material& m, const Vec3& wi) {
  if (!m.tables || !m.tables->glossy) return 0.0;
  return std::clamp(m.tables->glossy_kappa * (1.0 - m.tables->glossy->at(wi.z)), 0.0, 0.95);
}

}  // namespace

double lobe_evaluate(const Material& m, Lobe lobe, const Vec3& wi, const Vec3& wo, bool front) {
  if (!(wi.z > 0.0)) return 0.0;
  switch (lobe) {
    case Lobe::DiffuseReflect: return wo.z > 0.0 ? wo.z / std::numbers::pi : 0.0;
    case Lobe::DiffuseTransmit: return wo.z < 0.0 ? -wo.z / std::numbers::pi : 0.0;
    case Lobe::Glossy: {
      if (!(wo.z > 0.0)) return 0.0;
      double f = glossy_brdf(m, wi, wo) * wo.z;
      if (m.tables && m.tables->glossy) f += glossy_ms_evaluate(*m.tables->glossy, m.tables->glossy_kappa, wi, wo);
      return f;
    }
    case Lobe::AbgReflect:
    case Lobe::AbgTransmit: {
      const AbgTable* t = abg_of(m, lobe);
      return t ? abg_evaluate(*t, lobe == Lobe::AbgTransmit, wi, wo) : 0.0;
    }
    case Lobe::Tabulated: return m.table ? m.table->evaluate(front, wi, wo) : 0.0;
    case Lobe::Mirror:
    case Lobe::Dielectric:
    case Lobe::Absorb: break;
  }
  return 0.0;
}

double lobe_pdf(const Material& m, Lobe lobe, const Vec3& wi, const Vec3& wo, bool front) {
  if (!(wi.z > 0.0)) return 0.0;
  switch (lobe) {
    case Lobe::DiffuseReflect: return cosine_hemisphere_pdf(wo.z);
    case Lobe::DiffuseTransmit: return cosine_hemisphere_pdf(-wo.z);
    case Lobe::Glossy: {
      const double p = ms_share(m, wi);
      double pdf = (1.0 - p) * glossy_pdf(m, wi, wo);
      if (p > 0.0) pdf += p * glossy_ms_pdf(*m.tables->glossy, wo);
      return pdf;
    }
    case Lobe::AbgReflect:
    case Lobe::AbgTransmit: {
      const AbgTable* t = abg_of(m, lobe);
      return t ? abg_pdf(*t, lobe == Lobe::AbgTransmit, wi, wo) : 0.0;
    }
    case Lobe::Tabulated: {
      if (!m.table) return 0.0;
      const double a = m.table->albedo(front, wi);
      return a > 0.0 ? m.table->evaluate(front, wi, wo) / a : 0.0;
    }
    case Lobe::Mirror:
    case Lobe::Dielectric:
    case Lobe::Absorb: break;
  }
  return 0.0;
}

LobeSample lobe_sample(const Material& m, Lobe lobe, const Vec3& wi, PhotonRandom& rng, bool front) {
  LobeSample s;
  if (!(wi.z > 0.0)) return s;
  switch (lobe) {
    case Lobe::Absorb: return s;
    case Lobe::Mirror:
      s.wo = {-wi.x, -wi.y, wi.z};
      s.weight = 1.0;
      s.delta = true;
      return s;
    case Lobe::Dielectric: {
      const double eta_i = front ? 1.0 : m.ior, eta_t = front ? m.ior : 1.0;
      s.delta = true;
      s.weight = 1.0;
      const Vec3 n{0, 0, 1};
      if (rng.uniform() < fresnel_dielectric(wi.z, eta_i, eta_t) || !refract(wi, n, eta_i / eta_t, &s.wo))
        s.wo = {-wi.x, -wi.y, wi.z};
      return s;
    }
    case Lobe::DiffuseReflect:
    case Lobe::DiffuseTransmit:
      s.wo = sample_cosine_hemisphere(rng);
      if (lobe == Lobe::DiffuseTransmit) s.wo.z = -s.wo.z;
      break;
    case Lobe::Glossy: {
      const double p = ms_share(m, wi);
      if (p > 0.0 && rng.uniform() < p) {
        s.wo = sample_glossy_ms(*m.tables->glossy, rng);
      } else {
        s.wo = sample_glossy(m, wi, rng).wo;
      }
      break;
    }
    case Lobe::AbgReflect:
    case Lobe::AbgTransmit: {
      const AbgTable* t = abg_of(m, lobe);
      if (!t) return s;
      s.wo = sample_abg(*t, lobe == Lobe::AbgTransmit, wi, rng);
      break;
    }
    case Lobe::Tabulated: {
      if (!m.table) return s;
      double u[4];
      for (double& x : u) x = rng.uniform();
      s.wo = m.table->sample(front, wi, u[0], u[1], u[2], u[3]);
      break;
    }
  }
  s.pdf = lobe_pdf(m, lobe, wi, s.wo, front);
  s.weight = s.pdf > 0.0 ? lobe_evaluate(m, lobe, wi, s.wo, front) / s.pdf : 0.0;
  return s;
}

double lobe_albedo(const Material& m, Lobe lobe, const Vec3& wi, bool front) {
  if (!(wi.z > 0.0)) return 0.0;
  switch (lobe) {
    case Lobe::Absorb: return 0.0;
    case Lobe::DiffuseReflect:
    case Lobe::DiffuseTransmit:
    case Lobe::Mirror:
    case Lobe::Dielectric: return 1.0;
    case Lobe::Glossy: {
      double a = glossy_single_albedo(m.glossy_mx, m.glossy_my, m.glossy_f0, wi);
      if (m.tables && m.tables->glossy)
        a += m.tables->glossy_kappa * (1.0 - glossy_single_albedo(m.glossy_mx, m.glossy_my, 1.0, wi));
      return a;
    }
    case Lobe::AbgReflect:
    case Lobe::AbgTransmit: {
      const AbgTable* t = abg_of(m, lobe);
      return t ? abg_albedo(*t, wi) : 0.0;
    }
    case Lobe::Tabulated: return m.table ? m.table->albedo(front, wi) : 0.0;
  }
  return 0.0;
}

double weight_at(const Material& m, Lobe lobe, double cos_theta_i) {
  if (lobe == Lobe::Absorb) {
    double sum = 0.0;
    for (int k = 1; k < kLobeCount; ++k) sum += weight_at(m, static_cast<Lobe>(k), cos_theta_i);
    return 1.0 - sum;
  }
  const auto k = static_cast<std::size_t>(lobe) - 1;
  return lobe_weight(m, lobe) * m.over_incidence[k].at(cos_theta_i);
}

double surface_evaluate(const Material& m, const Vec3& wi, const Vec3& wo, bool front) {
  double f = 0.0;
  for (int k = 1; k < kLobeCount; ++k) {
    const auto lobe = static_cast<Lobe>(k);
    if (is_delta(lobe)) continue;
    const double w = weight_at(m, lobe, wi.z);
    if (w > 0.0) f += w * lobe_evaluate(m, lobe, wi, wo, front);
  }
  return f;
}

}  // namespace gonio::sim
