#include "photometry/non_uniform_glare.h"

#include <algorithm>
#include <cmath>

#include "photometry/format.h"

namespace gonio::photometry {
namespace {

// 2√(2 ln 2): FWHM / σ of a Gaussian.
constexpr double kFwhmPerSigma = 2.3548200450309493;

struct Kernel {
  double sigma_px = 0.0;
  int radius = 0;
  std::vector<double> weights;  // 2r + 1, summing to 1
};

Kernel kernel_for(double pixel_m, const NonUniformGlareParameters& p) {
  Kernel k;
  k.sigma_px = p.eye_resolution_m / kFwhmPerSigma / pixel_m;
  k.radius = static_cast<int>(std::ceil(3.0 * k.sigma_px));
  k.weights.resize(static_cast<std::size_t>(2 * k.radius + 1));
  double sum = 0.0;
  for (int i = -k.radius; i <= k.radius; ++i) {
    const double w = k.sigma_px > 0.0 ? std::exp(-0.5 * (i * i) / (k.sigma_px * k.sigma_px)) : (i == 0 ? 1.0 : 0.0);
    k.weights[static_cast<std::size_t>(i + k.radius)] = w;
    sum += w;
  }
  for (double& w : k.weights) w /= sum;
  return k;
}

bool valid(const LuminanceMap& m) {
  return m.width > 0 && m.height > 0 && m.pixel_m > 0.0 && std::isfinite(m.pixel_m) &&
         m.cd_m2.size() == static_cast<std::size_t>(m.width) * static_cast<std::size_t>(m.height);
}

LuminanceMap filtered(const LuminanceMap& image, const Kernel& k) {
  // Separable: rows, then columns, on the padded image.
  const int r = k.radius, w = image.width + 2 * r, h = image.height + 2 * r;
  const auto at = [w](int x, int y) { return static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x); };
  std::vector<double> padded(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0.0);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      padded[at(x + r, y + r)] = image.cd_m2[static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) +
                                             static_cast<std::size_t>(x)];
  std::vector<double> rows(padded.size(), 0.0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double s = 0.0;
      for (int i = -r; i <= r; ++i) {
        const int xi = x + i;
        if (xi >= 0 && xi < w) s += k.weights[static_cast<std::size_t>(i + r)] * padded[at(xi, y)];
      }
      rows[at(x, y)] = s;
    }
  LuminanceMap out;
  out.width = w;
  out.height = h;
  out.pixel_m = image.pixel_m;
  out.cd_m2.assign(padded.size(), 0.0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double s = 0.0;
      for (int i = -r; i <= r; ++i) {
        const int yi = y + i;
        if (yi >= 0 && yi < h) s += k.weights[static_cast<std::size_t>(i + r)] * rows[at(x, yi)];
      }
      out.cd_m2[at(x, y)] = s;
    }
  return out;
}

}  // namespace

LuminanceMap eye_filtered(const LuminanceMap& image, const NonUniformGlareParameters& parameters) {
  if (!valid(image)) return {};
  return filtered(image, kernel_for(image.pixel_m, parameters));
}

NonUniformGlare analyse_non_uniform_glare(const LuminanceMap& image, double intensity_cd, double projected_area_m2,
                                          const NonUniformGlareParameters& parameters) {
  NonUniformGlare g;
  g.intensity_cd = intensity_cd;
  g.projected_area_m2 = projected_area_m2;
  if (!valid(image)) {
    g.why_undefined = "no luminance image";
    return g;
  }
  const Kernel k = kernel_for(image.pixel_m, parameters);
  g.fwhm_m = parameters.eye_resolution_m;
  g.sigma_px = k.sigma_px;
  g.kernel_radius_px = k.radius;
  g.resolution_ok = image.pixel_m <= parameters.eye_resolution_m / 10.0 * (1.0 + 1e-9);
  const double area = image.pixel_m * image.pixel_m;
  for (double l : image.cd_m2) g.image_intensity_cd += l * area;
  if (!(intensity_cd > 0.0) || !(projected_area_m2 > 0.0)) {
    g.why_undefined = "no intensity towards the viewer or no luminous area";
    return g;
  }
  g.mean_luminance_cd_m2 = intensity_cd / projected_area_m2;
  const LuminanceMap f = filtered(image, k);
  double sum = 0.0;
  std::size_t count = 0;
  for (double l : f.cd_m2) {
    g.peak_filtered_cd_m2 = std::max(g.peak_filtered_cd_m2, l);
    if (l >= parameters.threshold_cd_m2) {
      sum += l;
      ++count;
    }
  }
  if (count == 0) {
    g.why_undefined = "no pixel of the filtered image reaches " + format_number(parameters.threshold_cd_m2) + " cd/m²";
    return g;
  }
  g.glare_area_m2 = static_cast<double>(count) * area;
  g.glare_luminance_cd_m2 = sum / static_cast<double>(count);
  g.k2 = g.glare_luminance_cd_m2 * g.glare_luminance_cd_m2 * g.glare_area_m2 * projected_area_m2 /
         (intensity_cd * intensity_cd);
  g.delta_ugr = 8.0 * std::log10(g.k2);
  g.corrected_projected_area_m2 = projected_area_m2 / g.k2;
  g.defined = true;
  return g;
}

}  // namespace gonio::photometry
