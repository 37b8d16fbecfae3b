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

// A floor plane X × Y at H below a uniform array of luminaires (room axes;
// the luminaire's C0 along room x, or along room y when endwise), and the
// share of the array's downward flux that lands on it directly.
struct FloorPlane {
  double x_m = 0.0, y_m = 0.0;
  bool endwise = false;
  double fraction = 0.0;  // [1], filled by direct_floor_fractions()
};

// Fills every floor's `fraction`: the luminaire's intensity on a 1° (C) ×
// 0.25° (γ) midpoint grid of the lower hemisphere, weighted by its cell's
// solid angle; a ring at horizontal distance t = H tan γ along C lands from
// the share P = (1 − t|cos C|/X)₊ (1 − t|sin C|/Y)₊ of the luminaire
// positions. P falls with γ, so per plane the rings that land are a prefix,
// and Σ flux·P over it is Σflux − (a + b) Σflux·t + ab Σflux·t² with
// a = |cos C|/X, b = |sin C|/Y: prefix sums along γ and one search per plane
// and floor. Planes are sampled a few at a time (little memory).
void direct_floor_fractions(const IntensitySampler& s, std::vector<FloorPlane>& floors) {
  constexpr int kPlanes = 360, kRings = 360, kChunk = 24;
  static_assert(kPlanes % kChunk == 0);
  const double dc = 2 * kPi / kPlanes, dg = 0.5 * kPi / kRings;
  std::vector<double> g_deg(kRings), sin_g(kRings), t_m(kRings);
  for (int j = 0; j < kRings; ++j) {
    const double g = (j + 0.5) * dg;
    g_deg[j] = g / kDeg;
    sin_g[j] = std::sin(g);
    t_m[j] = std::tan(g) * kH;
  }
  std::vector<double> c_deg(kChunk), sum0(kRings + 1), sum1(kRings + 1), sum2(kRings + 1);
  std::vector<double> direct(floors.size(), 0.0);
  double total = 0.0;
  for (int first = 0; first < kPlanes; first += kChunk) {
    for (int k = 0; k < kChunk; ++k) c_deg[k] = (first + k + 0.5) * dc / kDeg;
    const std::vector<double> cd = s.grid(c_deg, g_deg);
    for (int k = 0; k < kChunk; ++k) {
      for (int j = 0; j < kRings; ++j) {
        const double f = cd[k * kRings + j] * sin_g[j] * dc * dg, t = t_m[j];
        sum0[j + 1] = sum0[j] + f;
        sum1[j + 1] = sum1[j] + f * t;
        sum2[j + 1] = sum2[j] + f * t * t;
      }
      total += sum0[kRings];
      const double c = (first + k + 0.5) * dc;
      const double abs_cos = std::abs(std::cos(c)), abs_sin = std::abs(std::sin(c));
      for (std::size_t q = 0; q < floors.size(); ++q) {
        const FloorPlane& fl = floors[q];
        const double cx = fl.endwise ? abs_sin : abs_cos, cy = fl.endwise ? abs_cos : abs_sin;
        const auto lands = [&](double t) {
          return std::max(0.0, 1.0 - t * cx / fl.x_m) * std::max(0.0, 1.0 - t * cy / fl.y_m) > 0.0;
        };
        const std::size_t n =
            static_cast<std::size_t>(std::partition_point(t_m.begin(), t_m.end(), lands) - t_m.begin());
        if (n == 0) continue;  // nothing lands (also a degenerate room of zero size)
        const double a = cx / fl.x_m, b = cy / fl.y_m;
        direct[q] += sum0[n] - (a + b) * sum1[n] + a * b * sum2[n];
      }
    }
  }
  for (std::size_t q = 0; q < floors.size(); ++q) floors[q].fraction = total > 0.0 ? direct[q] / total : 0.0;
}

// L² ω / p² of one luminaire seen from the eye, the luminaire at (vx, vy)
// from the eye in room axes [m] (vy ≤ 0: in front), its C0 along room x (or
// y when endwise) [(cd/m²)² sr]; 0 where it sends no light or shows no area.
double glare_term(const IntensitySampler& sampler, const LuminousOpening& opening, double vx, double vy,
                  bool endwise) {
  const double horiz = std::hypot(vx, vy);
  // The same in the luminaire's frame (C90 is 90° counter-clockwise of C0).
  const double fx = endwise ? vy : vx, fy = endwise ? -vx : vy;
  double c_deg = std::atan2(fy, fx) / kDeg;
  if (c_deg < 0) c_deg += 360;
  const double g_deg = std::atan2(horiz, kH) / kDeg;
  const double i_cd = sampler.cd(c_deg, g_deg);
  if (i_cd <= 0.0) return 0.0;
  const double ap = projected_area_m2(opening, c_deg, g_deg);
  if (ap <= 0.0) return 0.0;
  const double r2 = horiz * horiz + kH * kH;
  const double t = std::abs(vx), r = -vy;
  const double alpha = std::atan2(t, kH) / kDeg;
  const double beta = std::atan2(std::hypot(t, kH), r) / kDeg;
  const double pidx = position_index(alpha, beta);
  return i_cd * i_cd / (ap * r2 * pidx * pidx);
}

