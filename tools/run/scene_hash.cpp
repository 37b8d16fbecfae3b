#include "tools/run/scene_hash.h"

#include "io/support/content_hash.h"

namespace gonio::cli {

std::string scene_hash(const sim::SceneDesc& scene) {
  io::ContentHash h;
  h.value(scene.materials.size());
  for (const sim::Material& m : scene.materials) {
    for (double v : {m.diffuse_reflect, m.diffuse_transmit, m.mirror, m.glossy, m.glossy_mx,
                     m.glossy_my, m.glossy_f0, m.dielectric, m.ior, m.attenuation_per_m})
      h.value(v);
  }
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
  for (const sim::Emitter& e : scene.emitters) {
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
  }
  h.vec(scene.frame.c0);
  h.vec(scene.frame.c90);
  h.vec(scene.frame.up);
  return h.hex();
}

}  // namespace gonio::cli
