// Luminance images: the luminaire as an observer at infinity sees it — the
// far-field observer of the goniophotometer, looking back along a direction
// (C, γ) of the photometric frame — a third detector beside the far field
// and the near-field planes (ARCHITECTURE.md, "Detectors").
//
// The view is orthographic: the image plane is perpendicular to the viewing
// direction t (unit, from the luminaire towards the observer: the light's
// direction of travel), `up` is the photometric zenith projected onto it
// (at γ = 0° and 180°, where the zenith is t itself, the horizontal
// direction of the C-plane, ± so that it turns continuously), `right` = up ×
// t (the observer's right). Pixels are squares of `pixel_m`, `pixels` a
// side, centred on the scene's bounding-box centre, rows from the top.
//
// Two kinds of photon events fill an image, each in integer units of
// power per steradian (kPowerUnits per photon of nominal power, ×1/sr):
// - an escape whose direction lies within the viewing cone (half-angle
//   `cone_deg` about t) is binned at the pixel where its last free path
//   starts (the surface point it leaves), projected along t, with weight
//   1/Ω_cone: the luminance averaged over the cone;
// - a next-event connection: a photon at a vertex with non-delta lobes
//   (sim/bsdfs/bsdf_eval.h) — or leaving an area emitter — sends, when nothing
//   blocks the straight line from that point along t, f(wi, t)·|cos θt|
//   (an area emitter: cos θt/π, two-sided |cos θt|/2π) at the vertex's
//   pixel: the intensity that event sends towards the observer. Its escape
//   after that event is then not binned (the connection stands for it):
//   nothing is counted twice. Specular paths (a lens, a mirror reflector)
//   appear through the binned escapes alone.
// Luminance L = units · (lm per unit) / pixel area [cd/m²]; an image's
// integral Σ L · pixel area is the intensity towards t, averaged over the
// cone for the binned part [cd].
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "photometry/frame.h"
#include "photometry/vec3.h"

namespace gonio::sim {

inline constexpr double kLuminanceConeDeg = 2.5;    // default viewing cone half-angle [deg]
inline constexpr double kLuminancePixelM = 0.0012;  // default pixel: CIE 232's d/10, d = 12 mm [m]
inline constexpr int kLuminanceMaxPixels = 1024;    // default largest side [pixels]

// A viewing direction of the photometric frame [deg]: C in [0, 360), γ in
// [0, 180] (γ = 0: the observer straight below).
struct LuminanceView {
  double c_deg = 0.0;
  double gamma_deg = 0.0;
};

// The UGR viewing directions of CIE 232:2019 (through the TechnoTeam DUGR
// Calculator's manual, §3.2 and §5.7): 25° and 40° above the luminaire's
// plane, i.e. γ = 65° and 50°, lengthwise (C0) and crosswise (C90).
std::vector<LuminanceView> ugr_luminance_views();

// "C:γ[,C:γ…]" in degrees, or the named set "ugr"; error message otherwise
// (empty on success). Duplicates are kept once; at most 16 views.
std::string parse_luminance_views(std::string_view text, std::vector<LuminanceView>* views);

struct LuminanceImageSettings {
  std::vector<LuminanceView> views;
  double cone_deg = kLuminanceConeDeg;       // (0, 90]
  double pixel_m = kLuminancePixelM;         // > 0; enlarged where the side would exceed max_pixels
  int max_pixels = kLuminanceMaxPixels;      // 16 … 8192
};

// One view's geometry.
struct ImagePlane {
  LuminanceView view;
  Vec3 toward, right, up;  // unit, world
  Vec3 centre;             // world point at the image's middle [m]
  double pixel_m = 0.0;    // [m]
  int pixels = 0;          // a side
  std::size_t pixel_count() const { return static_cast<std::size_t>(pixels) * static_cast<std::size_t>(pixels); }
  // The pixel (row-major from the top) where a world point projects; npos
  // outside the image.
  static constexpr std::size_t npos = ~std::size_t{0};
  std::size_t pixel_of(const Vec3& p) const;
};

// All views of a run.
struct LuminanceCamera {
  std::vector<ImagePlane> planes;
  double cos_cone = 1.0;  // cosine of the cone half-angle
  double cone_sr = 0.0;   // Ω of the cone, 2π(1 − cos) [sr]
  bool spectral = false;  // X and Z are kept beside Y
};

// The camera for a scene's bounding box (lower, upper corners [m]) and
// photometric frame: every view sees the box's bounding sphere whole.
// Settings must be valid (validate_luminance_settings).
LuminanceCamera make_luminance_camera(const LuminanceImageSettings& settings, const Vec3& box_lower,
                                      const Vec3& box_upper, const photometry::PhotometricFrame& frame,
                                      bool spectral);
std::string validate_luminance_settings(const LuminanceImageSettings& settings);  // empty: valid

// A thread's (or a run's) units per view and pixel; X and Z beside them in
// spectral runs (kColourUnits per photon of Y, sim/tracer/spectral.h, × 1/sr).
struct LuminanceTally {
  std::vector<std::vector<std::uint64_t>> units;
  std::vector<std::vector<std::uint64_t>> x_units, z_units;

  bool active() const { return !units.empty(); }
  void reset(const LuminanceCamera& camera);
  void clear();
  void add(const LuminanceTally& other);
  // An escape (origin [m], unit direction, power units; colour units per
  // photon of Y when spectral): binned in every view whose cone holds it.
  void add_escape(const LuminanceCamera& camera, const Vec3& origin, const Vec3& direction, std::uint64_t power_units,
                  std::uint64_t x = 0, std::uint64_t z = 0);
  // A connection of view k from point p carrying power_units · per_sr.
  void add_connection(const LuminanceCamera& camera, std::size_t k, const Vec3& p, double power_units_per_sr,
                      std::uint64_t x = 0, std::uint64_t z = 0);
};

// One finished image.
struct LuminanceImage {
  ImagePlane plane;
  std::vector<double> cd_m2;    // row-major from the top [cd/m²]
  // Spectral runs: CIE 1931 chromaticity per pixel (0 where dark); empty otherwise.
  std::vector<double> cie_x, cie_y;
  double intensity_cd = 0.0;    // Σ L · pixel area [cd]
  double max_cd_m2 = 0.0;
};

// The images from summed units; lm_per_unit: flux of one power unit [lm]
// (as the far field's), lm_per_colour_unit: of one X or Z unit.
std::vector<LuminanceImage> luminance_images(const LuminanceCamera& camera, const LuminanceTally& sum,
                                             double lm_per_unit, double lm_per_colour_unit);

}  // namespace gonio::sim
