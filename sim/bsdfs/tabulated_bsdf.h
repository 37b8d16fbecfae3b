// A measured, isotropic BSDF as plain data: what io/materials reads from
// Radiance/WINDOW BSDF XML (Klems matrices, tensor trees) and goniometer
// CSV tables, and what the tracer scatters with (sim/bsdfs/lobes.h).
//
// Frame. For light arriving on one side, z is the normal on that side and
// the incident light travels along azimuth 0: wi = (−sin θi, 0, cos θi)
// points back to the source, so the specular direction is
// (sin θi, 0, cos θi) and the straight-through one (sin θi, 0, −cos θi),
// both at outgoing azimuth 0 (the Klems and tensor-tree convention, where
// they are the matrix's diagonal). An outgoing direction below the surface
// (transmission) is looked up by its mirror image (x, y, −z).
//
// Outgoing directions of a hemisphere are split into patches, each with its
// projected solid angle Ω (∫ cos θ dω over it; they sum to π), and the BSDF
// is constant over a patch [1/sr]:
//   Rings   θ rings, each split in φ (Klems: patches centred on φ = 360°k/n;
//           CSV tables: bounds halfway between measured angles);
//   Square  n × n cells of Shirley and Chiu's square (Radiance's tensor
//           trees): every cell has Ω = π/n².
// Each side (front: light arriving on the face the normal points to) holds
// rows of reflection and transmission values at increasing angles of
// incidence; between rows the BSDF is interpolated linearly in θi, beyond
// them held. Directional albedo of a row: Σ f Ω.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "photometry/diagnostics.h"
#include "photometry/vec3.h"

namespace gonio::sim {

struct PatchBasis {
  enum class Kind { Rings, Square };
  Kind kind = Kind::Rings;
  // Rings: bounds of the rings in θ [deg] from 0 to 90 (rings + 1 values),
  // and per ring the patch bounds in φ [deg], increasing, the last one the
  // first plus 360 (patches + 1 values): patch k spans [b_k, b_k+1).
  std::vector<double> ring_theta_deg;
  std::vector<std::vector<double>> ring_phi_deg;
  // Square: cells per side.
  int square_n = 0;

  std::size_t size() const;
  // The patch of a direction with z >= 0 (a unit vector); SIZE_MAX for none.
  std::size_t patch_of(const Vec3& w) const;
  double projected_solid_angle(std::size_t patch) const;
  // A direction in the patch, uniform in projected solid angle, from (u, v)
  // in [0, 1)²; z >= 0.
  Vec3 direction_in(std::size_t patch, double u, double v) const;
  // The direction at the patch's middle (for reports and checks).
  Vec3 centre_of(std::size_t patch) const;
  // The Klems bases of LBNL/WINDOW: "LBNL/Klems Full" (145 patches), Half
  // (73) and Quarter (41).
  static PatchBasis klems(const std::string& name);
};

// Shirley and Chiu's concentric map between the square [0,1]² and the unit
// disc (as Radiance's square2disk and disk2square): area-preserving, so a
// uniform point in a cell is uniform in projected solid angle once lifted
// onto the hemisphere.
void square_to_disc(double sx, double sy, double* dx, double* dy);
void disc_to_square(double dx, double dy, double* sx, double* sy);

struct TabulatedBsdf {
  struct Row {
    double theta_deg = 0.0;      // angle of incidence [deg]
    std::vector<float> reflect;  // f per patch [1/sr]; empty: none
    std::vector<float> transmit; // f per patch [1/sr]; empty: none
    double reflect_albedo = 0.0;   // Σ f Ω (filled by finish())
    double transmit_albedo = 0.0;
    // Cumulative share of f Ω over the reflection patches, then the
    // transmission ones (2 × basis.size() values; filled by finish()).
    std::vector<double> cdf;
  };
  struct Side {
    std::vector<Row> rows;  // increasing theta_deg
    bool empty() const { return rows.empty(); }
  };

  std::string name;  // where it came from (file, material name)
  PatchBasis basis;
  Side front, back;
  // Light arriving on the back where `back` is empty uses `front` (a
  // symmetric sheet); so does the front where `front` is empty.

  // Checks the shapes (every row's vectors empty or basis.size() long,
  // values finite and >= 0, rows' angles increasing within [0, 90], some
  // data on some side), computes the rows' albedos, and scales down any row
  // whose reflection and transmission together exceed 1 + 10⁻³, saying so
  // in `findings` (code "bsdf-albedo-above-1", naming the side and angle).
  Status finish(std::vector<Finding>& findings);

  // The side that light arriving at `front` uses.
  const Side& side(bool arrives_front) const;
  // f · |cos θo| [1/sr] for wi (z > 0, any azimuth: the table is
  // isotropic) and wo (z > 0 reflection, z < 0 transmission), interpolated
  // between rows.
  double evaluate(bool arrives_front, const Vec3& wi, const Vec3& wo) const;
  // Reflection and transmission albedo at the angle of incidence of wi.
  double albedo(bool arrives_front, const Vec3& wi, double* reflect = nullptr,
                double* transmit = nullptr) const;
  // An outgoing direction for light along wi with density
  // evaluate / albedo, from five uniforms in [0, 1): the row (between the
  // two about θi, in proportion to their interpolated albedos), the patch,
  // two for the point in it. The zero vector where the albedo is 0.
  Vec3 sample(bool arrives_front, const Vec3& wi, double u_row, double u_patch, double u,
              double v) const;
  // Mean relative difference |f(a→b) − f(b→a)| / ((f(a→b) + f(b→a))/2) of
  // the front reflection over pairs of patch centres (weighted by f Ω Ω),
  // and of transmission between the two sides (front → back against
  // back → front reversed) where both are given: the reciprocity report.
  // Negative where nothing could be compared.
  double reciprocity_error(bool transmission) const;
};

}  // namespace gonio::sim
