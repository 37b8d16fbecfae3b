#include "design/revolved.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "photometry/format.h"

namespace gonio::design {
namespace {

constexpr std::size_t kFineSamples = 4096;  // the profile's samples for tessellation and distances
constexpr double kRowsPerDeflection = 0.25;  // the rows' tangent turn per angular deflection (revolved.h)

// d/dx at nodes[0] of the polynomial through (nodes[i], values[i]).
double end_slope(const double* x, const double* y, std::size_t m) {
  double slope = 0.0;
  for (std::size_t j = 0; j < m; ++j) {
    double dl = 0.0;  // L_j'(x[0])
    if (j == 0) {
      for (std::size_t k = 1; k < m; ++k) dl += 1.0 / (x[0] - x[k]);
    } else {
      double num = 1.0, den = 1.0;
      for (std::size_t k = 0; k < m; ++k) {
        if (k == j) continue;
        den *= x[j] - x[k];
        if (k != 0) num *= x[0] - x[k];
      }
      dl = num / den;
    }
    slope += dl * y[j];
  }
  return slope;
}

// Slopes of the clamped cubic spline through (x, y): end slopes from the
// cubic through the four nearest nodes (fewer where there are fewer).
std::vector<double> spline_slopes(const std::vector<double>& x, const std::vector<double>& y) {
  const std::size_t n = x.size();
  std::vector<double> m(n, 0.0);
  if (n == 2) {
    m[0] = m[1] = (y[1] - y[0]) / (x[1] - x[0]);
    return m;
  }
  const std::size_t e = std::min<std::size_t>(n, 4);
  m[0] = end_slope(x.data(), y.data(), e);
  {
    std::vector<double> xr(x.rbegin(), x.rbegin() + static_cast<std::ptrdiff_t>(e));
    std::vector<double> yr(y.rbegin(), y.rbegin() + static_cast<std::ptrdiff_t>(e));
    m[n - 1] = end_slope(xr.data(), yr.data(), e);
  }
  // Interior: h_i m_{i−1} + 2(h_{i−1} + h_i) m_i + h_{i−1} m_{i+1} = 3(h_i δ_{i−1} + h_{i−1} δ_i).
  const std::size_t k = n - 2;
  std::vector<double> a(k), b(k), c(k), d(k);
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const double h0 = x[i] - x[i - 1], h1 = x[i + 1] - x[i];
    const double d0 = (y[i] - y[i - 1]) / h0, d1 = (y[i + 1] - y[i]) / h1;
    a[i - 1] = h1;
    b[i - 1] = 2.0 * (h0 + h1);
    c[i - 1] = h0;
    d[i - 1] = 3.0 * (h1 * d0 + h0 * d1);
  }
  d[0] -= a[0] * m[0];
  d[k - 1] -= c[k - 1] * m[n - 1];
  // Thomas algorithm.
  for (std::size_t i = 1; i < k; ++i) {
    const double w = a[i] / b[i - 1];
    b[i] -= w * c[i - 1];
    d[i] -= w * d[i - 1];
  }
  m[k] = d[k - 1] / b[k - 1];
  for (std::size_t i = k - 1; i-- > 0;) m[i + 1] = (d[i] - c[i] * m[i + 2]) / b[i];
  return m;
}

double conic_root(const ConicProfile& p, double rho) {
  const double c = p.radius != 0.0 ? 1.0 / p.radius : 0.0;
  return 1.0 - (1.0 + p.conic) * c * c * rho * rho;
}

// The clamped uniform knot vector of n control points and degree p.
std::vector<double> clamped_knots(std::size_t n, int p) {
  const std::size_t m = n + static_cast<std::size_t>(p) + 1;
  std::vector<double> u(m);
  const std::size_t spans = n - static_cast<std::size_t>(p);
  for (std::size_t i = 0; i < m; ++i) {
    const double k = static_cast<double>(std::clamp<std::ptrdiff_t>(
        static_cast<std::ptrdiff_t>(i) - p, 0, static_cast<std::ptrdiff_t>(spans)));
    u[i] = k / static_cast<double>(spans);
  }
  return u;
}

// de Boor: the point of the B-spline of degree p with knots u and control
// values c at t.
double de_boor(const std::vector<double>& u, const std::vector<double>& c, int p, double t) {
  const std::size_t n = c.size();
  std::size_t k = static_cast<std::size_t>(p);
  while (k + 1 < n && t >= u[k + 1]) ++k;
  std::vector<double> d(static_cast<std::size_t>(p) + 1);
  for (int j = 0; j <= p; ++j) d[static_cast<std::size_t>(j)] = c[k - static_cast<std::size_t>(p) + static_cast<std::size_t>(j)];
  for (int r = 1; r <= p; ++r)
    for (int j = p; j >= r; --j) {
      const std::size_t i = k - static_cast<std::size_t>(p) + static_cast<std::size_t>(j);
      const double den = u[i + static_cast<std::size_t>(p - r) + 1] - u[i];
      const double a = den > 0.0 ? (t - u[i]) / den : 0.0;
      d[static_cast<std::size_t>(j)] = (1.0 - a) * d[static_cast<std::size_t>(j) - 1] + a * d[static_cast<std::size_t>(j)];
    }
  return d[static_cast<std::size_t>(p)];
}

// The point and derivative of a B-spline profile at t.
void bspline_eval(const BSplineProfile& b, double t, double& rho, double& z, double& drho, double& dz) {
  const std::size_t n = b.rho.size();
  const int p = b.degree;
  const std::vector<double> u = clamped_knots(n, p);
  rho = de_boor(u, b.rho, p, t);
  z = de_boor(u, b.z, p, t);
  // The derivative: degree p − 1 over the inner knots, Q_i = p (P_{i+1} − P_i)/(u_{i+p+1} − u_{i+1}).
  std::vector<double> qr(n - 1), qz(n - 1);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double den = u[i + static_cast<std::size_t>(p) + 1] - u[i + 1];
    const double w = den > 0.0 ? p / den : 0.0;
    qr[i] = w * (b.rho[i + 1] - b.rho[i]);
    qz[i] = w * (b.z[i + 1] - b.z[i]);
  }
  const std::vector<double> inner(u.begin() + 1, u.end() - 1);
  drho = p > 1 ? de_boor(inner, qr, p - 1, t) : qr[std::min<std::size_t>(static_cast<std::size_t>(t * static_cast<double>(n - 1)), n - 2)];
  dz = p > 1 ? de_boor(inner, qz, p - 1, t) : qz[std::min<std::size_t>(static_cast<std::size_t>(t * static_cast<double>(n - 1)), n - 2)];
}

}  // namespace

