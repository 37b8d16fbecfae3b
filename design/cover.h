// Covers and diffusers of a design file (design/design_file.h): a plate or
// a dome below (or above) the luminaire, of a material from the file's
// [materials] (the material library's presets among them):
//
//   [[covers]]
//   name = "diffuser"
//   material = "opal"                  # [materials.opal] preset = "opal PC 3 mm"
//   shape = "plate"                    # "plate" or "dome"
//   size = [600, 60]                   # plate: a rectangle x by y about the axis, or
//   diameter = 80                      # plate: a disc; dome: its base circle
//   height = -20                       # z of the face toward the luminaire
//                                      #   (plate: its upper face; dome: its base circle)
//   thickness = 3                      # volume materials (below)
//   sag = 15                           # dome: depth of the spherical cap below its
//                                      #   base (negative: it bulges up), < diameter/2
//
// What the cover is follows its material, as a CAD part's surfaces do:
//   - a volume material (a smooth dielectric interface, a scattering or
//     absorbing medium: `dielectric`, `ior` with `transmittance` and
//     `diffusion` < 1, the library's opal and satin sheets) makes a closed
//     solid of `thickness` (default: the preset's own): a plate spans
//     height − thickness … height; a dome lies between its outer sphere
//     (through the base circle with the stated sag) and the concentric sphere
//     `thickness` nearer the centre, closed by the flat ring at its base.
//     Normals face out of the solid, triangles counter-clockwise from outside;
//     shared edges are the same numbers on both faces (watertight);
//   - any other material (a thin-sheet BSDF: diffuse_transmit, abg_transmit,
//     a measured BSDF, a mirror) makes one surface, normals facing the
//     luminaire's side (the origin); a thickness given with it is an error.
// Curved edges and domes are meshed to the tessellation's deflections (the
// dome by revolved.h's rule, as a reflector of revolution).
#pragma once

#include <optional>
#include <string>

#include "io/model/cad_model.h"
#include "io/model/parts_file.h"
#include "io/model/toml_tree.h"
#include "photometry/diagnostics.h"

namespace gonio::design {

struct Cover {
  enum class Shape { Plate, Dome };
  std::string name;
  std::string material;
  Shape shape = Shape::Plate;
  std::optional<double> width, depth;   // plate rectangle [m]
  std::optional<double> diameter;       // disc or the dome's base [m]
  double height = 0.0;                  // [m]
  std::optional<double> thickness;      // [m]
  int thickness_line = 0;
  double sag = 0.0;                     // dome [m]
  int line = 0;
};

// A [[covers]] table (variables resolved; lengths × unit_m). Errors name
// `path` and the line: unknown keys, a shape Gonio does not know, a size
// that is not > 0, a dome's sag not within (0, diameter/2) in size.
Result<Cover> read_cover(const io::TomlNode& t, const std::string& path, double unit_m);

// Whether `material` (a sidecar material's extras) is a volume: a closed
// solid's material rather than a thin sheet's; `thickness_m` gets the
// library preset's thickness where it names one. Errors: the material's own.
Result<bool> is_volume_material(const io::PartsMaterial& material, const std::string& path, double* thickness_m);

struct CoverMesh {
  io::CadSurface surface;
  bool solid = false;
  double size_m = 0.0, chordal_m = 0.0;
};

// The cover meshed: a solid of `thickness_m` (> 0), or a sheet (0).
// Errors (no place): a dome thicker than its sag, too many triangles.
Result<CoverMesh> tessellate_cover(const Cover& cover, double thickness_m, const io::CadTessellation& tess,
                                   std::size_t max_triangles);

// Whether the point p [m] lies in the cover's solid of `thickness_m`, or on
// its sheet within `chordal_m` (thickness 0): where no emitter may sit.
bool cover_holds(const Cover& cover, double thickness_m, double chordal_m, const Vec3& p);

}  // namespace gonio::design
