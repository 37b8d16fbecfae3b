// Photometric frames: how a distribution's angles sit in the world.
//
// Local photometric frame of Type C: x = C0, y = C90, z = zenith (up); the
// direction at (C, γ) is (sin γ cos C, sin γ sin C, −cos γ), so γ = 0 is the
// nadir and C turns counter-clockwise seen from above.
//
// Gonio's default in glTF's Y-up world: nadir −Y, C0 along +X, C90 along −Z.
// (EXT_lights_ies uses its own mapping; see io/model/gltf.h.)
#pragma once

#include "photometry/vec3.h"

namespace gonio::photometry {

// Orthonormal, right-handed: c0 × c90 = up.
struct PhotometricFrame {
  Vec3 c0{1.0, 0.0, 0.0};    // world direction of C0 (γ = 90°)
  Vec3 c90{0.0, 0.0, -1.0};  // world direction of C90 (γ = 90°)
  Vec3 up{0.0, 1.0, 0.0};    // world direction of the zenith (γ = 180°)

  // World direction of a local one and back.
  Vec3 to_world(const Vec3& local) const { return local.x * c0 + local.y * c90 + local.z * up; }
  Vec3 to_local(const Vec3& world) const { return {dot(world, c0), dot(world, c90), dot(world, up)}; }
};

// The frame with the given zenith and C0 directions (need not be unit or
// exactly orthogonal: C0 is orthogonalised against the zenith).
PhotometricFrame make_frame(const Vec3& up, const Vec3& c0);

// Local unit direction at Type C angles [rad].
Vec3 direction_from_c_gamma(double c_rad, double gamma_rad);

// Type C angles [rad] of a local direction (need not be unit, must be
// non-zero): c in [0, 2π), gamma in [0, π]. At the poles c is 0.
struct CGamma {
  double c_rad;
  double gamma_rad;
};
CGamma c_gamma_from_direction(const Vec3& local);

}  // namespace gonio::photometry
