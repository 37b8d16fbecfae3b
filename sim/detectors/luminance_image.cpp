#include "sim/detectors/luminance_image.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>

#include "sim/ledger.h"

namespace gonio::sim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// The unit direction (C, γ) of the frame, in the world.
Vec3 direction_of(const photometry::PhotometricFrame& f, double c_deg, double gamma_deg) {
  const double c = c_deg * kDeg, g = gamma_deg * kDeg;
  const Vec3 horizontal = std::cos(c) * f.c0 + std::sin(c) * f.c90;
  return normalize(std::sin(g) * horizontal - std::cos(g) * f.up);
}

bool parse_number(std::string_view s, double* v) {
  while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
  while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
  if (s.empty()) return false;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), *v);
  return r.ec == std::errc() && r.ptr == s.data() + s.size() && std::isfinite(*v);
}

}  // namespace

std::vector<LuminanceView> ugr_luminance_views() { return {{0.0, 65.0}, {0.0, 50.0}, {90.0, 65.0}, {90.0, 50.0}}; }

std::string parse_luminance_views(std::string_view text, std::vector<LuminanceView>* views) {
  views->clear();
  const auto keep = [&](const LuminanceView& v) {
    for (const LuminanceView& w : *views)
      if (w.c_deg == v.c_deg && w.gamma_deg == v.gamma_deg) return;
    views->push_back(v);
  };
  for (std::size_t start = 0; start <= text.size();) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string_view token = text.substr(start, comma - start);
    start = comma + 1;
    if (token == "ugr") {
      for (const LuminanceView& v : ugr_luminance_views()) keep(v);
      continue;
    }
    const std::size_t colon = token.find(':');
    LuminanceView v;
    if (colon == std::string_view::npos || !parse_number(token.substr(0, colon), &v.c_deg) ||
        !parse_number(token.substr(colon + 1), &v.gamma_deg))
      return "'" + std::string(token.substr(0, 40)) + "' is not C:gamma in degrees (e.g. 0:65) or 'ugr'";
    if (!(v.c_deg >= 0.0 && v.c_deg < 360.0) || !(v.gamma_deg >= 0.0 && v.gamma_deg <= 180.0))
      return "'" + std::string(token.substr(0, 40)) + "': C must lie in [0, 360) and gamma in [0, 180] degrees";
    keep(v);
  }
  if (views->empty()) return "no viewing direction given";
  if (views->size() > 16) return "at most 16 viewing directions";
  return {};
}

std::string validate_luminance_settings(const LuminanceImageSettings& s) {
  if (s.views.size() > 16) return "at most 16 luminance images";
  if (!(s.cone_deg > 0.0 && s.cone_deg <= 90.0)) return "the luminance images' viewing cone must lie in (0, 90] degrees";
  if (!(s.pixel_m > 0.0 && std::isfinite(s.pixel_m))) return "the luminance images' pixel must be > 0 m";
  if (s.max_pixels < 16 || s.max_pixels > 8192) return "the luminance images' side must lie in 16..8192 pixels";
  return {};
}

std::size_t ImagePlane::pixel_of(const Vec3& p) const {
  const Vec3 d = p - centre;
  const double half = 0.5 * pixel_m * pixels;
  const double u = (dot(d, right) + half) / pixel_m;
  const double v = (half - dot(d, up)) / pixel_m;
  const double n = pixels;
  if (!(u >= 0.0 && u < n && v >= 0.0 && v < n)) return npos;
  return static_cast<std::size_t>(v) * static_cast<std::size_t>(pixels) + static_cast<std::size_t>(u);
}

LuminanceCamera make_luminance_camera(const LuminanceImageSettings& settings, const Vec3& lower, const Vec3& upper,
                                      const photometry::PhotometricFrame& frame, bool spectral) {
  LuminanceCamera cam;
  cam.cos_cone = std::cos(settings.cone_deg * kDeg);
  cam.cone_sr = 2.0 * std::numbers::pi * (1.0 - cam.cos_cone);
  cam.spectral = spectral;
  const Vec3 centre = 0.5 * (lower + upper);
  // The bounding sphere's diameter, with a pixel's margin.
  const double diameter = std::max(length(upper - lower), 1e-6);
  double pixel = settings.pixel_m;
  int pixels = static_cast<int>(std::ceil(diameter / pixel)) + 2;
  if (pixels > settings.max_pixels) {
    pixels = settings.max_pixels;
    pixel = diameter / (pixels - 2);
  }
  pixels += pixels % 2 == 0 ? 1 : 0;  // odd: the middle pixel on the centre
  for (const LuminanceView& v : settings.views) {
    ImagePlane p;
    p.view = v;
    p.toward = direction_of(frame, v.c_deg, v.gamma_deg);
    const Vec3 zenith = frame.up;
    Vec3 up = zenith - dot(zenith, p.toward) * p.toward;
    if (length(up) < 1e-9) {
      // Straight below or above: the C-plane's horizontal, as the limit.
      const double c = v.c_deg * kDeg;
      const Vec3 h = std::cos(c) * frame.c0 + std::sin(c) * frame.c90;
      up = v.gamma_deg < 90.0 ? h : -1.0 * h;
    }
    p.up = normalize(up);
    p.right = normalize(cross(p.up, p.toward));
    p.centre = centre;
    p.pixel_m = pixel;
    p.pixels = pixels;
    cam.planes.push_back(p);
  }
  return cam;
}

