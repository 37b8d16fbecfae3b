// How a glTF 2.0 material becomes the simulation's lobe weights
// (sim::Material). Plain data in, plain data out: io/model/gltf.cpp fills
// GltfMaterial from the file and MaterialExtras from `extras.gonio`.
//
// The mapping (all weights are energy fractions at normal incidence, so they
// sum to at most 1 and the remainder is absorbed):
//
//   ρ   = luminance of baseColorFactor (RGB; alpha ignored)
//   m   = metallic, α = roughness²
//   t   = KHR_materials_transmission transmissionFactor
//   dt  = KHR_materials_diffuse_transmission diffuseTransmissionFactor,
//         ρdt its colour's luminance
//   F0  = min(1, ((n − 1)/(n + 1))² · luminance(specularColorFactor))
//         · specularFactor (KHR_materials_specular, n from KHR_materials_ior)
//
//   specular reflection  = m·ρ + (1 − m)(1 − t)·F0
//       → mirror when roughness < kMirrorRoughness, else the glossy lobe
//         with mx = my = α and f0 = 1 (reflectance equal to the weight, as
//         datasheets state it, for smooth lobes; rough ones reflect less,
//         e.g. 0.94 of it at α = 0.5 and normal incidence: sim/bsdfs/material.h)
//   dielectric           = (1 − m)·t·ρ  (smooth interface: Fresnel reflection,
//                          refraction, total internal reflection; ior = n)
//   diffuse_transmit     = (1 − m)(1 − t)(1 − F0)·dt·ρdt
//   diffuse_reflect      = (1 − m)(1 − t)(1 − F0)(1 − dt)·ρ
//   attenuation_per_m    = −ln(luminance(attenuationColor)) / attenuationDistance
//                          (KHR_materials_volume; 0 without it)
//
// `extras.gonio` overrides this in one of two forms (mixing them is an error):
//   thesis parameters — "kd" (Lambertian reflection), "ks" (glossy lobe),
//     "mx", "my" (lobe roughness), "f0" (Schlick reflectance of the lobe),
//     plus "diffuse_transmit", "mirror", "dielectric", "ior",
//     "attenuation_per_m". When any weight (kd, ks, diffuse_transmit, mirror,
//     dielectric) is given, every weight comes from the extras (unnamed ones
//     are 0); shape parameters (mx, my, f0, ior, attenuation_per_m) override
//     the derived ones individually.
//   datasheet values — "reflectance" (total light reflectance),
//     "diffuse_reflectance" (its diffuse part; default: all of it),
//     "transmittance" (total light transmittance), "diffusion" (diffuse
//     fraction of the transmission; default 1), optionally "ior", "mx", "my":
//       diffuse_reflect  = diffuse_reflectance
//       mirror           = reflectance − diffuse_reflectance (glossy with
//                          mx, my, f0 = 1 when mx or my is given)
//       diffuse_transmit = transmittance · diffusion
//       dielectric       = transmittance · (1 − diffusion)
//     The regular (non-diffuse) part of the transmission is a smooth
//     dielectric event whose own Fresnel reflection adds to the reflectance.
// Every value must be finite and within its range (weights and datasheet
// values in [0, 1], sums ≤ 1, mx, my > 0, ior ≥ 1, attenuation ≥ 0):
// anything else is an error naming the material and the key.
#pragma once

#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "photometry/diagnostics.h"
#include "sim/scene.h"

namespace gonio::io {

// Linear RGB as glTF stores colour factors.
struct Rgb {
  double r = 1.0, g = 1.0, b = 1.0;
};

// Relative luminance of linear RGB with sRGB/Rec. 709 primaries (glTF's
// colour space): 0.2126 R + 0.7152 G + 0.0722 B.
double luminance(const Rgb& c);

// Below this glTF roughness a specular lobe is a perfect mirror.
inline constexpr double kMirrorRoughness = 0.1;

// The parameters of one glTF material, defaults as the glTF specification and
// its extensions define them (a primitive without a material gets exactly
// these: white rough metal).
struct GltfMaterial {
  std::string name;
  Rgb base_color;                     // baseColorFactor (RGB)
  double metallic = 1.0;              // metallicFactor
  double roughness = 1.0;             // roughnessFactor
  Rgb emissive{0.0, 0.0, 0.0};        // emissiveFactor
  double emissive_strength = 1.0;     // KHR_materials_emissive_strength
  bool double_sided = false;          // doubleSided
  double transmission = 0.0;          // KHR_materials_transmission
  double ior = 1.5;                   // KHR_materials_ior
  double specular = 1.0;              // KHR_materials_specular specularFactor
  Rgb specular_color;                 // KHR_materials_specular specularColorFactor
  double diffuse_transmission = 0.0;  // KHR_materials_diffuse_transmission
  Rgb diffuse_transmission_color;     // its diffuseTransmissionColorFactor
  bool has_volume = false;            // KHR_materials_volume present
  double thickness_m = 0.0;           // thicknessFactor [m]; 0 = thin-walled
  double attenuation_distance_m = std::numeric_limits<double>::infinity();  // [m]
  Rgb attenuation_color;              // transmittance after attenuation_distance_m
};

// `extras.gonio` of a material; unset fields are absent from the file.
struct MaterialExtras {
  // Thesis parameters and the sim::Material lobes the thesis does not name.
  std::optional<double> kd, ks, mx, my, f0;
  std::optional<double> diffuse_transmit, mirror, dielectric;
  std::optional<double> ior, attenuation_per_m;  // [-], [1/m]
  // Datasheet values.
  std::optional<double> reflectance, diffuse_reflectance, transmittance, diffusion;
  // Emission: luminance of the surface [cd/m²], overriding emissiveFactor.
  std::optional<double> luminance_cd_m2;
  // Spectra (sim::Material): "spectral_reflectance" and
  // "spectral_transmittance" ({"wavelengths_nm": [...], "values": [...]},
  // values in [0, 1]) give the total reflectance and transmittance at each
  // wavelength, shared among the lobes the rest of the material sets up;
  // "ior_nm" (same form, values >= 1) or "abbe_number" (V_d > 0, with ior as
  // n_d) make the dielectric dispersive. The emitted spectrum of an emissive
  // material ("spectrum") is read by io/model/gltf.cpp into its emitters.
  std::optional<photometry::SampledSpectrum> spectral_reflectance, spectral_transmittance, ior_nm;
  std::optional<double> abbe_number;
  // The emitted spectrum of an emissive material ("spectrum"; empty: none).
  sim::EmitterSpectrum spectrum;

