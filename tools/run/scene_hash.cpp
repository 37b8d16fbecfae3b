#include "tools/run/scene_hash.h"

#include "io/support/content_hash.h"
#include "sim/bsdfs/tabulated_bsdf.h"

namespace gonio::app {
namespace {

void hash_spectrum(io::ContentHash& h, const photometry::SampledSpectrum& s) {
  h.values(s.wavelengths_nm);
  h.values(s.values);
}

// A measured BSDF as the tracer reads it: the basis and every row's values
// (the albedos and sampling tables are derived from them by finish()).
void hash_table(io::ContentHash& h, const sim::TabulatedBsdf* t) {
  h.value(t != nullptr);
  if (!t) return;
  h.value(static_cast<int>(t->basis.kind));
  h.values(t->basis.ring_theta_deg);
  h.value(t->basis.ring_phi_deg.size());
  for (const std::vector<double>& ring : t->basis.ring_phi_deg) h.values(ring);
  h.value(t->basis.square_n);
  for (const sim::TabulatedBsdf::Side* side : {&t->front, &t->back}) {
    h.value(side->rows.size());
    for (const sim::TabulatedBsdf::Row& row : side->rows) {
      h.value(row.theta_deg);
      h.values(row.reflect);
      h.values(row.transmit);
    }
  }
}

void hash_material(io::ContentHash& h, const sim::Material& m) {
  for (double v : {m.diffuse_reflect, m.diffuse_transmit, m.mirror, m.glossy, m.glossy_mx, m.glossy_my,
                   m.glossy_f0, m.dielectric, m.ior, m.attenuation_per_m, m.scattering_per_m, m.scattering_g,
                   m.abg_reflect.tis, m.abg_reflect.b, m.abg_reflect.g, m.abg_transmit.tis, m.abg_transmit.b,
                   m.abg_transmit.g, m.tabulated, m.abbe_number})
    h.value(v);
  h.value(m.glossy_compensation);
  hash_table(h, m.table.get());
  for (const sim::IncidenceTable& t : m.over_incidence) {
    h.values(t.theta_deg);
    h.values(t.factor);
  }
  hash_spectrum(h, m.spectral_reflectance);
  hash_spectrum(h, m.spectral_transmittance);
  hash_spectrum(h, m.ior_nm);
}

void hash_emitter(io::ContentHash& h, const sim::Emitter& e) {
  h.value(static_cast<int>(e.kind));
  h.value(e.flux_lm);
  h.vec(e.position);
  h.vec(e.frame.c0);
  h.vec(e.frame.c90);
  h.vec(e.frame.up);
  h.value(e.mesh);
  h.value(e.instance);
  h.value(e.two_sided);
  h.value(e.profile != nullptr);
  if (e.profile) {
    h.value(static_cast<int>(e.profile->type));
    h.value(static_cast<int>(e.profile->symmetry));
    h.values(e.profile->horizontal_deg);
    h.values(e.profile->vertical_deg);
    h.values(e.profile->candela);
  }
  h.value(e.rays != nullptr);
  if (e.rays) {
    h.values(e.rays->position_m);
    h.values(e.rays->direction);
    h.values(e.rays->flux_lm);
  }
  h.value(e.spectrum.over_gamma.size());
  for (const sim::EmitterSpectrum::AtGamma& g : e.spectrum.over_gamma) {
    h.value(g.gamma_deg);
    hash_spectrum(h, g.spectrum);
  }
}

}  // namespace

std::string scene_hash(const sim::SceneDesc& scene) {
  io::ContentHash h;
  h.value(scene.materials.size());
  for (const sim::Material& m : scene.materials) hash_material(h, m);
  h.value(scene.meshes.size());
  for (const sim::Mesh& m : scene.meshes) {
    h.values(m.positions);
    h.values(m.indices);
    h.values(m.normals);
    h.values(m.tangents);
    h.value(m.material);
    h.value(m.instanced);
  }
  h.value(scene.instances.size());
  for (const sim::Instance& i : scene.instances) {
    h.value(i.mesh);
    for (const auto& row : i.to_world.m)
      for (double v : row) h.value(v);
    h.vec(i.to_world.offset);
  }
  h.value(scene.emitters.size());
  for (const sim::Emitter& e : scene.emitters) hash_emitter(h, e);
  h.vec(scene.frame.c0);
  h.vec(scene.frame.c90);
  h.vec(scene.frame.up);
  return h.hex();
}

}  // namespace gonio::app
