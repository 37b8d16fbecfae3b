#include "design/part_mesh.h"

#include <utility>

#include "sim/scene.h"

namespace gonio::design {

std::uint32_t add_vertex(io::CadSurface& s, const Vec3& position, const Vec3& normal) {
  s.positions.push_back(sim::to_float(position));
  s.normals.push_back(sim::to_float(normal));
  return static_cast<std::uint32_t>(s.positions.size() - 1);
}

void add_triangle(io::CadSurface& s, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  if (a == b || b == c || a == c) return;
  const Vec3 pa = sim::to_double(s.positions[a]), pb = sim::to_double(s.positions[b]), pc = sim::to_double(s.positions[c]);
  if (!(length(cross(pb - pa, pc - pa)) > 0.0)) return;  // no area
  const Vec3 n = sim::to_double(s.normals[a]) + sim::to_double(s.normals[b]) + sim::to_double(s.normals[c]);
  if (dot(cross(pb - pa, pc - pa), n) < 0.0) std::swap(b, c);
  s.indices.insert(s.indices.end(), {a, b, c});
}

void flip(io::CadSurface& s) {
  for (sim::Vec3f& n : s.normals) n = sim::Vec3f{-n.x, -n.y, -n.z};
  for (std::size_t i = 0; i + 2 < s.indices.size(); i += 3) std::swap(s.indices[i + 1], s.indices[i + 2]);
}

void append(io::CadSurface& s, const io::CadSurface& other) {
  const auto base = static_cast<std::uint32_t>(s.positions.size());
  s.positions.insert(s.positions.end(), other.positions.begin(), other.positions.end());
  s.normals.insert(s.normals.end(), other.normals.begin(), other.normals.end());
  for (std::uint32_t i : other.indices) s.indices.push_back(base + i);
}

}  // namespace gonio::design
