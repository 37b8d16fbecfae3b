#include "samples/luminaires.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numbers>
#include <utility>

#include "io/support/file_io.h"
#include "io/photometric/ies.h"
#include "samples/gltf_writer.h"
#include "sim/affine.h"
#include "sim/bsdfs/library.h"
#include "sim/shapes.h"

namespace gonio::samples {
namespace {

using nlohmann::json;
constexpr double kPi = std::numbers::pi;

// A closed cylinder about the Y axis from y0 to y1, radius r, facing out.
sim::Mesh cylinder(double r, double y0, double y1, int segments) {
  const sim::ProfilePoint profile[] = {{0, y0}, {r, y0}, {r, y1}, {0, y1}};
  sim::LatheOptions o;
  o.segments = segments;
  return sim::lathe(profile, o);
}

// 1. A bell-shaped pendant with an opal glass shade and an omnidirectional
//    lamp: the reference thesis' test scene.
Sample bell() {
  GltfWriter w;
  w.use("KHR_materials_diffuse_transmission");
  const int opal = w.material(
      {{"name", "opal glass"},
       {"pbrMetallicRoughness", pbr(0.9, 0.0, 1.0)},
       {"doubleSided", true},
       {"extensions",
        {{"KHR_materials_diffuse_transmission", {{"diffuseTransmissionFactor", 0.6}}}}},
       // The thesis' opal: 60 % diffuse transmission, 30 % diffuse and 10 %
       // mirror reflection.
       {"extras",
        {{"gonio",
          {{"transmittance", 0.6}, {"diffusion", 1.0}, {"reflectance", 0.4},
           {"diffuse_reflectance", 0.3}}}}}});
  const int socket = w.material({{"name", "white plastic"}, {"pbrMetallicRoughness", pbr(0.8, 0.0, 0.7)}});
  const int cable = w.material({{"name", "black cable"}, {"pbrMetallicRoughness", pbr(0.03, 0.0, 0.8)}});

  // Shade: an open surface of revolution walked from the rim up, so its
  // front faces outwards. Rim Ø 400 mm at y = −250 mm; top opening Ø 40 mm.
  const std::vector<sim::ProfilePoint> shade = bell_shade_profile();
  sim::LatheOptions smooth;
  smooth.segments = 96;
  w.node({{"name", "shade"}, {"mesh", w.mesh(sim::lathe(shade, smooth), opal, "shade")}});
  w.node({{"name", "socket"},
          {"mesh", w.mesh(cylinder(0.018, -0.050, 0.020, 48), socket, "socket")}});
  w.node({{"name", "cable"}, {"mesh", w.mesh(cylinder(0.003, 0.020, 0.400, 16), cable, "cable")}});

  // An isotropic lamp of 1000 lm: I = 1000 / 4π cd.
  const int lamp = w.khr_light({{"name", "omnidirectional lamp"}, {"type", "point"},
                                {"intensity", 1000.0 / (4.0 * kPi)}});
  w.node({{"name", "lamp"}, {"translation", {0.0, -0.090, 0.0}},
          {"extensions", {{"KHR_lights_punctual", {{"light", lamp}}}}}});
  // The photometric frame, stated explicitly (it is also the default).
  w.doc()["scenes"][0]["extras"] = {{"gonio", {{"frame", {{"up", {0, 1, 0}}, {"c0", {1, 0, 0}}}}}}};
  return finish("bell", w);
}

// The downlight's LED: I(γ) = I0 cos^1.5 γ on the lower hemisphere, 1000 lm
// (Φ = 2πI0/(n + 1)), written by Gonio's own IES writer.
SampleFile led_profile() {
  photometry::Distribution d;
  d.type = photometry::PhotometricType::C;
  d.symmetry = photometry::Symmetry::Rotational;
  d.horizontal_deg = {0.0};
  const double n = 1.5, flux = 1000.0;
  const double i0 = flux * (n + 1.0) / (2.0 * kPi);
  for (int k = 0; k <= 36; ++k) {
    const double g = 2.5 * k;
    d.vertical_deg.push_back(g);
    d.candela.push_back(k == 36 ? 0.0 : i0 * std::pow(std::cos(g * kPi / 180.0), n));
  }
  d.lamps = {photometry::LampSet{}};
  d.lamps[0].count = 1;
  d.lamps[0].type = "mid-power LED, cos^1.5";
  d.lamps[0].flux_lm = flux;
  d.input_watts = 9.0;
  d.file_generation = photometry::FileGenerationType::ComputerSimulation;  // analytic, not measured
  d.set_keyword("TEST", "GONIO-SAMPLE-LED");
  d.set_keyword("TESTLAB", "Gonio sample generator (analytic profile)");
  d.set_keyword("MANUFAC", "Gonio samples");
  d.set_keyword("LUMCAT", "LED-COS1.5");
  d.set_keyword("LUMINAIRE", "bare LED, I = I0 cos^1.5 gamma");
  io::IesWriteOptions options;
  options.issue_date = "2024-01-01";
  options.file_generation_info = "analytic profile written by gonio_make_samples";
  return {"led.ies", io::write_ies(d, options, nullptr)};
}

// 2. A downlight: an LED at the focus of a semi-specular aluminium
// paraboloid. An ideal mirror would collimate the reflected light into a beam
// far narrower than any output grid; real downlight reflectors are peened or
// brushed to spread it, which the glossy lobe models.
Sample downlight() {
  GltfWriter w;
  const int aluminium = w.material(
      {{"name", "semi-specular aluminium"}, {"pbrMetallicRoughness", pbr(0.92, 1.0, 0.3)}});
  const int board = w.material({{"name", "white circuit board"}, {"pbrMetallicRoughness", pbr(0.75, 0.0, 0.6)}});

  // Focal length 20 mm, aperture Ø 160 mm: the rim lies 60 mm below the
  // focus. The reflector starts at the focal plane (ρ = 2f), where the LED
  // board closes it.
  sim::Mesh reflector = sim::paraboloid(0.020, 0.080, 0.040, 48, 128);
  w.node({{"name", "reflector"}, {"mesh", w.mesh(reflector, aluminium, "reflector")}});
  sim::Mesh pcb = sim::disc(0.042, 64);
  sim::flip(pcb);  // face down, into the reflector
  w.node({{"name", "board"}, {"translation", {0.0, 0.001, 0.0}}, {"mesh", w.mesh(pcb, board, "board")}});

  const int led = w.ies_light({{"name", "LED"}, {"uri", "led.ies"}});
  // EXT_lights_ies points the profile's γ = 0 along the node's −Z; turning
  // the node −90° about X aims it down (−Y) and keeps C0 on +X, C90 on −Z:
  // Gonio's default frame.
  w.node({{"name", "led"}, {"translation", {0.0, -0.0005, 0.0}}, {"rotation", about_x(-kPi / 2)},
          {"extensions", {{"EXT_lights_ies", {{"light", led}}}}}});
  return finish("downlight", w, {led_profile()});
}

// 3. A spotlight: an LED behind a plano-convex PMMA lens in a black tube.
Sample spotlight() {
  GltfWriter w;
  for (const char* e : {"KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume"})
    w.use(e);
  const double thickness = 0.012;
  const int pmma = w.material(
      {{"name", "PMMA"},
       {"pbrMetallicRoughness", pbr(1.0, 0.0, 0.0)},
       {"extensions",
        {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}},
         {"KHR_materials_ior", {{"ior", 1.49}}},
         {"KHR_materials_volume",
          {{"thicknessFactor", thickness},
           {"attenuationDistance", 0.5},
           {"attenuationColor", {0.92, 0.92, 0.92}}}}}}});
  const int black = w.material({{"name", "black anodised aluminium"}, {"pbrMetallicRoughness", pbr(0.03, 0.0, 0.5)}});

