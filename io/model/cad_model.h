// A CAD model (STEP or IGES) as OpenCASCADE leaves it after reading and
// tessellation, in plain data: the parts (each tessellated once, in its own
// frame) and their placements in the assembly. io/model/step.cpp makes it
// (in the helper program gonio-cad, io/model/cad_helper.cpp); io/model/cad.h
// turns it into the simulation's scene with the sidecar's materials and
// emitters. It travels between the two processes, and sits in the cache, as
// the binary form below.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "photometry/diagnostics.h"
#include "sim/affine.h"
#include "sim/scene.h"

namespace gonio::io {

// How the surfaces are cut into triangles (OpenCASCADE's BRepMesh). A facet
// whose normal is off the surface's by δ turns a reflected ray by 2δ; the
// angular deflection bounds δ between neighbouring facets, the chordal one
// the distance between facet and surface.
struct CadTessellation {
  // [deg], in (0, 90]: how far a facet's normal may be off the surface's at
  // its vertices (io/model/step.h); the default suits the default 2.5° grid
  // (io/model/cad.h, tessellation_for_grid).
  double angular_deflection_deg = 2.0;
  // Chordal deflection: the greater of `chordal_relative` × the part's size
  // (its bounding-box diagonal) and chordal_min_m, unless chordal_m is set.
  double chordal_relative = 1e-3;       // [-], > 0
  double chordal_min_m = 1e-6;          // [m], floor of the relative deflection
  double chordal_m = 0.0;               // [m], > 0: the same absolute deflection for every part
  // Shading normals from the exact surface at every vertex (BRep_Tool's
  // surface, evaluated at the vertex's (u, v)); false: none (the facets'
  // own normals, as a plain mesh export would give).
  bool exact_normals = true;
};

// One group of a part's faces that share a colour, as triangles in the
// part's frame [m]. Vertices are per face, so normals may differ across an
// edge; positions on a shared edge are the same numbers on both faces.
struct CadSurface {
  std::optional<sim::Vec3f> colour;      // linear RGB in [0, 1]; none: the part's
  std::vector<sim::Vec3f> positions;     // [m], the part's frame
  std::vector<sim::Vec3f> normals;       // unit, outward; empty: none (exact_normals off)
  std::vector<std::uint32_t> indices;    // three per triangle, counter-clockwise from outside
};

// One shape of the file: a solid, a shell or loose faces, tessellated once
// however often it is placed.
struct CadPart {
  std::string name;                      // the product's (shape label's) name; may be empty
  std::optional<sim::Vec3f> colour;      // the part's surface colour, linear RGB
  std::vector<std::string> layers;       // layer names of the part
  std::uint32_t faces = 0;               // B-rep faces
  std::uint32_t solids = 0;              // closed solids among its shapes
  double size_m = 0.0;                   // bounding-box diagonal [m]
  double chordal_m = 0.0;                // the chordal deflection it was meshed with [m]
  std::vector<CadSurface> surfaces;

  std::size_t triangle_count() const {
    std::size_t n = 0;
    for (const CadSurface& s : surfaces) n += s.indices.size() / 3;
    return n;
  }
};

// One placement of a part: where the assembly puts it.
struct CadPlacement {
  std::uint32_t part = 0;                // index into CadModel::parts
  sim::Affine to_world;                  // the part's frame → the file's world [m]
  // The assembly path: the names of the components from the root to this
  // placement, '/'-separated; a component without a name takes its
  // product's name, then "#<entity>" or "part<i>"; a name repeated among
  // siblings gets "[2]", "[3]", … after the first.
  std::string path;
  std::optional<sim::Vec3f> colour;      // the component's colour, which overrides the part's
  std::vector<std::string> layers;       // the component's layers (with the part's, for matching)
};

struct CadModel {
  std::string format;                    // "STEP" or "IGES", with the schema where known
  std::string file_unit;                 // the file's length unit as it names it ("MM", "INCH", …)
  double file_unit_m = 0.001;            // metres per file unit
  CadTessellation tessellation;          // what the parts were meshed with
  std::vector<CadPart> parts;
  std::vector<CadPlacement> placements;
  std::vector<Finding> findings;         // the reader's warnings (file and entity or part named)

  std::size_t unique_triangle_count() const;
  std::size_t placed_triangle_count() const;
};

// The binary form (little-endian; magic "GONIOCAD", kCadModelFormat). The
// reader checks every count against the bytes left before it allocates and
// every index against its range, so a damaged cache entry is an error, not
// a crash. `name` is the file named in errors.
inline constexpr std::uint32_t kCadModelFormat = 1;

// Raised whenever io/model/step.cpp would mesh or name a file differently,
// so that cached tessellations (io/model/cad.h) are made again.
inline constexpr std::uint32_t kCadReaderRevision = 1;
std::string serialize_cad_model(const CadModel& model);
Result<CadModel> parse_cad_model(std::string_view bytes, const std::string& name);

}  // namespace gonio::io