// Whether segments ab and cd cross (touching ends of neighbours excepted by the caller).
bool segments_cross(double ax, double ay, double bx, double by, double cx, double cy, double dx, double dy) {
  auto orient = [](double px, double py, double qx, double qy, double rx, double ry) {
    const double v = (qx - px) * (ry - py) - (qy - py) * (rx - px);
    return (v > 0.0) - (v < 0.0);
  };
  const int o1 = orient(ax, ay, bx, by, cx, cy), o2 = orient(ax, ay, bx, by, dx, dy);
  const int o3 = orient(cx, cy, dx, dy, ax, ay), o4 = orient(cx, cy, dx, dy, bx, by);
  return o1 * o2 < 0 && o3 * o4 < 0;
}

double polar_r(const PolarProfile& p, double theta, double* dlnr) {
  // Slopes are recomputed here for a one-off evaluation; ProfileCurve keeps them.
  std::vector<double> y(p.r.size());
  for (std::size_t i = 0; i < y.size(); ++i) y[i] = std::log(p.r[i]);
  const std::vector<double> m = spline_slopes(p.theta, y);
  const std::size_t n = p.theta.size();
  std::size_t i = static_cast<std::size_t>(std::upper_bound(p.theta.begin(), p.theta.end(), theta) - p.theta.begin());
  i = std::clamp<std::size_t>(i, 1, n - 1) - 1;
  const double h = p.theta[i + 1] - p.theta[i];
  const double s = (theta - p.theta[i]) / h;
  const double s2 = s * s, s3 = s2 * s;
  const double v = (2 * s3 - 3 * s2 + 1) * y[i] + (s3 - 2 * s2 + s) * h * m[i] + (-2 * s3 + 3 * s2) * y[i + 1] +
                   (s3 - s2) * h * m[i + 1];
  if (dlnr)
    *dlnr = ((6 * s2 - 6 * s) * y[i] + (3 * s2 - 4 * s + 1) * h * m[i] + (-6 * s2 + 6 * s) * y[i + 1] +
             (3 * s2 - 2 * s) * h * m[i + 1]) /
            h;
  return std::exp(v);
}

