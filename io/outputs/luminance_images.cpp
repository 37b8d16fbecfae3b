#include "io/outputs/luminance_images.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "io/outputs/exr.h"
#include "io/outputs/image.h"
#include "photometry/format.h"
#include "photometry/luminance.h"

namespace gonio::io {
namespace {

constexpr int kThumbnail = 48;

// The smallest square of pixels around everything lit (one pixel's margin).
struct Crop {
  int x0 = 0, y0 = 0, side = 0;
};
Crop lit_square(const sim::LuminanceImage& img) {
  const int n = img.plane.pixels;
  int lo_x = n, lo_y = n, hi_x = -1, hi_y = -1;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      if (img.cd_m2[static_cast<std::size_t>(y) * static_cast<std::size_t>(n) + static_cast<std::size_t>(x)] > 0.0) {
        lo_x = std::min(lo_x, x);
        hi_x = std::max(hi_x, x);
        lo_y = std::min(lo_y, y);
        hi_y = std::max(hi_y, y);
      }
  if (hi_x < 0) return {0, 0, n};
  const int side = std::min(n, std::max(hi_x - lo_x, hi_y - lo_y) + 3);
  const int cx = (lo_x + hi_x) / 2, cy = (lo_y + hi_y) / 2;
  return {std::clamp(cx - side / 2, 0, n - side), std::clamp(cy - side / 2, 0, n - side), side};
}

// Block means of the crop on a grid of at most kThumbnail a side.
nlohmann::json thumbnail(const sim::LuminanceImage& img, const Crop& c) {
  const int m = std::min(kThumbnail, c.side);
  const int n = img.plane.pixels;
  nlohmann::json values = nlohmann::json::array();
  for (int ty = 0; ty < m; ++ty)
    for (int tx = 0; tx < m; ++tx) {
      const int x0 = c.x0 + tx * c.side / m, x1 = c.x0 + (tx + 1) * c.side / m;
      const int y0 = c.y0 + ty * c.side / m, y1 = c.y0 + (ty + 1) * c.side / m;
      double sum = 0.0;
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x)
          sum += img.cd_m2[static_cast<std::size_t>(y) * static_cast<std::size_t>(n) + static_cast<std::size_t>(x)];
      const double mean = sum / std::max(1, (x1 - x0) * (y1 - y0));
      values.push_back(std::stod(format_number(mean, 4)));
    }
  return {{"size", m}, {"cd_m2", values}};
}

// The picture's white point: the 99.5th percentile of the lit pixels'
// luminance, so that a bare lamp's few pixels (millions of cd/m²) clip to
// white instead of leaving the rest of the luminaire black.
double white_point(const sim::LuminanceImage& img) {
  std::vector<double> lit;
  for (double l : img.cd_m2)
    if (l > 0.0) lit.push_back(l);
  if (lit.empty()) return 0.0;
  const std::size_t k = static_cast<std::size_t>(0.995 * static_cast<double>(lit.size() - 1));
  std::nth_element(lit.begin(), lit.begin() + static_cast<std::ptrdiff_t>(k), lit.end());
  return lit[k];
}

// False colour on a log scale over three decades below the white point
// (brighter clips to white): black → blue → red → yellow → white. Crops
// under 256 pixels are enlarged (pixel copies), over 384 reduced to block
// means.
Image8 picture(const sim::LuminanceImage& img, const Crop& c) {
  const int up = std::max(1, 256 / c.side);
  const int down = c.side > 384 ? (c.side + 383) / 384 : 1;
  Image8 out;
  out.width = out.height = c.side * up / down;
  out.channels = 3;
  out.pixels.assign(static_cast<std::size_t>(out.width) * static_cast<std::size_t>(out.height) * 3, 0);
  const double stops[5][3] = {{0, 0, 0}, {30, 40, 160}, {200, 40, 40}, {250, 220, 60}, {255, 255, 255}};
  const int n = img.plane.pixels;
  const double white = white_point(img);
  const auto at = [&](int x, int y) {
    return img.cd_m2[static_cast<std::size_t>(c.y0 + y) * static_cast<std::size_t>(n) + static_cast<std::size_t>(c.x0 + x)];
  };
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      double l = 0.0;
      if (down > 1) {
        for (int j = 0; j < down; ++j)
          for (int i = 0; i < down; ++i) l += at(std::min(c.side - 1, x * down + i), std::min(c.side - 1, y * down + j));
        l /= down * down;
      } else {
        l = at(x / up, y / up);
      }
      if (!(l > 0.0) || !(white > 0.0)) continue;
      const double t = std::clamp(1.0 + std::log10(l / white) / 3.0, 0.0, 1.0) * 4.0;
      const int i = std::min(3, static_cast<int>(t));
      const double f = t - i;
      std::uint8_t* p = &out.pixels[(static_cast<std::size_t>(y) * static_cast<std::size_t>(out.width) +
                                     static_cast<std::size_t>(x)) * 3];
      for (int k = 0; k < 3; ++k)
        p[k] = static_cast<std::uint8_t>(stops[i][k] + f * (stops[i + 1][k] - stops[i][k]));
    }
  return out;
}

