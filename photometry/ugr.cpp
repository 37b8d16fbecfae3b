#include "photometry/ugr.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "photometry/flux.h"
#include "photometry/intensity_sampler.h"
#include "photometry/luminance.h"

namespace gonio::photometry {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr double kH = 2.0;  // luminaire plane above the eye [m]

// Guth's position index (CIE 117:1995), α and β in degrees.
double position_index(double alpha_deg, double beta_deg) {
  const double a = alpha_deg, b = beta_deg;
  const double ln_p = (35.2 - 0.31889 * a - 1.22 * std::exp(-2.0 * a / 9.0)) * 1e-3 * b +
                      (21.0 + 0.26667 * a - 0.002963 * a * a) * 1e-5 * b * b;
  return std::exp(ln_p);
}

// The luminaire's intensity on a 1° (C) × 0.25° (γ) midpoint grid of the
// lower hemisphere, weighted by its cell's solid angle: flux per cell [lm].
struct LowerHemisphere {
  static constexpr int kPlanes = 360, kRings = 360;
  std::vector<double> flux_lm;  // [plane * kRings + ring]
  std::vector<double> tan_g;    // per ring
  double down_lm = 0.0, up_lm = 0.0;
};

LowerHemisphere lower_hemisphere(const Distribution& d, const IntensitySampler& s) {
  LowerHemisphere h;
  const int np = LowerHemisphere::kPlanes, nr = LowerHemisphere::kRings;
  h.flux_lm.resize(static_cast<std::size_t>(np) * nr);
  h.tan_g.resize(nr);
  const double dc = 2 * kPi / np, dg = 0.5 * kPi / nr;
  double sum = 0.0;
  for (int j = 0; j < nr; ++j) h.tan_g[j] = std::tan((j + 0.5) * dg);
  for (int i = 0; i < np; ++i)
    for (int j = 0; j < nr; ++j) {
      const double g = (j + 0.5) * dg;
      const double f = s.cd((i + 0.5) * dc / kDeg, g / kDeg) * std::sin(g) * dc * dg;
      h.flux_lm[i * nr + j] = f;
      sum += f;
    }
  // Scale to the exact quadrature of photometry/flux.h.
  h.down_lm = downward_flux_lm(d);
  h.up_lm = upward_flux_lm(d);
  if (sum > 0.0)
    for (double& f : h.flux_lm) f *= h.down_lm / sum;
  return h;
}

// Fraction of the downward flux of a uniform array that lands on the floor
// plane X × Y at H below (room axes; the luminaire's C0 along room x, or
// along room y when endwise).
double floor_fraction(const LowerHemisphere& h, double x, double y, bool endwise) {
  if (h.down_lm <= 0.0) return 0.0;
  const int np = LowerHemisphere::kPlanes, nr = LowerHemisphere::kRings;
  double direct = 0.0;
  for (int i = 0; i < np; ++i) {
    const double c = (i + 0.5) * 2 * kPi / np;
    double cx = std::abs(std::cos(c)), cy = std::abs(std::sin(c));
    if (endwise) std::swap(cx, cy);
    for (int j = 0; j < nr; ++j) {
      const double t = h.tan_g[j] * kH;
      const double p = std::max(0.0, 1.0 - t * cx / x) * std::max(0.0, 1.0 - t * cy / y);
      if (p <= 0.0) break;  // farther rings land on the walls too
      direct += h.flux_lm[i * nr + j] * p;
    }
  }
  return direct / h.down_lm;
}

struct Prepared {
  const IntensitySampler& sampler;
  LowerHemisphere hemi;
  const Distribution& d;
};

// What a room and orientation give, whatever the reflectances.
struct RoomView {
  double x = 0, y = 0;          // [m]
  double n = 0;                 // luminaires
  double on_floor_lm = 0;       // downward flux landing directly on the floor plane [lm]
  double sum = 0;               // Σ L² ω / p² [(cd/m²)² sr]
};

RoomView room_view(const Prepared& p, double x_h, double y_h, bool endwise, double spacing_h) {
  RoomView v;
  v.x = x_h * kH;
  v.y = y_h * kH;
  const double S = spacing_h * kH;
  const int nx = std::max(1, static_cast<int>(std::lround(v.x / S)));
  const int ny = std::max(1, static_cast<int>(std::lround(v.y / S)));
  v.n = static_cast<double>(nx) * ny;
  v.on_floor_lm = v.n * p.hemi.down_lm * floor_fraction(p.hemi, v.x, v.y, endwise);
  const double ox = v.x / 2;
  for (int i = 0; i < nx; ++i) {
    const double lx_room = (i + 0.5) * S;
    for (int j = 0; j < ny; ++j) {
      const double ly_room = (j + 0.5) * S;
      // From the luminaire to the eye, room axes.
      const double vx = ox - lx_room, vy = -ly_room;
      const double horiz = std::hypot(vx, vy);
      // The same in the luminaire's frame (C90 is 90° counter-clockwise of C0).
      const double fx = endwise ? vy : vx, fy = endwise ? -vx : vy;
      double c_deg = std::atan2(fy, fx) / kDeg;
      if (c_deg < 0) c_deg += 360;
      const double g_deg = std::atan2(horiz, kH) / kDeg;
      const double i_cd = p.sampler.cd(c_deg, g_deg);
      if (i_cd <= 0.0) continue;
      const double ap = projected_area_m2(p.d.opening, c_deg, g_deg);
      if (ap <= 0.0) continue;
      const double r2 = horiz * horiz + kH * kH;
      const double t = std::abs(vx), r = ly_room;
      const double alpha = std::atan2(t, kH) / kDeg;
      const double beta = std::atan2(std::hypot(t, kH), r) / kDeg;
      const double pidx = position_index(alpha, beta);
      v.sum += i_cd * i_cd / (ap * r2 * pidx * pidx);  // L² ω / p²
    }
  }
  return v;
}

double ugr_of(const Prepared& p, const RoomView& v, const std::array<double, 3>& rho) {
  // Background luminance from the flux transfer of the box.
  const double af = v.x * v.y, aw = 2 * (v.x + v.y) * kH;
  const double f_fc = facing_rectangles_view_factor(v.x, v.y, kH);
  const double f_fw = 1 - f_fc, f_wf = f_fw * af / aw, f_ww = 1 - 2 * f_wf;
  const double down = v.n * p.hemi.down_lm, up = v.n * p.hemi.up_lm;
  // Direct flux onto ceiling, walls, floor; solve in = direct + Fᵀ ρ in.
  const double dir_c = up, dir_w = down - v.on_floor_lm, dir_f = v.on_floor_lm;
  const double rc = rho[0], rw = rho[1], rf = rho[2];
  // in_c = dir_c + f_fc rf in_f + f_wf rw in_w
  // in_w = dir_w + f_fw rc in_c + f_fw rf in_f + f_ww rw in_w
  // in_f = dir_f + f_fc rc in_c + f_wf rw in_w
  double m[3][4] = {{1, -f_wf * rw, -f_fc * rf, dir_c},
                    {-f_fw * rc, 1 - f_ww * rw, -f_fw * rf, dir_w},
                    {-f_fc * rc, -f_wf * rw, 1, dir_f}};
  for (int k = 0; k < 3; ++k) {
    for (int r = k + 1; r < 3; ++r) {
      const double q = m[r][k] / m[k][k];
      for (int c = k; c < 4; ++c) m[r][c] -= q * m[k][c];
    }
  }
  double in[3];
  for (int k = 2; k >= 0; --k) {
    double val = m[k][3];
    for (int c = k + 1; c < 3; ++c) val -= m[k][c] * in[c];
    in[k] = val / m[k][k];
  }
  const double e_indirect = (in[1] - dir_w) / aw;
  const double lb = e_indirect / kPi;
  if (!(lb > 0.0) || !(v.sum > 0.0)) return kNaN;
  return 8.0 * std::log10(0.25 / lb * v.sum);
}

}  // namespace