// glare_term() for the luminaire positions the rooms of one table share:
// with the walls on the spacing's grid, every luminaire sits at
// vx = (m/2) S, vy = −(j + ½) S from the eye for integers m, j, whatever
// the room, so each term is computed once per orientation (lazily; NaN marks
// one not computed yet). Positions off that grid are computed directly.
class GlareTerms {
 public:
  GlareTerms(const IntensitySampler& sampler, const LuminousOpening& opening, double spacing_m, int half_m,
             int rows)
      : sampler_(sampler), opening_(opening), spacing_m_(spacing_m), half_m_(half_m), rows_(rows) {
    for (auto& t : terms_) t.assign(static_cast<std::size_t>(2 * half_m + 1) * rows, kNaN);
  }

  double at(double vx, double vy, int j, bool endwise) {
    const double m = 2.0 * vx / spacing_m_;
    const double mi = std::round(m);
    if (m != mi || std::abs(mi) > half_m_ || j < 0 || j >= rows_ || vy != -(j + 0.5) * spacing_m_)
      return glare_term(sampler_, opening_, vx, vy, endwise);
    double& slot = terms_[endwise][static_cast<std::size_t>(static_cast<int>(mi) + half_m_) * rows_ + j];
    if (std::isnan(slot)) slot = glare_term(sampler_, opening_, vx, vy, endwise);
    return slot;
  }

 private:
  const IntensitySampler& sampler_;
  const LuminousOpening& opening_;
  double spacing_m_;
  int half_m_, rows_;
  std::vector<double> terms_[2];
};

struct Prepared {
  double down_lm = 0.0, up_lm = 0.0;  // of one luminaire, the exact quadrature of photometry/flux.h
  GlareTerms& terms;
};

// What a room and orientation give, whatever the reflectances.
struct RoomView {
  double x = 0, y = 0;          // [m]
  double n = 0;                 // luminaires
  double on_floor_lm = 0;       // downward flux landing directly on the floor plane [lm]
  double sum = 0;               // Σ L² ω / p² [(cd/m²)² sr]
};

// `floor_fraction`: direct_floor_fractions() of this room and orientation.
RoomView room_view(const Prepared& p, double x_h, double y_h, bool endwise, double spacing_h,
                   double floor_fraction) {
  RoomView v;
  v.x = x_h * kH;
  v.y = y_h * kH;
  const double S = spacing_h * kH;
  const int nx = std::max(1, static_cast<int>(std::lround(v.x / S)));
  const int ny = std::max(1, static_cast<int>(std::lround(v.y / S)));
  v.n = static_cast<double>(nx) * ny;
  v.on_floor_lm = v.n * p.down_lm * floor_fraction;
  const double ox = v.x / 2;
  for (int i = 0; i < nx; ++i) {
    const double lx_room = (i + 0.5) * S;
    for (int j = 0; j < ny; ++j) {
      const double ly_room = (j + 0.5) * S;
      // From the luminaire to the eye, room axes.
      v.sum += p.terms.at(ox - lx_room, -ly_room, j, endwise);
    }
  }
  return v;
}

double ugr_of(const Prepared& p, const RoomView& v, const std::array<double, 3>& rho) {
  // Background luminance from the flux transfer of the box.
  const double af = v.x * v.y, aw = 2 * (v.x + v.y) * kH;
  const double f_fc = facing_rectangles_view_factor(v.x, v.y, kH);
  const double f_fw = 1 - f_fc, f_wf = f_fw * af / aw, f_ww = 1 - 2 * f_wf;
  const double down = v.n * p.down_lm, up = v.n * p.up_lm;
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
  GlareTerms terms(s, d.opening, spacing_h * kH, 0, 0);
  const Prepared p{downward_flux_lm(d), upward_flux_lm(d), terms};
  std::vector<FloorPlane> floor{{x_h * kH, y_h * kH, endwise, 0.0}};
  direct_floor_fractions(s, floor);
  return ugr_of(p, room_view(p, x_h, y_h, endwise, spacing_h, floor[0].fraction), reflectances);
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
  const std::vector<std::array<double, 2>> sizes = ugr_room_sizes();
  std::vector<FloorPlane> floors;  // crosswise, endwise per room
  double max_x_h = 0.0, max_y_h = 0.0;  // bound the luminaire positions (GlareTerms)
  for (const auto& [x, y] : sizes) {
    for (bool endwise : {false, true}) floors.push_back({x * kH, y * kH, endwise, 0.0});
    max_x_h = std::max(max_x_h, x);
    max_y_h = std::max(max_y_h, y);
  }
  GlareTerms terms(s, d.opening, t.spacing_h * kH, static_cast<int>(std::lround(max_x_h / t.spacing_h)),
                   static_cast<int>(std::lround(max_y_h / t.spacing_h)));
  const Prepared p{downward_flux_lm(d), upward_flux_lm(d), terms};
  direct_floor_fractions(s, floors);
  for (std::size_t r = 0; r < sizes.size(); ++r) {
    const auto [x, y] = sizes[r];
    UgrRoom room;
    room.x_h = x;
    room.y_h = y;
    const RoomView cross = room_view(p, x, y, false, t.spacing_h, floors[2 * r].fraction);
    const RoomView end = room_view(p, x, y, true, t.spacing_h, floors[2 * r + 1].fraction);
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