namespace {
Result<ProfileCurve> finite_or_error(Result<ProfileCurve> curve) {
  if (!curve.ok()) return curve;
  for (int k = 0; k <= 1024; ++k) {
    const double t = curve->t0() + (curve->t1() - curve->t0()) * k / 1024.0;
    double rho = 0, z = 0, dr = 0, dz = 0;
    curve->eval(t, rho, z, dr, dz);
    if (!(std::isfinite(rho) && std::isfinite(z) && std::isfinite(dr) && std::isfinite(dz) && std::abs(rho) < 1e6 &&
          std::abs(z) < 1e6))
      return make_error("the profile leaves any size a luminaire has (|ρ|, |z| above 1000 km, or not finite) near its " +
                        std::string(k == 0 ? "start" : k == 1024 ? "end" : "middle"));
  }
  return curve;
}
}  // namespace

Result<ProfileCurve> ProfileCurve::make(const Profile& profile) { return finite_or_error(make_unchecked(profile)); }

Result<ProfileCurve> ProfileCurve::make_unchecked(const Profile& profile) {
  ProfileCurve out;
  out.profile_ = profile;
  if (const auto* c = std::get_if<ConicProfile>(&profile)) {
    if (!(c->inner >= 0.0 && c->outer > c->inner))
      return make_error("the aperture must be [inner, outer] with 0 ≤ inner < outer");
    for (double rho : {c->inner, c->outer})
      if (!(conic_root(*c, rho) > 1e-12))
        return make_error("the conic (radius " + format_number(c->radius * 1e3) + " mm, conic " +
                          format_number(c->conic) + ") is not defined out to ρ = " + format_number(rho * 1e3) +
                          " mm: its surface turns back before it (1 − (1+κ)ρ²/R² ≤ 0)");
    out.t0_ = c->inner;
    out.t1_ = c->outer;
    return out;
  }
  if (const auto* b = std::get_if<BSplineProfile>(&profile)) {
    if (b->degree < 1 || b->degree > 5) return make_error("the degree must be 1 … 5");
    if (b->rho.size() < static_cast<std::size_t>(b->degree) + 1)
      return make_error("a B-spline of degree " + std::to_string(b->degree) + " needs at least " +
                        std::to_string(b->degree + 1) + " points");
    for (std::size_t i = 0; i < b->rho.size(); ++i)
      if (!(b->rho[i] >= 0.0))
        return make_error("points[" + std::to_string(i) + "] has ρ = " + format_number(b->rho[i] * 1e3) +
                          " mm: a profile of revolution stays on its side of the axis (ρ ≥ 0)");
    out.t0_ = 0.0;
    out.t1_ = 1.0;
    // Regular (no cusp) and simple (no crossing), on a polyline of the curve.
    constexpr std::size_t kCheck = 1024;
    std::vector<double> pr(kCheck + 1), pz(kCheck + 1);
    for (std::size_t k = 0; k <= kCheck; ++k) {
      double dr = 0, dzz = 0;
      bspline_eval(*b, static_cast<double>(k) / kCheck, pr[k], pz[k], dr, dzz);
      if (!(std::hypot(dr, dzz) > 0.0))
        return make_error("the profile has a cusp (a zero tangent) near (ρ, z) = (" + format_number(pr[k] * 1e3) + ", " +
                          format_number(pz[k] * 1e3) + ") mm");
    }
    for (std::size_t i = 0; i < kCheck; ++i)
      for (std::size_t j = i + 2; j < kCheck; ++j)
        if (segments_cross(pr[i], pz[i], pr[i + 1], pz[i + 1], pr[j], pz[j], pr[j + 1], pz[j + 1]))
          return make_error("the profile crosses itself near (ρ, z) = (" + format_number(pr[j] * 1e3) + ", " +
                            format_number(pz[j] * 1e3) + ") mm");
    return out;
  }
  const auto& p = std::get<PolarProfile>(profile);
  if (p.theta.size() != p.r.size()) return make_error("theta_deg and r must have as many values");
  if (p.theta.size() < 2) return make_error("a polar profile needs at least two points");
  for (std::size_t i = 0; i < p.theta.size(); ++i) {
    if (!(p.theta[i] >= 0.0 && p.theta[i] <= std::numbers::pi))
      return make_error("theta_deg[" + std::to_string(i) + "] = " + format_number(p.theta[i] * 180 / std::numbers::pi) +
                        " lies outside 0..180");
    if (i > 0 && !(p.theta[i] > p.theta[i - 1]))
      return make_error("theta_deg must increase (" + format_number(p.theta[i] * 180 / std::numbers::pi) + " after " +
                        format_number(p.theta[i - 1] * 180 / std::numbers::pi) +
                        "): a profile that turns back in θ crosses itself");
    if (!(p.r[i] > 0.0) || !std::isfinite(p.r[i]))
      return make_error("r[" + std::to_string(i) + "] = " + format_number(p.r[i] * 1e3) +
                        " mm: r must be > 0 (a profile through the origin passes through the source)");
  }
  std::vector<double> y(p.r.size());
  for (std::size_t i = 0; i < y.size(); ++i) y[i] = std::log(p.r[i]);
  out.slope_ = spline_slopes(p.theta, y);
  out.t0_ = p.theta.front();
  out.t1_ = p.theta.back();
  return out;
}