std::vector<std::array<double, 2>> ugr_room_sizes() {
  std::vector<std::array<double, 2>> rooms;
  for (double x : {2.0, 4.0})
    for (double y : {2.0, 3.0, 4.0, 6.0, 8.0, 12.0}) rooms.push_back({x, y});
  for (double y : {4.0, 6.0, 8.0, 12.0}) rooms.push_back({8.0, y});
  for (double y : {4.0, 6.0, 8.0}) rooms.push_back({12.0, y});
  return rooms;
}

double ugr(const Distribution& d, double x_h, double y_h, const std::array<double, 3>& reflectances,
           bool endwise, double spacing_h) {
  GONIO_CHECK_MSG(validate(d).ok(), "ugr needs a valid distribution");
  const IntensitySampler s(d);
  const Prepared p{s, lower_hemisphere(d, s), d};
  return ugr_of(p, room_view(p, x_h, y_h, endwise, spacing_h), reflectances);
}

UgrTable ugr_table(const Distribution& d) {
  GONIO_CHECK_MSG(validate(d).ok(), "ugr_table needs a valid distribution");
  UgrTable t;
  t.flux_lm = total_flux_lm(d);
  if (projected_area_m2(d.opening, 0.0, 60.0) <= 0.0 && projected_area_m2(d.opening, 90.0, 60.0) <= 0.0) {
    t.why_undefined = "no luminous area toward the observer (point opening or one facing away): "
                      "UGR needs the luminaire's luminance";
    return t;
  }
  if (!(downward_flux_lm(d) > 0.0) && !(upward_flux_lm(d) > 0.0)) {
    t.why_undefined = "the distribution emits no light";
    return t;
  }
  const IntensitySampler s(d);
  const Prepared p{s, lower_hemisphere(d, s), d};
  for (const auto& [x, y] : ugr_room_sizes()) {
    UgrRoom room;
    room.x_h = x;
    room.y_h = y;
    const RoomView cross = room_view(p, x, y, false, t.spacing_h);
    const RoomView end = room_view(p, x, y, true, t.spacing_h);
    for (std::size_t k = 0; k < kUgrReflectances.size(); ++k) {
      room.crosswise[k] = ugr_of(p, cross, kUgrReflectances[k]);
      room.endwise[k] = ugr_of(p, end, kUgrReflectances[k]);
    }
    t.rooms.push_back(room);
  }
  bool any = false;
  for (const UgrRoom& r : t.rooms)
    for (std::size_t k = 0; k < kUgrReflectances.size(); ++k)
      any = any || std::isfinite(r.crosswise[k]) || std::isfinite(r.endwise[k]);
  if (!any) {
    t.rooms.clear();
    t.why_undefined = "no light from the luminaires reaches the observer's eye (e.g. an uplight)";
    return t;
  }
  t.defined = true;
  return t;
}

}  // namespace gonio::photometry