nlohmann::json number_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

}  // namespace

nlohmann::json luminance_thumbnails(const std::vector<sim::LuminanceImage>& images) {
  nlohmann::json out = nlohmann::json::array();
  for (const sim::LuminanceImage& img : images)
    out.push_back({{"c_deg", img.plane.view.c_deg},
                   {"gamma_deg", img.plane.view.gamma_deg},
                   {"intensity_cd", img.intensity_cd},
                   {"max_cd_m2", img.max_cd_m2},
                   {"thumbnail", thumbnail(img, lit_square(img))}});
  return out;
}

std::string luminance_image_name(const std::string& stem, const sim::LuminanceView& view) {
  return stem + ".luminance-C" + format_number(view.c_deg) + "-G" + format_number(view.gamma_deg) + ".exr";
}

photometry::NonUniformGlare cie232_of(const sim::LuminanceImage& image, const photometry::LuminousOpening& opening,
                                      const photometry::NonUniformGlareParameters& parameters) {
  photometry::LuminanceMap map;
  map.width = map.height = image.plane.pixels;
  map.pixel_m = image.plane.pixel_m;
  map.cd_m2 = image.cd_m2;
  const double ap = photometry::projected_area_m2(opening, image.plane.view.c_deg, image.plane.view.gamma_deg);
  return photometry::analyse_non_uniform_glare(map, image.intensity_cd, ap, parameters);
}

LargestDeltaUgr largest_delta_ugr(const std::vector<sim::LuminanceImage>& images,
                                  const photometry::LuminousOpening& opening,
                                  const photometry::NonUniformGlareParameters& parameters) {
  LargestDeltaUgr out;
  for (std::size_t i = 0; i < images.size(); ++i) {
    photometry::NonUniformGlare g = cie232_of(images[i], opening, parameters);
    // As write_luminance_images chooses: the first of equal largest values.
    if (g.defined && !(g.delta_ugr <= out.delta_ugr)) {
      out.delta_ugr = g.delta_ugr;
      out.image = i;
      out.glare = std::move(g);
    }
  }
  return out;
}

