// Scenes of other tools, rebuilt in Gonio from their published facts (never
// their code or data files), for measuring against them (docs/validation.md
// "The peer's led_with_housing (issue 43)"). Not among the four samples that
// the build writes: gonio_make_samples --peer DIR writes them.
#pragma once

#include <string>
#include <vector>

#include "samples/luminaires.h"

namespace gonio::samples {

// eulumdat-goniosim's led_with_housing(1000 lm, 120° beam): a point LED that
// emits a constant intensity I0 = Φ / (2π (1 − cos 60°)) = 1000/π cd into the
// cone γ ≤ 60° about the nadir and nothing outside it, at the upper rim of an
// open tube (radius 25 mm, 50 mm long, both ends open) of white paint that
// reflects 85 % diffusely (Lambertian) from either side.
//
// The peer's axes are z up, the LED emitting towards −z, C0 on +x and C90 on
// +y; Gonio's frame is y up, C0 on +x and C90 on −z (docs/conventions.md), so
// the peer's (x, y, z) is Gonio's (x, z, −y): the tube spans y ∈ [−50, 0] mm
// about the Y axis, the LED at the origin aims at −Y.
struct LedHousing {
  double flux_lm = 1000.0;
  double half_angle_deg = 60.0;
  double radius_m = 0.025;
  double length_m = 0.050;
  double reflectance = 0.85;
  int segments = 256;  // facets around the axis (vertices on the circle)
};
Sample led_housing(const LedHousing& p = {});

// The scene's direct part in closed form [cd]: the LED's intensity where it
// leaves through the lower opening without touching the tube (γ below both
// the cone's half angle and atan(radius / length) = 26.57°), zero elsewhere.
double led_housing_direct_cd(const LedHousing& p, double gamma_deg);

// The scenes above (today led-housing), written as write_samples writes the
// four samples: <dir>/<name>/<files>.
std::vector<Sample> peer_samples();
Status write_peer_samples(const std::string& dir);

}  // namespace gonio::samples
