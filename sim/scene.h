// Scene description: the luminaire the simulation traces, as plain data.
// io/model/gltf.h builds it from a glTF 2.0 model; tests and the sample generator
// build it directly. Geometry is in world space, metres, except for
// instanced meshes: those are stored once in their own frame and placed by
// SceneDesc::instances (Embree instances in the tracer), so that memory and
// setup grow with unique geometry, not with copies.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "photometry/distribution.h"
#include "photometry/frame.h"
#include "photometry/spectrum.h"
#include "photometry/vec3.h"
#include "sim/affine.h"

namespace gonio::sim {

struct Vec3f {
  float x = 0.0f, y = 0.0f, z = 0.0f;
};

inline Vec3 to_double(const Vec3f& v) {
  return {static_cast<double>(v.x), static_cast<double>(v.y), static_cast<double>(v.z)};
}
inline Vec3f to_float(const Vec3& v) {
  return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
}

struct TabulatedBsdf;   // sim/bsdfs/tabulated_bsdf.h: a measured BSDF (plain data)
struct MaterialTables;  // sim/bsdfs/material_tables.h: what sim::prepare derives

// A lobe weight's dependence on the angle of incidence θ (between the
// incoming light and the surface normal on its side): the weight is
// multiplied by `factor`, linear in θ between the given angles and constant
// beyond the first and last. Empty: 1 at every angle.
struct IncidenceTable {
  std::vector<double> theta_deg;  // [deg], strictly increasing, within [0, 90]
  std::vector<double> factor;     // >= 0, one per angle
  bool empty() const { return theta_deg.empty(); }
  // The factor at cos θ (clamped to [0, 1]).
  double at(double cos_theta) const;
};

// The ABg scatter model of TracePro, LightTools and FRED (Harvey): BSDF =
// A / (B + |β − β0|^g) with β the outgoing direction projected on the
// surface and β0 the specular (reflection) or straight-through
// (transmission) direction projected likewise (sim/bsdfs/abg.h).
struct AbgScatter {
  double tis = 0.0;   // lobe weight: the total integrated scatter at normal incidence [-]
  double b = 1e-3;    // B [-], > 0: sets the width of the core, ~B^(1/g)
  double g = 2.0;     // g [-], in [0, 4]: the fall-off of the wings
};

// How a surface scatters a photon. Each hit chooses one event with these
// probabilities (they sum to at most 1; the remainder is absorbed), and the
// photon keeps its power: the reference thesis' material model (section 5.2)
// with Russian roulette. The lobes and their interface (evaluate, sample,
// pdf, albedo) are sim/bsdfs/lobes.h.
struct Material {
  std::string name;

  double diffuse_reflect = 0.0;   // Lambertian reflection (the thesis' kd)
  double diffuse_transmit = 0.0;  // Lambertian transmission to the far side (opal, diffusers)
  double mirror = 0.0;            // perfect specular reflection
  double glossy = 0.0;            // glossy reflection (the thesis' ks): microfacet lobe on the
                                  // anisotropic Beckmann distribution (sim/bsdfs/material.h)
  double glossy_mx = 0.1;         // lobe roughness (RMS slope) along the surface tangent
  double glossy_my = 0.1;         // lobe roughness along the bitangent
  double glossy_f0 = 1.0;         // Schlick's reflectance at normal incidence for the lobe
  double dielectric = 0.0;        // smooth dielectric interface: Fresnel reflection or
                                  // refraction, total internal reflection
  double ior = 1.5;               // refractive index of the volume behind the surface
  double attenuation_per_m = 0.0; // absorption coefficient inside that volume [1/m]
  // Volume scattering inside a closed dielectric part (sim/bsdfs/volume.h):
  // the scattering coefficient μs [1/m] and the Henyey–Greenstein asymmetry
  // g of its phase function, in (−1, 1). 0: a clear volume.
  double scattering_per_m = 0.0;
  double scattering_g = 0.0;
  // The glossy lobe's multiple-scattering compensation (Kulla & Conty 2017,
  // sim/bsdfs/glossy_energy.h): light that a single-scattering microfacet
  // lobe loses between facets leaves in a diffuse-like second lobe, so a
  // white lobe reflects all it receives. false: single scattering only.
  bool glossy_compensation = true;
  // ABg scatter in reflection and in transmission (weights: their `tis`).
  AbgScatter abg_reflect{}, abg_transmit{};
  // A measured (tabulated) BSDF: reflection and transmission on both sides
  // as read from a file (io/materials); `tabulated` is its weight.
  double tabulated = 0.0;
  std::shared_ptr<const TabulatedBsdf> table{};
  // Lobe weights over the angle of incidence, per lobe in sim::Lobe order
  // from DiffuseReflect (sim/bsdfs/material.h): index = Lobe − 1.
  std::array<IncidenceTable, 8> over_incidence{};
  // Tables derived from the above by sim::prepare (the tracer prepares its
  // materials; callers of sim::scatter prepare theirs); null until then.
  std::shared_ptr<const MaterialTables> tables{};