  // Plano-convex lens, aperture Ø 40 mm, convex radius 25 mm, edge 2 mm:
  // sag 10 mm, centre thickness 12 mm. A closed profile from the apex (south
  // pole) over the sphere to the rim, up the edge and across the flat top
  // (north pole), so that the solid faces outwards.
  const double rc = 0.025, aperture = 0.020, top = -0.008, rim = -0.010;
  const double centre_y = rim + std::sqrt(rc * rc - aperture * aperture);  // sphere centre
  std::vector<sim::ProfilePoint> lens;
  const double phi_max = std::asin(aperture / rc);
  const int steps = 32;
  for (int k = 0; k <= steps; ++k) {
    const double phi = phi_max * k / steps;
    lens.push_back({rc * std::sin(phi), centre_y - rc * std::cos(phi)});
  }
  lens.push_back({aperture, top});
  lens.push_back({0.0, top});
  sim::LatheOptions o;
  o.segments = 96;
  w.node({{"name", "lens"}, {"mesh", w.mesh(sim::lathe(lens, o), pmma, "lens")}});

  // Tube Ø 43 mm from just below the lens rim to the back plate.
  const sim::ProfilePoint tube[] = {{0.0215, -0.011}, {0.0215, 0.002}};
  sim::LatheOptions flat;
  flat.segments = 96;
  flat.shading_normals = false;
  w.node({{"name", "tube"}, {"mesh", w.mesh(sim::lathe(tube, flat), black, "tube")}});
  sim::Mesh back = sim::disc(0.0215, 96);
  sim::flip(back);
  w.node({{"name", "back"}, {"translation", {0.0, 0.002, 0.0}}, {"mesh", w.mesh(back, black, "back")}});

