#include "sim/bsdfs/library.h"

#include <utility>

namespace gonio::sim {
namespace {

MaterialPreset surface(std::string name, std::string datasheet, std::string source, Material m) {
  m.name = name;
  MaterialPreset p;
  p.name = std::move(name);
  p.datasheet = std::move(datasheet);
  p.source = std::move(source);
  p.material = std::move(m);
  return p;
}

// A sheet of a scattering medium (a closed part of the stated thickness):
// smooth faces (a dielectric of index n), the fitted medium inside.
MaterialPreset sheet(std::string name, std::string datasheet, std::string source, double ior, double mus,
                     double mua, double g, double transmittance, double haze, double half_value_deg,
                     double thickness_m) {
  Material m;
  m.dielectric = 1.0;
  m.ior = ior;
  m.scattering_per_m = mus;
  m.attenuation_per_m = mua;
  m.scattering_g = g;
  MaterialPreset p = surface(std::move(name), std::move(datasheet), std::move(source), m);
  p.transmittance = transmittance;
  p.haze = haze;
  p.half_value_deg = half_value_deg;
  p.thickness_m = thickness_m;
  return p;
}

std::vector<MaterialPreset> build() {
  std::vector<MaterialPreset> out;
  {
    // Diffuse white under a thin smooth-ish coat (glTF's dielectric F0 of
    // 0.04 as a glossy lobe of roughness 0.1).
    Material m;
    m.diffuse_reflect = 0.86;
    m.glossy = 0.04;
    m.glossy_mx = m.glossy_my = 0.1;
    out.push_back(surface("white powder coat",
                          "total reflectance 0.90 (diffuse 0.86, a gloss coat 0.04), RAL 9016 traffic white",
                          "TRILUX, Lighting practice: light distribution by reflection (painted reflectors, RAL 9016, "
                          "\"reflectance values exceeding 90 %\"); the split into diffuse and gloss is assumed",
                          m));
  }
  {
    // Anodised (semi-specular) aluminium: a specular share with ABg wings.
    Material m;
    m.mirror = 0.55;
    m.abg_reflect = {0.30, 2e-3, 2.0};
    out.push_back(surface("anodised aluminium",
                          "total reflectance 0.85: specular 0.55, scattered (ABg, B 0.002, g 2) 0.30",
                          "assumed: no maker's datasheet was found; 0.85 lies below the > 92 % that Fagerhult "
                          "(material properties: aluminium with good light-reflecting properties) gives for "
                          "vacuum-metallised surfaces",
                          m));
  }
  {
    Material m;
    m.mirror = 0.92;
    m.abg_reflect = {0.03, 1e-4, 2.0};
    out.push_back(surface("specular aluminium",
                          "total reflectance 0.95: specular 0.92, narrow ABg wings (B 0.0001, g 2) 0.03",
                          "Fagerhult, material properties: vacuum-metallised reflector sheet \"factor > 92 %\" "
                          "(specular share); the wings are assumed",
                          m));
  }
  // Fitted with sim::fit_volume (100,000 photons, seed 1); see library.h.
  out.push_back(sheet("opal PC 3 mm",
                      "light transmission 0.55 at 3 mm (ASTM D1003); half-value angle 50° (assumed); n 1.586; "
                      "g 0.8 (assumed)",
                      "Makrolon / TUFFAK Lumen XT sheet datasheet, grade LW9 at 0.118 in: light transmission 55 % "
                      "(ASTM D1003); the half-value angle is not given there",
                      1.586, 1927.8, 1.32649, 0.8, 0.55, 0.0, 50.0, 0.003));
  out.push_back(sheet("satin PC 3 mm",
                      "light transmission 0.81 at 3 mm (ASTM D1003); haze 0.90 (assumed); n 1.586; g 0.95 (assumed)",
                      "Makrolon / TUFFAK Lumen XT sheet datasheet, grade LW5 at 0.118 in: light transmission 81 % "
                      "(ASTM D1003); haze is not given there",
                      1.586, 952.471, 3.72042, 0.95, 0.81, 0.90, 0.0, 0.003));
  out.push_back(sheet("opal PMMA 3 mm",
                      "light transmission 0.60 at 3 mm; half-value angle 40° (assumed); n 1.49; g 0.8 (assumed)",
                      "the reference thesis' opal (Krösl 2016, section 5.2: 60 % diffuse transmission); no PMMA "
                      "maker's figure was found",
                      1.49, 1472.77, 2.89198, 0.8, 0.60, 0.0, 40.0, 0.003));
  out.push_back(sheet("satin PMMA 3 mm",
                      "light transmission 0.85 at 3 mm, haze 0.70 (both assumed); n 1.49; g 0.95 (assumed)",
                      "assumed: no maker's figure was found (clear PMMA transmits 92 %: ACRYLITE, visible light "
                      "transmission)",
                      1.49, 494.969, 10.1633, 0.95, 0.85, 0.70, 0.0, 0.003));
  // Clear optical plastics for lenses (design/lens.h): a smooth dielectric of
  // the measured index at 587.6 nm, no absorption and no dispersion.
  for (const auto& [name, ior] : {std::pair{"clear PMMA", 1.491}, std::pair{"clear PC", 1.585}}) {
    Material m;
    m.dielectric = 1.0;
    m.ior = ior;
    out.push_back(surface(name,
                          "refractive index " + std::string(ior == 1.491 ? "1.491" : "1.585") +
                              " at 587.6 nm; clear (no absorption or scattering, assumed); no dispersion",
                          "Sultanova, Kasarova and Nikolov, Dispersion properties of optical polymers, Acta Physica "
                          "Polonica A 116, 585 (2009): measured indices of PMMA and PC at 587.6 nm",
                          m));
  }
  {
    Material m;
    m.diffuse_reflect = 0.05;
    out.push_back(surface("black", "diffuse reflectance 0.05 (matt black paint)",
                          "assumed: OSRAM's table of room surfaces gives 0.1 for black; luminaire blacks (matt black "
                          "paint, black anodising) reflect less",
                          m));
  }
  return out;
}

}  // namespace

const std::vector<MaterialPreset>& material_library() {
  static const std::vector<MaterialPreset> library = build();
  return library;
}

const MaterialPreset* find_preset(std::string_view name) {
  for (const MaterialPreset& p : material_library())
    if (p.name == name) return &p;
  return nullptr;
}

}  // namespace gonio::sim