  // Spectral behaviour (sim/tracer/spectral.h applies it; all empty or 0: the same
  // at every wavelength). The reflectance spectrum is the total of the
  // reflection lobes (diffuse_reflect, mirror, glossy, ABg) at each wavelength,
  // shared among them in the proportion of their weights (all diffuse where
  // they are all 0); the transmittance spectrum likewise for diffuse_transmit,
  // dielectric and ABg (all diffuse where all are 0); the tabulated lobe acts
  // the same at every wavelength. Values in [0, 1].
  photometry::SampledSpectrum spectral_reflectance{};
  photometry::SampledSpectrum spectral_transmittance{};
  // Dispersion of the dielectric: a table of n over wavelength, or an Abbe
  // number V_d with `ior` as n_d (two-term Cauchy through n_d at 587.56 nm
  // with n_F − n_C = (n_d − 1)/V_d at 486.13 and 656.27 nm); 0: none.
  photometry::SampledSpectrum ior_nm{};
  double abbe_number = 0.0;

  bool spectral() const {
    return !spectral_reflectance.empty() || !spectral_transmittance.empty() || !ior_nm.empty() ||
           abbe_number > 0.0;
  }

  double total() const {
    return diffuse_reflect + diffuse_transmit + mirror + glossy + dielectric + abg_reflect.tis +
           abg_transmit.tis + tabulated;
  }
  // Whether any lobe weight depends on the angle of incidence.
  bool angular() const {
    for (const IncidenceTable& t : over_incidence)
      if (!t.empty()) return true;
    return false;
  }
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
  // Instanced: positions, normals and tangents are in the mesh's own frame
  // and the mesh is placed only by SceneDesc::instances (any number of
  // times, possibly none); otherwise it is world geometry, placed once.
  bool instanced = false;

  std::size_t triangle_count() const { return indices.size() / 3; }
};

inline constexpr std::uint32_t kNoInstance = 0xffffffffu;

// One placement of an instanced mesh. A mirroring transform (negative
// determinant) turns the winding, as glTF requires of mirrored nodes: the
// front side stays the one the transformed normals point to.
struct Instance {
  std::uint32_t mesh = 0;  // index into SceneDesc::meshes; the mesh is `instanced`
  Affine to_world;         // the mesh's frame → world [m]; must be invertible
  std::string name;        // for reports: the glTF node (and instance) it comes from
};

// A near-field ray set (an IES TM-25 file placed in the world): per ray a
// start point [m], a unit direction and its luminous flux [lm], all in the
// world (sim/emitters/ray_set_emitter.h samples it).
struct RaySet {
  std::vector<Vec3f> position_m;
  std::vector<Vec3f> direction;
  std::vector<float> flux_lm;
  std::size_t size() const { return flux_lm.size(); }
};

// An emitter's relative spectral power distribution, possibly changing with
// the angle γ from the emitter's axis (a point emitter's photometric nadir,
// γ = 0 of its profile; an area emitter's surface normal). Between the given
// angles the spectrum is interpolated linearly, each entry first scaled to
// the same luminous content; outside them the nearest entry holds. The
// spectrum shapes the colour only: the emitter's flux and intensity
// distribution stay as given. Empty: no spectral input.
struct EmitterSpectrum {
  struct AtGamma {
    double gamma_deg = 0.0;          // [deg], strictly increasing over the entries, in [0, 180]
    photometry::SampledSpectrum spectrum;   // relative spectral power (photometry::validate_spectrum)
  };
  std::vector<AtGamma> over_gamma;   // one entry: the same in every direction