void ProfileCurve::eval(double t, double& rho, double& z, double& drho, double& dz) const {
  if (const auto* c = std::get_if<ConicProfile>(&profile_)) {
    const double cc = c->radius != 0.0 ? 1.0 / c->radius : 0.0;
    const double root = std::sqrt(std::max(conic_root(*c, t), 0.0));
    double sag = cc * t * t / (1.0 + root);
    double dsag = root > 0.0 ? cc * t / root : 0.0;
    double power = t * t * t;  // ρ^(2i−1) for i = 2
    for (std::size_t i = 0; i < c->aspheric.size(); ++i) {
      const double order = 2.0 * static_cast<double>(i + 2);
      sag += c->aspheric[i] * power * t;
      dsag += order * c->aspheric[i] * power;
      power *= t * t;
    }
    rho = t;
    z = c->vertex - sag;
    drho = 1.0;
    dz = -dsag;
    return;
  }
  if (const auto* b = std::get_if<BSplineProfile>(&profile_)) {
    bspline_eval(*b, t, rho, z, drho, dz);
    return;
  }
  const auto& p = std::get<PolarProfile>(profile_);
  const std::size_t n = p.theta.size();
  std::size_t i = static_cast<std::size_t>(std::upper_bound(p.theta.begin(), p.theta.end(), t) - p.theta.begin());
  i = std::clamp<std::size_t>(i, 1, n - 1) - 1;
  const double h = p.theta[i + 1] - p.theta[i];
  const double s = (t - p.theta[i]) / h;
  const double s2 = s * s, s3 = s2 * s;
  const double y0 = std::log(p.r[i]), y1 = std::log(p.r[i + 1]);
  const double y = (2 * s3 - 3 * s2 + 1) * y0 + (s3 - 2 * s2 + s) * h * slope_[i] + (-2 * s3 + 3 * s2) * y1 +
                   (s3 - s2) * h * slope_[i + 1];
  const double dy = ((6 * s2 - 6 * s) * y0 + (3 * s2 - 4 * s + 1) * h * slope_[i] + (-6 * s2 + 6 * s) * y1 +
                     (3 * s2 - 2 * s) * h * slope_[i + 1]) /
                    h;
  const double r = std::exp(y), dr = r * dy;
  rho = r * std::sin(t);
  z = -r * std::cos(t);
  drho = dr * std::sin(t) + r * std::cos(t);
  dz = -dr * std::cos(t) + r * std::sin(t);
}

bool ProfileCurve::piecewise_linear() const {
  const auto* b = std::get_if<BSplineProfile>(&profile_);
  return b && b->degree == 1;
}

