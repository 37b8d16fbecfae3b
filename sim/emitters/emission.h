// Emission: where photons start and in which direction, sampled exactly
// from each emitter's distribution, with the densities of those samplers.
//
// Every photon of a run carries the same power (total flux / photons): the
// emitter is chosen in proportion to its flux, then a position and a
// direction are drawn from that emitter's own distribution.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "photometry/diagnostics.h"
#include "photometry/distribution.h"
#include "sim/samplers/alias_table.h"
#include "sim/samplers/random.h"
#include "sim/emitters/ray_set_emitter.h"
#include "sim/samplers/sampling.h"
#include "sim/scene.h"

namespace gonio::sim {

// Directions from an intensity distribution of Type C, B or A, in its local
// photometric frame (x = C0, y = C90, z = zenith; photometry/frame.h and,
// for Types A and B, photometry/angles.h), with density exactly proportional
// to the intensity photometry::interpolate() gives on the symmetry-expanded
// grid (bilinear in the grid angles; zero where the grid holds no data).
//
// A grid cell is chosen in proportion to the exact flux of the bilinear
// interpolant over it (alias table, O(1)); inside the cell a direction is
// drawn uniformly in solid angle (uniform along the azimuthal grid angle and
// in μ of the polar one: −cos γ for Type C, sin H for Type B, sin V for
// Type A) and accepted with probability I/I_max of the cell, so each try
// costs three uniform numbers and at least one try in four is accepted (one
// in 1.1 for smooth profiles). Under low-discrepancy draws (sim/samplers/sampler.h)
// the direction inside the cell is drawn by inversion instead: the polar
// angle from the marginal CDF of the bilinear interpolant in solid angle
// (safeguarded Newton steps), then the azimuthal one from the conditional,
// linear density: two numbers, the same density.
class ProfileSampler {
 public:
  // Errors: an invalid distribution, no flux at all.
  static Result<ProfileSampler> create(const photometry::Distribution& profile);

  // Unit direction in the local photometric frame.
  Vec3 sample(PhotonRandom& rng) const;
  // Density of sample() at a local direction (need not be unit) [1/sr].
  double pdf(const Vec3& local) const { return intensity_cd(local) / flux_lm_; }
  // Interpolated intensity at a local direction [cd].
  double intensity_cd(const Vec3& local) const;
  // ∫ I dΩ of the interpolant over the sphere [lm]: the profile's own flux.
  double flux_lm() const { return flux_lm_; }
  std::size_t cell_count() const { return cells_.size(); }

 private:
  struct Cell {
    double h0_rad, dh_rad;          // horizontal grid angle range (C or H) [rad]
    double v0_rad, dv_rad;          // vertical grid angle range (γ or V) [rad]
    double mu0, mu1;                // μ of the polar angle at its ends, mu0 < mu1
    double i00, i10, i01, i11;      // corners (h0,v0), (h1,v0), (h0,v1), (h1,v1) [cd]
    double i_min, i_max;            // smallest and largest corner [cd]
    double cos_mid, sin_mid;        // Type C: cos and sin of the cell's middle C angle
    // sin and cos of the polar angle at its ends and middle (inversion).
    double sin_p0, cos_p0, sin_p1, cos_p1, sin_pmid, cos_pmid;
  };
  // The direction inside cell c by inversion from two uniforms.
  Vec3 sample_in_cell(const Cell& c, double u1, double u2) const;

  photometry::PhotometricType type_ = photometry::PhotometricType::C;
  bool polar_is_vertical_ = true;   // Types C and A; Type B's polar angle is H
  bool polar_is_gamma_ = true;      // Type C: μ = −cos γ; A and B: μ = sin
  std::shared_ptr<const photometry::Distribution> expanded_;
  std::vector<Cell> cells_;
  AliasTable cell_table_;
  double flux_lm_ = 0.0;
};

// Points uniform in area over a mesh and cosine-weighted directions about
// each triangle's front normal (either side with equal chance if two-sided):
// a Lambertian emitter of uniform luminance.
// Density: 1/A · cos θ/π [1/(m²·sr)], or 1/(2A) · |cos θ|/π two-sided.
class AreaSampler {
 public:
  // Errors: a mesh without triangles of positive area, bad indices.
  static Result<AreaSampler> create(const Mesh& mesh, bool two_sided);

  struct Sample {
    Vec3 position;       // on the mesh [m]
    Vec3 normal;         // unit normal of the side it leaves from
    Vec3 direction;      // unit, dot(direction, normal) > 0
    std::uint32_t triangle;
  };
  Sample sample(PhotonRandom& rng) const;
  // Density of a direction leaving a point of the mesh whose front normal is
  // `front_normal` [1/(m²·sr)].
  double pdf(const Vec3& front_normal, const Vec3& direction) const;
  double area_m2() const { return area_m2_; }

 private:
  struct Triangle {
    Vec3 corner, edge1, edge2;  // p0, p1 − p0, p2 − p0 [m]
    Basis front;                // orthonormal, front.n the unit front normal
  };
  std::vector<Triangle> triangles_;            // those with positive area
  std::vector<std::uint32_t> triangle_index_;  // index in the mesh
  AliasTable triangle_table_;
  double area_m2_ = 0.0;
  bool two_sided_ = false;
};

// One emitted photon.
struct EmittedPhoton {
  Vec3 origin;             // [m]
  Vec3 direction;          // unit
  std::uint32_t emitter;   // index in SceneDesc::emitters
  bool on_surface = false; // leaves the surface of an area emitter's mesh
  Vec3 surface_normal;     // on_surface: unit normal of the side it leaves
};

// All emitters of a scene. Emitters with zero flux never emit.
class EmissionSampler {
 public:
  // Errors name the emitter: non-finite or negative flux, no flux in total,
  // a missing mesh, a profile that cannot be sampled, a point emitter's
  // frame that is not orthonormal and right-handed (photometry/frame.h).
  static Result<EmissionSampler> create(const SceneDesc& scene);

  EmittedPhoton sample(PhotonRandom& rng) const;

  std::size_t emitter_count() const { return emitters_.size(); }
  // Chance that a photon comes from emitter i: flux_i / Σ flux.
  double emitter_probability(std::size_t i) const { return emitter_table_.pmf(i); }
  double total_flux_lm() const { return total_flux_lm_; }

 private:
  struct Source {
    Emitter::Kind kind;
    Vec3 position;
    photometry::PhotometricFrame frame;
    std::shared_ptr<const ProfileSampler> profile;  // null: isotropic point
    std::shared_ptr<const AreaSampler> area;
    std::shared_ptr<const RaySetSampler> rays;
  };
  std::vector<Source> emitters_;
  AliasTable emitter_table_;
  double total_flux_lm_ = 0.0;
};

}  // namespace gonio::sim