  bool empty() const { return over_gamma.empty(); }
};

// Checks an emitter's spectrum: entries' γ strictly increasing in [0, 180],
// each spectrum valid (photometry::validate_spectrum) with some luminous
// content between 360 and 830 nm. Messages name the entry.
Status validate_emitter_spectrum(const EmitterSpectrum& s);

struct Emitter {
  enum class Kind {
    Point,   // a point with a measured (or isotropic) intensity distribution
    Area,    // every triangle of one mesh, uniform over area, cosine in direction
    RaySet,  // photons drawn from a ray set in proportion to ray flux
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
  // An instanced mesh emits from one of its instances (`instance`, an index
  // into SceneDesc::instances of that mesh); world meshes have kNoInstance.
  std::uint32_t mesh = 0;
  std::uint32_t instance = kNoInstance;
  bool two_sided = false;
  // Ray-set emitters: the rays in the world (position: the node's origin, for
  // reports); flux_lm is the emitter's, the rays' fluxes only weigh them.
  std::shared_ptr<const RaySet> rays;

  EmitterSpectrum spectrum;  // empty: no spectral input (sim/tracer/spectral.h)
};

struct SceneDesc {
  std::string name;                    // the model's file name or a sample's name
  std::vector<Material> materials;
  std::vector<Mesh> meshes;
  std::vector<Instance> instances;     // placements of the instanced meshes
  std::vector<Emitter> emitters;
  photometry::PhotometricFrame frame;  // the luminaire's photometric frame in the world

  // Whether any emitter or material has spectral input: photons then carry
  // wavelengths and the far field gains X and Z (sim/tracer/spectral.h); an emitter
  // without a spectrum then emits the equal-energy spectrum (CIE illuminant
  // E). Otherwise the tracer takes today's path, draw for draw.
  bool spectral() const {
    for (const Emitter& e : emitters)
      if (!e.spectrum.empty()) return true;
    for (const Material& m : materials)
      if (m.spectral()) return true;
    return false;
  }

  double total_flux_lm() const {
    double sum = 0.0;
    for (const Emitter& e : emitters) sum += e.flux_lm;
    return sum;
  }
  // Triangles as stored (each instanced mesh once) and as placed (each
  // instance counted; an instanced mesh without instances not at all).
  std::size_t unique_triangle_count() const;
  std::size_t placed_triangle_count() const;
};

// Calls f(world position [m]) for every vertex as placed: world meshes'
// vertices once, an instanced mesh's once per instance (transformed).
template <class F>
void for_each_placed_vertex(const SceneDesc& scene, F&& f) {
  for (const Mesh& m : scene.meshes)
    if (!m.instanced)
      for (const Vec3f& p : m.positions) f(to_double(p));
  for (const Instance& i : scene.instances)
    if (i.mesh < scene.meshes.size())
      for (const Vec3f& p : scene.meshes[i.mesh].positions) f(i.to_world.point(to_double(p)));
}

// Applies an affine map to positions, shading normals and tangents. A map
// that mirrors (negative determinant) also reverses the winding so that the
// front side stays the side the normals point to.
void transform(Mesh& mesh, const Affine& map);

// Whether a and b have the same traced geometry: every mesh's positions,
// indices and instanced flag, every instance's mesh and transform (not
// names, materials, normals or emitters): one BVH serves both.
bool same_geometry(const SceneDesc& a, const SceneDesc& b);

// The same scene with every instance replaced by a world mesh of its own,
// named "<instance name>/<mesh name>": meshes in their order, an instanced
// mesh replaced by its instances in instance order; area emitters follow
// their mesh. For writers of flat geometry and for tests of instancing.
SceneDesc flattened(const SceneDesc& scene);

}  // namespace gonio::sim