std::vector<ProfileSample> sample_profile(const ProfileCurve& curve) {
  const bool linear = curve.piecewise_linear();
  std::vector<ProfileSample> fine(kFineSamples);
  for (std::size_t k = 0; k < kFineSamples; ++k) {
    ProfileSample& s = fine[k];
    s.t = curve.t0() + (curve.t1() - curve.t0()) * static_cast<double>(k) / static_cast<double>(kFineSamples - 1);
    curve.eval(s.t, s.rho, s.z, s.drho, s.dz);
    s.angle = std::atan2(s.dz, s.drho);
    if (k > 0) {  // unwrap
      while (s.angle - fine[k - 1].angle > std::numbers::pi) s.angle -= 2 * std::numbers::pi;
      while (s.angle - fine[k - 1].angle < -std::numbers::pi) s.angle += 2 * std::numbers::pi;
      // Within a straight span the tangent is the same to rounding.
      s.corner = linear && std::abs(s.angle - fine[k - 1].angle) > 1e-9;
    }
  }
  return fine;
}

std::vector<std::size_t> profile_rows(const std::vector<ProfileSample>& fine, double delta, double chordal) {
  std::vector<std::size_t> rows = {0};
  auto fits = [&](std::size_t a, std::size_t b) {
    if (std::abs(fine[b].angle - fine[a].angle) > delta * kRowsPerDeflection) return false;
    for (std::size_t k = a + 1; k <= b; ++k)
      if (fine[k].corner) return false;
    const double ex = fine[b].rho - fine[a].rho, ez = fine[b].z - fine[a].z;
    const double len = std::hypot(ex, ez);
    for (std::size_t k = a + 1; k < b; ++k) {
      const double d = len > 0.0 ? std::abs((fine[k].rho - fine[a].rho) * ez - (fine[k].z - fine[a].z) * ex) / len
                                 : std::hypot(fine[k].rho - fine[a].rho, fine[k].z - fine[a].z);
      if (d > chordal) return false;
    }
    return true;
  };
  const std::size_t n = fine.size();
  for (std::size_t k = 1; k < n; ++k)
    if (!fits(rows.back(), k)) rows.push_back(k - 1 > rows.back() ? k - 1 : k);
  if (rows.back() != n - 1) rows.push_back(n - 1);
  return rows;
}

RevolvedExtent revolved_extent(double rho_max, double z_min, double z_max, const io::CadTessellation& tess) {
  RevolvedExtent e;
  e.size = std::sqrt(8.0 * rho_max * rho_max + (z_max - z_min) * (z_max - z_min));
  e.chordal = tess.chordal_m > 0.0 ? tess.chordal_m : std::max(tess.chordal_relative * e.size, tess.chordal_min_m);
  return e;
}

std::size_t azimuth_segments(double rho_max, double delta, double chordal) {
  std::size_t segments = static_cast<std::size_t>(std::ceil(2.0 * std::numbers::pi / delta));
  if (rho_max > chordal) {
    const double by_chord = std::numbers::pi / std::acos(1.0 - chordal / rho_max);
    segments = std::max(segments, static_cast<std::size_t>(std::ceil(by_chord)));
  }
  return std::max<std::size_t>(segments, 8);
}

double normal_side(const std::vector<ProfileSample>& fine) {
  double facing = 0.0;
  for (const ProfileSample& s : fine) facing += (s.dz * -s.rho - s.drho * -s.z) / std::max(std::hypot(s.drho, s.dz), 1e-300);
  return facing >= 0.0 ? 1.0 : -1.0;
}

