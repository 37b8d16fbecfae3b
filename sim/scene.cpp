#include "sim/scene.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>

#include "photometry/colour.h"
#include "photometry/format.h"

namespace gonio::sim {

double IncidenceTable::at(double cos_theta) const {
  if (theta_deg.empty()) return 1.0;
  const double theta = std::acos(std::clamp(cos_theta, 0.0, 1.0)) * (180.0 / std::numbers::pi);
  if (theta <= theta_deg.front()) return factor.front();
  if (theta >= theta_deg.back()) return factor.back();
  const auto it = std::upper_bound(theta_deg.begin(), theta_deg.end(), theta);
  const auto i = static_cast<std::size_t>(it - theta_deg.begin());
  const double t = (theta - theta_deg[i - 1]) / (theta_deg[i] - theta_deg[i - 1]);
  return (1.0 - t) * factor[i - 1] + t * factor[i];
}

Status validate_emitter_spectrum(const EmitterSpectrum& s) {
  for (std::size_t i = 0; i < s.over_gamma.size(); ++i) {
    const EmitterSpectrum::AtGamma& a = s.over_gamma[i];
    const std::string what = s.over_gamma.size() == 1 ? std::string("spectrum")
                                                       : "spectrum at entry " + std::to_string(i);
    if (!std::isfinite(a.gamma_deg) || a.gamma_deg < 0.0 || a.gamma_deg > 180.0)
      return make_error(what + ": gamma_deg " + format_number(a.gamma_deg) + " must lie in [0, 180]");
    if (i > 0 && !(a.gamma_deg > s.over_gamma[i - 1].gamma_deg))
      return make_error(what + ": gamma_deg " + format_number(a.gamma_deg) + " does not increase");
    if (Status st = photometry::validate_spectrum(a.spectrum); !st.ok()) return make_error(what + ": " + st.error().message);
    if (!(photometry::tristimulus(a.spectrum).Y > 0.0))
      return make_error(what + ": no power between 360 and 830 nm where the eye sees");
  }
  return Ok{};
}


std::size_t SceneDesc::unique_triangle_count() const {
  std::size_t n = 0;
  for (const Mesh& m : meshes) n += m.triangle_count();
  return n;
}

std::size_t SceneDesc::placed_triangle_count() const {
  std::size_t n = 0;
  for (const Mesh& m : meshes)
    if (!m.instanced) n += m.triangle_count();
  for (const Instance& i : instances)
    if (i.mesh < meshes.size()) n += meshes[i.mesh].triangle_count();
  return n;
}

void transform(Mesh& mesh, const Affine& map) {
  for (Vec3f& p : mesh.positions) p = to_float(map.point(to_double(p)));
  for (Vec3f& n : mesh.normals) n = to_float(normalize(map.normal(to_double(n))));
  for (Vec3f& t : mesh.tangents) t = to_float(normalize(map.linear(to_double(t))));
  if (map.determinant() < 0.0)
    for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3)
      std::swap(mesh.indices[i + 1], mesh.indices[i + 2]);
}

bool same_geometry(const SceneDesc& a, const SceneDesc& b) {
  if (a.meshes.size() != b.meshes.size() || a.instances.size() != b.instances.size()) return false;
  const auto same = [](const Vec3f& p, const Vec3f& q) { return p.x == q.x && p.y == q.y && p.z == q.z; };
  for (std::size_t m = 0; m < a.meshes.size(); ++m) {
    const Mesh& x = a.meshes[m];
    const Mesh& y = b.meshes[m];
    if (x.instanced != y.instanced || x.indices != y.indices || x.positions.size() != y.positions.size() ||
        !std::equal(x.positions.begin(), x.positions.end(), y.positions.begin(), same))
      return false;
  }
  for (std::size_t i = 0; i < a.instances.size(); ++i) {
    const Affine& x = a.instances[i].to_world;
    const Affine& y = b.instances[i].to_world;
    if (a.instances[i].mesh != b.instances[i].mesh || x.offset.x != y.offset.x || x.offset.y != y.offset.y ||
        x.offset.z != y.offset.z)
      return false;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        if (x.m[r][c] != y.m[r][c]) return false;
  }
  return true;
}

SceneDesc flattened(const SceneDesc& scene) {
  SceneDesc out;
  out.name = scene.name;
  out.materials = scene.materials;
  out.frame = scene.frame;
  std::vector<std::uint32_t> world(scene.meshes.size(), kNoInstance);   // world mesh → new mesh
  std::vector<std::vector<std::uint32_t>> of_mesh(scene.meshes.size());
  for (std::uint32_t i = 0; i < scene.instances.size(); ++i)
    if (scene.instances[i].mesh < scene.meshes.size()) of_mesh[scene.instances[i].mesh].push_back(i);
  std::vector<std::uint32_t> instance_mesh(scene.instances.size(), kNoInstance);
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    if (!mesh.instanced) {
      world[m] = static_cast<std::uint32_t>(out.meshes.size());
      out.meshes.push_back(mesh);
      continue;
    }
    for (std::uint32_t i : of_mesh[m]) {
      const Instance& inst = scene.instances[i];
      instance_mesh[i] = static_cast<std::uint32_t>(out.meshes.size());
      Mesh copy = mesh;
      transform(copy, inst.to_world);
      copy.instanced = false;
      copy.name = inst.name + "/" + mesh.name;
      out.meshes.push_back(std::move(copy));
    }
  }
  for (Emitter e : scene.emitters) {
    if (e.kind == Emitter::Kind::Area) {
      if (e.instance != kNoInstance && e.instance < instance_mesh.size())
        e.mesh = instance_mesh[e.instance];
      else if (e.mesh < world.size())
        e.mesh = world[e.mesh];
      e.instance = kNoInstance;
    }
    out.emitters.push_back(std::move(e));
  }
  return out;
}

}  // namespace gonio::sim