void LuminanceTally::reset(const LuminanceCamera& camera) {
  units.clear();
  x_units.clear();
  z_units.clear();
  for (const ImagePlane& p : camera.planes) {
    units.emplace_back(p.pixel_count(), 0);
    if (camera.spectral) {
      x_units.emplace_back(p.pixel_count(), 0);
      z_units.emplace_back(p.pixel_count(), 0);
    }
  }
}

void LuminanceTally::clear() {
  for (auto* set : {&units, &x_units, &z_units})
    for (auto& v : *set) std::fill(v.begin(), v.end(), std::uint64_t{0});
}

void LuminanceTally::add(const LuminanceTally& o) {
  const std::vector<std::vector<std::uint64_t>>* from[] = {&o.units, &o.x_units, &o.z_units};
  std::vector<std::vector<std::uint64_t>>* to[] = {&units, &x_units, &z_units};
  for (int s = 0; s < 3; ++s)
    for (std::size_t k = 0; k < to[s]->size(); ++k)
      for (std::size_t i = 0; i < (*to[s])[k].size(); ++i) (*to[s])[k][i] += (*from[s])[k][i];
}

void LuminanceTally::add_escape(const LuminanceCamera& camera, const Vec3& origin, const Vec3& direction,
                                std::uint64_t power_units, std::uint64_t x, std::uint64_t z) {
  for (std::size_t k = 0; k < camera.planes.size(); ++k) {
    const ImagePlane& p = camera.planes[k];
    if (dot(direction, p.toward) < camera.cos_cone) continue;
    add_connection(camera, k, origin, static_cast<double>(power_units) / camera.cone_sr, x, z);
  }
}

void LuminanceTally::add_connection(const LuminanceCamera& camera, std::size_t k, const Vec3& p,
                                    double power_units_per_sr, std::uint64_t x, std::uint64_t z) {
  const std::size_t i = camera.planes[k].pixel_of(p);
  if (i == ImagePlane::npos) return;
  units[k][i] += static_cast<std::uint64_t>(std::llround(power_units_per_sr));
  if (camera.spectral) {
    // X and Z are per photon of Y (nominal power): scaled like Y.
    const double per = power_units_per_sr / static_cast<double>(kPowerUnits);
    x_units[k][i] += static_cast<std::uint64_t>(std::llround(static_cast<double>(x) * per));
    z_units[k][i] += static_cast<std::uint64_t>(std::llround(static_cast<double>(z) * per));
  }
}

std::vector<LuminanceImage> luminance_images(const LuminanceCamera& camera, const LuminanceTally& sum,
                                             double lm_per_unit, double lm_per_colour_unit) {
  std::vector<LuminanceImage> out;
  for (std::size_t k = 0; k < camera.planes.size(); ++k) {
    LuminanceImage img;
    img.plane = camera.planes[k];
    const double area = img.plane.pixel_m * img.plane.pixel_m;
    const std::size_t n = img.plane.pixel_count();
    img.cd_m2.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      img.cd_m2[i] = static_cast<double>(sum.units[k][i]) * lm_per_unit / area;
      img.intensity_cd += img.cd_m2[i] * area;
      img.max_cd_m2 = std::max(img.max_cd_m2, img.cd_m2[i]);
    }
    if (camera.spectral) {
      img.cie_x.assign(n, 0.0);
      img.cie_y.assign(n, 0.0);
      for (std::size_t i = 0; i < n; ++i) {
        const double y = img.cd_m2[i] * area;
        const double x = static_cast<double>(sum.x_units[k][i]) * lm_per_colour_unit;
        const double z = static_cast<double>(sum.z_units[k][i]) * lm_per_colour_unit;
        const double s = x + y + z;
        if (s > 0.0) {
          img.cie_x[i] = x / s;
          img.cie_y[i] = y / s;
        }
      }
    }
    out.push_back(std::move(img));
  }
  return out;
}

}  // namespace gonio::sim