Result<io::CadSurface> revolve(const ProfileCurve& curve, const io::CadTessellation& tess, std::size_t max_triangles,
                               double* size_out, double* chordal_out, const RevolveOptions& extra) {
  using Sample = ProfileSample;
  const std::vector<Sample> fine = sample_profile(curve);
  double rho_max = 0.0, z_min = INFINITY, z_max = -INFINITY;
  for (const Sample& s : fine) {
    rho_max = std::max(rho_max, s.rho);
    z_min = std::min(z_min, s.z);
    z_max = std::max(z_max, s.z);
  }
  const auto [size, chordal] = revolved_extent(rho_max, z_min, z_max, tess);
  const double delta = tess.angular_deflection_deg * std::numbers::pi / 180.0;
  if (size_out) *size_out = size;
  if (chordal_out) *chordal_out = chordal;

  // Rows along the profile.
  const std::vector<std::size_t> rows = profile_rows(fine, delta, chordal);

  // Around the axis.
  const std::size_t segments = extra.segments > 0 ? extra.segments : azimuth_segments(rho_max, delta, chordal);
  if (2.0 * static_cast<double>(rows.size()) * static_cast<double>(segments) > static_cast<double>(max_triangles))
    return make_error("meshed to an angular deflection of " + format_number(tess.angular_deflection_deg) + "° it would take " +
                      format_number(2.0 * static_cast<double>(rows.size()) * static_cast<double>(segments), 3) +
                      " triangles, more than " + std::to_string(max_triangles) + ": coarsen the tessellation");

  // The normal's side: toward the origin (where the source sits) over the profile as a whole.
  const double side = extra.normal_side != 0 ? (extra.normal_side > 0 ? 1.0 : -1.0)
                                            : normal_side(fine);  // normal = side · (dz, −dρ)/|·|

  io::CadSurface out;
  const double pole = 1e-9 * size;
  std::vector<std::uint32_t> first(rows.size());
  std::vector<bool> is_pole(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Sample& s = fine[rows[i]];
    const double len = std::hypot(s.drho, s.dz);
    const double nr = side * s.dz / len, nz = -side * s.drho / len;
    first[i] = static_cast<std::uint32_t>(out.positions.size());
    is_pole[i] = s.rho <= pole;
    if (is_pole[i]) {
      out.positions.push_back({0.0f, 0.0f, static_cast<float>(s.z)});
      out.normals.push_back({0.0f, 0.0f, nz >= 0.0 ? 1.0f : -1.0f});
      continue;
    }
    for (std::size_t j = 0; j < segments; ++j) {
      const double psi = 2.0 * std::numbers::pi * static_cast<double>(j) / static_cast<double>(segments);
      const double c = std::cos(psi), sn = std::sin(psi);
      out.positions.push_back(sim::to_float(Vec3{s.rho * c, s.rho * sn, s.z}));
      out.normals.push_back(sim::to_float(Vec3{nr * c, nr * sn, nz}));
    }
  }
  auto vertex = [&](std::size_t row, std::size_t j) {
    return is_pole[row] ? first[row] : first[row] + static_cast<std::uint32_t>(j % segments);
  };
  auto push = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    if (a == b || b == c || a == c) return;
    // Counter-clockwise seen from the side the normals face.
    const Vec3 pa = sim::to_double(out.positions[a]), pb = sim::to_double(out.positions[b]),
               pc = sim::to_double(out.positions[c]);
    const Vec3 n = sim::to_double(out.normals[a]) + sim::to_double(out.normals[b]) + sim::to_double(out.normals[c]);
    if (dot(cross(pb - pa, pc - pa), n) < 0.0) std::swap(b, c);
    out.indices.insert(out.indices.end(), {a, b, c});
  };
  for (std::size_t i = 0; i + 1 < rows.size(); ++i)
    for (std::size_t j = 0; j < segments; ++j) {
      push(vertex(i, j), vertex(i, j + 1), vertex(i + 1, j + 1));
      push(vertex(i, j), vertex(i + 1, j + 1), vertex(i + 1, j));
    }
  return out;
}

double distance_to_profile(const ProfileCurve& curve, double rho, double z) {
  double best = INFINITY;
  double pr = 0, pz = 0, d1 = 0, d2 = 0;
  curve.eval(curve.t0(), pr, pz, d1, d2);
  for (std::size_t k = 1; k < kFineSamples; ++k) {
    const double t = curve.t0() + (curve.t1() - curve.t0()) * static_cast<double>(k) / static_cast<double>(kFineSamples - 1);
    double qr = 0, qz = 0;
    curve.eval(t, qr, qz, d1, d2);
    const double ex = qr - pr, ez = qz - pz, len2 = ex * ex + ez * ez;
    const double u = len2 > 0.0 ? std::clamp(((rho - pr) * ex + (z - pz) * ez) / len2, 0.0, 1.0) : 0.0;
    best = std::min(best, std::hypot(rho - (pr + u * ex), z - (pz + u * ez)));
    pr = qr;
    pz = qz;
  }
  return best;
}

}  // namespace gonio::design
