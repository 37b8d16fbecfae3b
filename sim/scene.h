// Scene description: the luminaire the simulation traces, as plain data.
// io/gltf.h builds it from a glTF 2.0 model; tests and the sample generator
// build it directly. Geometry is in world space, metres.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "photometry/distribution.h"
#include "photometry/frame.h"
#include "photometry/vec3.h"

namespace gonio::sim {

struct Vec3f {
  float x = 0.0f, y = 0.0f, z = 0.0f;
};

// How a surface scatters a photon. Each hit chooses one event with these
// probabilities (they sum to at most 1; the remainder is absorbed), and the
// photon keeps its power: the reference thesis' material model (section 5.2)
// with Russian roulette.
struct Material {
  std::string name;

  double diffuse_reflect = 0.0;   // Lambertian reflection (the thesis' kd)
  double diffuse_transmit = 0.0;  // Lambertian transmission to the far side (opal, diffusers)
  double mirror = 0.0;            // perfect specular reflection
  double glossy = 0.0;            // glossy reflection (the thesis' ks): microfacet lobe on the
                                  // anisotropic Beckmann distribution (sim/material.h)
  double glossy_mx = 0.1;         // lobe roughness (RMS slope) along the surface tangent
  double glossy_my = 0.1;         // lobe roughness along the bitangent
  double glossy_f0 = 1.0;         // Schlick's reflectance at normal incidence for the lobe
  double dielectric = 0.0;        // smooth dielectric interface: Fresnel reflection or
                                  // refraction, total internal reflection
  double ior = 1.5;               // refractive index of the volume behind the surface
  double attenuation_per_m = 0.0; // absorption coefficient inside that volume [1/m]

  double total() const { return diffuse_reflect + diffuse_transmit + mirror + glossy + dielectric; }
};

// One triangle mesh with one material. Refractive volumes are closed meshes
// whose triangles wind counter-clockwise seen from outside (normals outward).
struct Mesh {
  std::string name;                    // for reports: glTF node/mesh name
  std::vector<Vec3f> positions;        // world space [m]
  std::vector<std::uint32_t> indices;  // three per triangle
  std::vector<Vec3f> normals;          // optional per-vertex shading normals (unit, world)
  std::vector<Vec3f> tangents;         // optional per-vertex tangents for anisotropic lobes
  std::uint32_t material = 0;          // index into SceneDesc::materials

  std::size_t triangle_count() const { return indices.size() / 3; }
};

struct Emitter {
  enum class Kind {
    Point,  // a point with a measured (or isotropic) intensity distribution
    Area,   // every triangle of one mesh, uniform over area, cosine in direction
  };
  Kind kind = Kind::Point;
  std::string name;
  double flux_lm = 0.0;  // flux the emitter sends out [lm]

  // Point emitters: where the point is, and how the profile's photometric
  // frame sits in the world. A null profile is isotropic.
  Vec3 position;
  photometry::PhotometricFrame frame;
  std::shared_ptr<const photometry::Distribution> profile;

  // Area emitters: the emitting mesh; front side only unless two_sided.
  std::uint32_t mesh = 0;
  bool two_sided = false;
};

struct SceneDesc {
  std::string name;                    // the model's file name or a sample's name
  std::vector<Material> materials;
  std::vector<Mesh> meshes;
  std::vector<Emitter> emitters;
  photometry::PhotometricFrame frame;  // the luminaire's photometric frame in the world

  double total_flux_lm() const {
    double sum = 0.0;
    for (const Emitter& e : emitters) sum += e.flux_lm;
    return sum;
  }
};

}  // namespace gonio::sim
