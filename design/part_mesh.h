// Small helpers that the design's part kinds share to build their meshes
// (design/trough.h, design/cover.h, design/facets.h): vertices with exact
// normals, triangles wound counter-clockwise seen from the side the normals
// face, and a surface turned to face the other way.
#pragma once

#include <cstdint>

#include "io/model/cad_model.h"
#include "photometry/vec3.h"

namespace gonio::design {

// Appends a vertex (position [m], unit normal) and returns its index.
std::uint32_t add_vertex(io::CadSurface& s, const Vec3& position, const Vec3& normal);

// Appends the triangle (a, b, c), wound counter-clockwise seen from the
// side its vertices' normals face (their sum); triangles without area are
// left out.
void add_triangle(io::CadSurface& s, std::uint32_t a, std::uint32_t b, std::uint32_t c);

// Normals negated and every triangle's winding reversed.
void flip(io::CadSurface& s);

// Appends `other`'s vertices and triangles to `s`.
void append(io::CadSurface& s, const io::CadSurface& other);

}  // namespace gonio::design