  // The LED as a KHR spot with inner 0 and outer 90°: the extension's
  // falloff is then exactly cos² θ, Φ = 2πI/3. 500 lm.
  const int led = w.khr_light({{"name", "LED"}, {"type", "spot"}, {"intensity", 3.0 * 500.0 / (2.0 * kPi)},
                               {"spot", {{"innerConeAngle", 0.0}, {"outerConeAngle", kPi / 2}}}});
  w.node({{"name", "led"}, {"rotation", about_x(-kPi / 2)},
          {"extensions", {{"KHR_lights_punctual", {{"light", led}}}}}});
  return finish("spotlight", w);
}

// 4. Nine LEDs under an opal diffuser plate in a white box.
Sample led_array() {
  GltfWriter w;
  w.use("KHR_materials_emissive_strength");
  w.use("KHR_materials_diffuse_transmission");
  const int white = w.material({{"name", "white paint"}, {"pbrMetallicRoughness", pbr(0.85, 0.0, 0.9)}});
  const int diffuser = w.material(
      {{"name", "opal PMMA 3 mm"},
       {"pbrMetallicRoughness", pbr(0.9, 0.0, 1.0)},
       {"doubleSided", true},
       {"extensions",
        {{"KHR_materials_diffuse_transmission", {{"diffuseTransmissionFactor", 0.55}}}}},
       {"extras",
        {{"gonio", {{"transmittance", 0.55}, {"diffusion", 1.0}, {"reflectance", 0.40},
                    {"diffuse_reflectance", 0.38}}}}}});

  // Box 300 × 300 mm, 50 mm deep, open at the bottom (y = 0).
  sim::Mesh box = sim::box(0.300, 0.050, 0.300);
  sim::Mesh open;
  open.positions = box.positions;
  for (std::size_t t = 0; t < box.triangle_count(); ++t)
    if (sim::triangle_normal(box, t).y > -0.5)
      open.indices.insert(open.indices.end(), box.indices.begin() + static_cast<std::ptrdiff_t>(3 * t),
                          box.indices.begin() + static_cast<std::ptrdiff_t>(3 * t + 3));
  w.node({{"name", "housing"}, {"translation", {0.0, 0.025, 0.0}}, {"mesh", w.mesh(open, white, "housing")}});

  // The diffuser closes the opening: one sheet facing down.
  sim::Mesh sheet;
  sheet.positions = {{-0.15f, 0.0f, -0.15f}, {0.15f, 0.0f, -0.15f}, {0.15f, 0.0f, 0.15f}, {-0.15f, 0.0f, 0.15f}};
  sheet.indices = {0, 1, 2, 0, 2, 3};  // counter-clockwise seen from below
  w.node({{"name", "diffuser"}, {"mesh", w.mesh(sheet, diffuser, "diffuser")}});

  // LEDs: discs Ø 5 mm facing down, 100 lm each. The emissive luminance is
  // the one that gives 100 lm by Φ = πLA; extras.gonio.flux_lm states it too.
  sim::Mesh die = sim::disc(0.0025, 16);
  sim::flip(die);
  const double area = sim::surface_area_m2(die);
  const double flux = 100.0;
  const int led = w.material({{"name", "LED"},
                              {"pbrMetallicRoughness", pbr(0.2, 0.0, 0.5)},
                              {"emissiveFactor", {1.0, 1.0, 1.0}},
                              {"extensions",
                               {{"KHR_materials_emissive_strength",
                                 {{"emissiveStrength", flux / (kPi * area)}}}}}});
  const int die_mesh = w.mesh(die, led, "LED die");
  int k = 0;
  for (double x : {-0.08, 0.0, 0.08})
    for (double z : {-0.08, 0.0, 0.08})
      w.node({{"name", "led-" + std::to_string(++k)},
              {"translation", {x, 0.0495, z}},
              {"mesh", die_mesh},
              {"extras", {{"gonio", {{"flux_lm", flux}}}}}});
  return finish("led-array", w);
}

}  // namespace