  // Measured materials (docs/materials.md):
  //   "preset": a name of the material library (sim/bsdfs/library.h); it
  //     stands alone (no lobe weights or datasheet values beside it).
  std::optional<std::string> preset;
  //   "volume_form": "walk" (the default: a closed part of a volume preset,
  //     traced by the volume walk) or "sheet" (with a volume preset only:
  //     the part is one sheet of triangles that scatters by the tabulated
  //     BSDF of the preset's sheet, sim::sheet_bsdf at its thickness).
  std::optional<std::string> volume_form;
  //   "abg" / "abg_transmit": {"B": b, "g": g} with "tis" (Gonio's weight:
  //     total integrated scatter at normal incidence) or "A" (TracePro's
  //     BSDF scale [1/sr], TIS = A · I0(B, g)): ABg scatter in reflection /
  //     transmission, beside the other lobes.
  std::optional<sim::AbgScatter> abg_reflect, abg_transmit;
  //   "scattering_per_m", "scattering_g": volume scattering inside the part
  //     (μs [1/m], Henyey–Greenstein g); absorption is attenuation_per_m.
  std::optional<double> scattering_per_m, scattering_g;
  //   "bsdf_file": a measured BSDF (BSDF XML or CSV, io/materials) beside
  //     the model, with the weight "tabulated" (default 1 with a file); it
  //     replaces the lobes glTF's factors give, unless lobe weights or
  //     datasheet values in the extras set lobes beside it.
  std::optional<std::string> bsdf_file;
  std::optional<double> tabulated;
  //   "reflectance_over_angle" / "transmittance_over_angle":
  //     {"angles_deg": [...], "values": [...]}: total reflectance /
  //     transmittance at those angles of incidence (Photopia-style R(θ),
  //     T(θ)); the reflection / transmission lobes keep their shares.
  //   "lobe_over_angle": {"<lobe>": {"angles_deg", "values"}, ...}: a
  //     factor on one lobe's weight ("diffuse_reflect", "diffuse_transmit",
  //     "mirror", "glossy", "dielectric", "abg", "abg_transmit", "tabulated").
  std::optional<sim::IncidenceTable> reflectance_over_angle, transmittance_over_angle;
  std::vector<std::pair<std::string, sim::IncidenceTable>> lobe_over_angle;
  //   "glossy_compensation": false switches Kulla–Conty's compensation off.
  std::optional<bool> glossy_compensation;

  bool has_lobe_weights() const { return kd || ks || diffuse_transmit || mirror || dielectric; }
  bool has_datasheet() const {
    return reflectance || diffuse_reflectance || transmittance || diffusion;
  }
};

// The simulation material for a glTF material and its extras. `where` names
// the file and `what` the material for errors and findings (out-of-range glTF
// factors are clamped with a warning; out-of-range extras are errors).
// `table`: the measured BSDF extras.bsdf_file names, read by the caller
// (null without one).
Result<sim::Material> map_material(const GltfMaterial& m, const MaterialExtras& extras,
                                   const SourceLoc& where, const std::string& what,
                                   std::vector<Finding>& findings,
                                   std::shared_ptr<const sim::TabulatedBsdf> table = nullptr);

// Luminance of an emissive surface [cd/m²]: extras.luminance_cd_m2 when set,
// else emissive_strength × luminance(emissive). glTF leaves emission units
// open; Gonio reads KHR_materials_emissive_strength × emissiveFactor as
// luminance in cd/m², so a Lambertian side of area A emits Φ = π·L·A.
double emissive_luminance_cd_m2(const GltfMaterial& m, const MaterialExtras& extras);

}  // namespace gonio::io
