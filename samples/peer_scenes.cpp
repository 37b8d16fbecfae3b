#include "samples/peer_scenes.h"

#include <cmath>
#include <numbers>

#include "io/support/file_io.h"
#include "samples/gltf_writer.h"
#include "sim/shapes.h"

namespace gonio::samples {
namespace {

constexpr double kPi = std::numbers::pi;

double led_intensity_cd(const LedHousing& p) {
  return p.flux_lm / (2.0 * kPi * (1.0 - std::cos(p.half_angle_deg * kPi / 180.0)));
}

}  // namespace

Sample led_housing(const LedHousing& p) {
  GltfWriter w;
  // Lambertian reflection alone (extras.gonio's lobe weights): no specular
  // coat, nothing transmitted.
  const int paint = w.material({{"name", "white paint (85 % diffuse)"},
                                {"pbrMetallicRoughness", pbr(p.reflectance, 0.0, 1.0)},
                                {"doubleSided", true},
                                {"extras", {{"gonio", {{"kd", p.reflectance}}}}}});
  // The open tube: one profile segment walked from the bottom up (front faces
  // outwards; the paint is double-sided).
  const sim::ProfilePoint profile[] = {{p.radius_m, -p.length_m}, {p.radius_m, 0.0}};
  sim::LatheOptions o;
  o.segments = p.segments;
  w.node({{"name", "tube"}, {"mesh", w.mesh(sim::lathe(profile, o), paint, "tube")}});
  // A hard-edged cone: KHR spot with inner = outer (the loader warns that the
  // cone has a hard edge, which is what is meant).
  const double half = p.half_angle_deg * kPi / 180.0;
  const int led = w.khr_light({{"name", "LED"},
                               {"type", "spot"},
                               {"intensity", led_intensity_cd(p)},
                               {"spot", {{"innerConeAngle", half}, {"outerConeAngle", half}}}});
  w.node({{"name", "led"}, {"rotation", about_x(-kPi / 2)}, {"extensions", {{"KHR_lights_punctual", {{"light", led}}}}}});
  w.doc()["scenes"][0]["extras"] = {{"gonio", {{"frame", {{"up", {0, 1, 0}}, {"c0", {1, 0, 0}}}}}}};
  return finish("led-housing", w);
}

double led_housing_direct_cd(const LedHousing& p, double gamma_deg) {
  const double edge = std::min(p.half_angle_deg, std::atan(p.radius_m / p.length_m) * 180.0 / kPi);
  return gamma_deg < edge ? led_intensity_cd(p) : 0.0;
}

std::vector<Sample> peer_samples() { return {led_housing()}; }

Status write_peer_samples(const std::string& dir) {
  for (const Sample& s : peer_samples()) {
    const std::string folder = dir + "/" + s.name;
    if (Status st = io::make_directories(folder); !st.ok()) return st;
    for (const SampleFile& f : s.files)
      if (Status st = io::write_file_atomic(folder + "/" + f.name, f.bytes); !st.ok()) return st;
  }
  return Ok{};
}

}  // namespace gonio::samples