std::vector<sim::ProfilePoint> bell_shade_profile() {
  return {{0.200, -0.250}, {0.196, -0.238}, {0.184, -0.215}, {0.160, -0.180}, {0.130, -0.140}, {0.104, -0.100},
          {0.084, -0.060}, {0.068, -0.025}, {0.052, -0.002}, {0.034, 0.008},  {0.020, 0.010}};
}

std::vector<Sample> make_samples() { return {bell(), downlight(), spotlight(), led_array()}; }

Status write_samples(const std::string& dir) {
  for (const Sample& s : make_samples()) {
    const std::string folder = dir + "/" + s.name;
    if (Status st = io::make_directories(folder); !st.ok()) return st;
    for (const SampleFile& f : s.files)
      if (Status st = io::write_file_atomic(folder + "/" + f.name, f.bytes); !st.ok()) return st;
  }
  return Ok{};
}

std::optional<sim::SceneDesc> bell_with_volume_shade(const sim::SceneDesc& bell) {
  std::size_t shade = bell.meshes.size();
  for (std::size_t m = 0; m < bell.meshes.size(); ++m)
    if (bell.meshes[m].name.find("shade") != std::string::npos) shade = m;
  if (shade == bell.meshes.size()) return std::nullopt;
  const sim::MaterialPreset& opal = *sim::find_preset("opal PMMA 3 mm");
  const std::vector<sim::ProfilePoint> outer = bell_shade_profile();
  std::vector<sim::ProfilePoint> loop = outer;
  for (std::size_t k = outer.size(); k-- > 0;) {
    const sim::ProfilePoint& p0 = outer[k == 0 ? 0 : k - 1];
    const sim::ProfilePoint& p1 = outer[k + 1 < outer.size() ? k + 1 : k];
    const double dr = p1.r_m - p0.r_m, dy = p1.y_m - p0.y_m, len = std::hypot(dr, dy);
    // The outward normal is (dy, −dr)/len: step against it.
    loop.push_back({outer[k].r_m - opal.thickness_m * dy / len, outer[k].y_m + opal.thickness_m * dr / len});
  }
  sim::LatheOptions o;
  o.segments = 96;
  o.closed_profile = true;
  sim::SceneDesc b = bell;
  sim::Mesh shell = sim::lathe(loop, o);
  shell.name = "shade (3 mm shell)";
  shell.material = static_cast<std::uint32_t>(b.materials.size());
  b.materials.push_back(opal.material);
  b.meshes[shade] = std::move(shell);
  return b;
}

}  // namespace gonio::samples