LuminanceOutputs write_luminance_images(const std::string& out_dir, const std::string& stem,
                                        const std::vector<sim::LuminanceImage>& images,
                                        const photometry::LuminousOpening& opening, double cone_deg,
                                        const photometry::NonUniformGlareParameters& parameters) {
  LuminanceOutputs out;
  double best = photometry::kNaN;
  const sim::LuminanceView* best_view = nullptr;
  for (const sim::LuminanceImage& img : images) {
    const sim::LuminanceView& view = img.plane.view;
    const std::string name = luminance_image_name(stem, view);
    const std::string path = (std::filesystem::path(out_dir) / name).string();
    ExrImage exr;
    exr.width = exr.height = img.plane.pixels;
    exr.float_channels.push_back({"L", std::vector<float>(img.cd_m2.begin(), img.cd_m2.end())});
    if (!img.cie_x.empty()) {
      exr.float_channels.push_back({"x", std::vector<float>(img.cie_x.begin(), img.cie_x.end())});
      exr.float_channels.push_back({"y", std::vector<float>(img.cie_y.begin(), img.cie_y.end())});
    }
    exr.attributes = {
        {"gonio:quantity", img.cie_x.empty() ? "luminance L" : "luminance L, CIE 1931 chromaticity x, y"},
        {"gonio:units", "cd/m2"},
        {"gonio:view", "C " + format_number(view.c_deg) + " deg, gamma " + format_number(view.gamma_deg) +
                           " deg (the observer at infinity in that direction of the photometric frame)"},
        {"gonio:pixel_size_m", format_number(img.plane.pixel_m)},
        {"gonio:cone_deg", format_number(cone_deg)},
        {"gonio:axes", "orthographic; rows from the top (the zenith projected), columns to the observer's right"}};
    // The PNG: log scale over three decades below the 99.5th percentile of
    // the lit pixels (brighter clips to white).
    if (Status s = write_exr(path, exr); !s.ok()) out.failures.push_back(s.error());
    else out.written.push_back(path);
    const Crop crop = lit_square(img);
    const std::string png_name = name.substr(0, name.size() - 4) + ".png";
    const std::string png_path = (std::filesystem::path(out_dir) / png_name).string();
    if (Status s = write_png(png_path, picture(img, crop)); !s.ok()) out.failures.push_back(s.error());
    else out.written.push_back(png_path);

    const photometry::NonUniformGlare g = cie232_of(img, opening, parameters);
    nlohmann::json cie = {{"defined", g.defined},
                          {"intensity_cd", number_or_null(g.intensity_cd)},
                          {"projected_area_m2", number_or_null(g.projected_area_m2)},
                          {"mean_luminance_cd_m2", number_or_null(g.mean_luminance_cd_m2)},
                          {"glare_area_m2", number_or_null(g.glare_area_m2)},
                          {"glare_luminance_cd_m2", number_or_null(g.glare_luminance_cd_m2)},
                          {"peak_filtered_cd_m2", number_or_null(g.peak_filtered_cd_m2)},
                          {"k2", number_or_null(g.k2)},
                          {"delta_ugr", number_or_null(g.delta_ugr)},
                          {"corrected_projected_area_m2", number_or_null(g.corrected_projected_area_m2)},
                          {"resolution_ok", g.resolution_ok}};
    if (!g.defined) cie["why_undefined"] = g.why_undefined;
    if (g.defined && !(g.delta_ugr <= best)) {
      best = g.delta_ugr;
      best_view = &view;
    }
    out.images.push_back({{"c_deg", view.c_deg},
                          {"gamma_deg", view.gamma_deg},
                          {"file", name},
                          {"picture", png_name},
                          {"pixels", img.plane.pixels},
                          {"pixel_m", img.plane.pixel_m},
                          {"cone_deg", cone_deg},
                          {"intensity_cd", img.intensity_cd},
                          {"max_cd_m2", img.max_cd_m2},
                          {"thumbnail", thumbnail(img, crop)},
                          {"cie232", cie}});
  }
  out.cie232 = {{"delta_ugr", number_or_null(best)},
                {"eye_resolution_mm", parameters.eye_resolution_m * 1000.0},
                {"threshold_cd_m2", parameters.threshold_cd_m2},
                {"method",
                 "CIE 232:2019 (with CIE TN 014:2023 and TechnoTeam's DUGR Calculator 1.5.0): the luminance image "
                 "filtered by a Gaussian of 12 mm FWHM, the glare source where it reaches 500 cd/m2, k2 = "
                 "L_eff^2 A_p,eff A_p / I^2, delta UGR = 8 log10 k2; the largest over the views"}};
  if (best_view) {
    out.cie232["c_deg"] = best_view->c_deg;
    out.cie232["gamma_deg"] = best_view->gamma_deg;
  }
  return out;
}

}  // namespace gonio::io
