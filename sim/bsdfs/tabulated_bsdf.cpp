#include "sim/bsdfs/tabulated_bsdf.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>

#include "photometry/format.h"

namespace gonio::sim {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();

double wrap_into(double phi, double start) {
  double p = std::fmod(phi - start, 360.0);
  if (p < 0.0) p += 360.0;
  return start + p;
}

// Turns w about z so that the incident light's direction of travel (−wi
// projected) lies along +x; (c, s): cos and sin of that azimuth.
void incident_azimuth(const Vec3& wi, double* c, double* s) {
  const double x = -wi.x, y = -wi.y, r = std::sqrt(x * x + y * y);
  if (!(r > 1e-12)) {
    *c = 1.0;
    *s = 0.0;
    return;
  }
  *c = x / r;
  *s = y / r;
}

Vec3 to_table(const Vec3& w, double c, double s) { return {c * w.x + s * w.y, -s * w.x + c * w.y, w.z}; }
Vec3 from_table(const Vec3& w, double c, double s) { return {c * w.x - s * w.y, s * w.x + c * w.y, w.z}; }

// The two rows about θ and the weight of the second.
struct Bracket {
  std::size_t a = 0, b = 0;
  double t = 0.0;
};
Bracket bracket(const TabulatedBsdf::Side& side, double theta_deg) {
  const auto& rows = side.rows;
  if (theta_deg <= rows.front().theta_deg) return {0, 0, 0.0};
  if (theta_deg >= rows.back().theta_deg) return {rows.size() - 1, rows.size() - 1, 0.0};
  std::size_t b = 1;
  while (rows[b].theta_deg < theta_deg) ++b;
  const double t = (theta_deg - rows[b - 1].theta_deg) / (rows[b].theta_deg - rows[b - 1].theta_deg);
  return {b - 1, b, t};
}

double theta_of(const Vec3& wi) { return std::acos(std::clamp(wi.z, -1.0, 1.0)) / kDeg; }

double row_value(const TabulatedBsdf::Row& r, bool transmit, std::size_t patch) {
  const std::vector<float>& v = transmit ? r.transmit : r.reflect;
  return v.empty() ? 0.0 : static_cast<double>(v[patch]);
}

}  // namespace

void square_to_disc(double sx, double sy, double* dx, double* dy) {
  const double a = 2.0 * sx - 1.0, b = 2.0 * sy - 1.0;
  double r, phi;
  if (a > -b) {
    if (a > b) {
      r = a;
      phi = (kPi / 4.0) * (b / a);
    } else {
      r = b;
      phi = (kPi / 4.0) * (2.0 - a / b);
    }
  } else if (a < b) {
    r = -a;
    phi = (kPi / 4.0) * (4.0 + b / a);
  } else {
    r = -b;
    phi = b != 0.0 ? (kPi / 4.0) * (6.0 - a / b) : 0.0;
  }
  *dx = r * std::cos(phi);
  *dy = r * std::sin(phi);
}

void disc_to_square(double dx, double dy, double* sx, double* sy) {
  const double r = std::sqrt(dx * dx + dy * dy);
  double phi = std::atan2(dy, dx);
  double a, b;
  if (phi < -kPi / 4.0) phi += 2.0 * kPi;
  if (phi < kPi / 4.0) {
    a = r;
    b = phi * a / (kPi / 4.0);
  } else if (phi < 3.0 * kPi / 4.0) {
    b = r;
    a = -(phi - kPi / 2.0) * b / (kPi / 4.0);
  } else if (phi < 5.0 * kPi / 4.0) {
    a = -r;
    b = (phi - kPi) * a / (kPi / 4.0);
  } else {
    b = -r;
    a = -(phi - 3.0 * kPi / 2.0) * b / (kPi / 4.0);
  }
  *sx = 0.5 * a + 0.5;
  *sy = 0.5 * b + 0.5;
}

std::size_t PatchBasis::size() const {
  if (kind == Kind::Square) return static_cast<std::size_t>(square_n) * static_cast<std::size_t>(square_n);
  std::size_t n = 0;
  for (const auto& b : ring_phi_deg) n += b.size() - 1;
  return n;
}

std::size_t PatchBasis::patch_of(const Vec3& w) const {
  if (kind == Kind::Square) {
    double sx, sy;
    disc_to_square(w.x, w.y, &sx, &sy);
    const int n = square_n;
    const int i = std::clamp(static_cast<int>(sx * n), 0, n - 1);
    const int j = std::clamp(static_cast<int>(sy * n), 0, n - 1);
    return static_cast<std::size_t>(i) * static_cast<std::size_t>(n) + static_cast<std::size_t>(j);
  }
  const double theta = std::acos(std::clamp(std::abs(w.z), 0.0, 1.0)) / kDeg;
  std::size_t first = 0;
  for (std::size_t r = 0; r + 1 < ring_theta_deg.size(); ++r) {
    const std::vector<double>& b = ring_phi_deg[r];
    if (theta < ring_theta_deg[r + 1] || r + 2 == ring_theta_deg.size()) {
      const double phi = wrap_into(std::atan2(w.y, w.x) / kDeg, b.front());
      const auto k = static_cast<std::size_t>(std::upper_bound(b.begin(), b.end(), phi) - b.begin());
      return first + std::clamp<std::size_t>(k, 1, b.size() - 1) - 1;
    }
    first += b.size() - 1;
  }
  return kNone;
}

namespace {
// Ring and φ index of a Rings patch.
void ring_of(const PatchBasis& p, std::size_t patch, std::size_t* ring, std::size_t* k) {
  std::size_t r = 0;
  while (patch >= p.ring_phi_deg[r].size() - 1) {
    patch -= p.ring_phi_deg[r].size() - 1;
    ++r;
  }
  *ring = r;
  *k = patch;
}
}  // namespace

double PatchBasis::projected_solid_angle(std::size_t patch) const {
  if (kind == Kind::Square) return kPi / (static_cast<double>(square_n) * square_n);
  std::size_t r, k;
  ring_of(*this, patch, &r, &k);
  const double c0 = std::cos(ring_theta_deg[r] * kDeg), c1 = std::cos(ring_theta_deg[r + 1] * kDeg);
  const std::vector<double>& b = ring_phi_deg[r];
  return 0.5 * (c0 * c0 - c1 * c1) * (b[k + 1] - b[k]) * kDeg;
}

Vec3 PatchBasis::direction_in(std::size_t patch, double u, double v) const {
  if (kind == Kind::Square) {
    const auto n = static_cast<std::size_t>(square_n);
    const std::size_t i = patch / n, j = patch % n;
    double dx, dy;
    square_to_disc((static_cast<double>(i) + u) / square_n, (static_cast<double>(j) + v) / square_n, &dx, &dy);
    const double z = std::sqrt(std::max(0.0, 1.0 - dx * dx - dy * dy));
    return {dx, dy, z};
  }
  std::size_t r, k;
  ring_of(*this, patch, &r, &k);
  const double c0 = std::cos(ring_theta_deg[r] * kDeg), c1 = std::cos(ring_theta_deg[r + 1] * kDeg);
  const double z = std::sqrt(c0 * c0 + u * (c1 * c1 - c0 * c0));  // cos²θ uniform
  const std::vector<double>& b = ring_phi_deg[r];
  const double phi = (b[k] + v * (b[k + 1] - b[k])) * kDeg;
  const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {s * std::cos(phi), s * std::sin(phi), z};
}

Vec3 PatchBasis::centre_of(std::size_t patch) const {
  if (kind == Kind::Rings) {
    std::size_t r, k;
    ring_of(*this, patch, &r, &k);
    if (ring_theta_deg[r] == 0.0 && ring_phi_deg[r].size() == 2) return {0.0, 0.0, 1.0};
  }
  return direction_in(patch, 0.5, 0.5);
}

PatchBasis PatchBasis::klems(const std::string& name) {
  struct Lat {
    double tmin;
    int nphis;
  };
  static const std::vector<Lat> full = {{0, 1},   {5, 8},   {15, 16}, {25, 20}, {35, 24},
                                        {45, 24}, {55, 24}, {65, 16}, {75, 12}, {90, 0}};
  static const std::vector<Lat> half = {{0, 1}, {6.5, 8}, {19.5, 12}, {32.5, 16}, {46.5, 20}, {61.5, 12}, {76.5, 4}, {90, 0}};
  static const std::vector<Lat> quarter = {{0, 1}, {9, 8}, {27, 12}, {46, 12}, {66, 8}, {90, 0}};
  const std::vector<Lat>* lats = nullptr;
  if (name == "LBNL/Klems Full") lats = &full;
  if (name == "LBNL/Klems Half") lats = &half;
  if (name == "LBNL/Klems Quarter") lats = &quarter;
  PatchBasis p;
  if (!lats) return p;
  for (std::size_t i = 0; i < lats->size(); ++i) {
    p.ring_theta_deg.push_back((*lats)[i].tmin);
    const int n = (*lats)[i].nphis;
    if (n == 0) break;
    std::vector<double> b;
    for (int k = 0; k <= n; ++k) b.push_back((k - 0.5) * 360.0 / n);
    p.ring_phi_deg.push_back(std::move(b));
  }
  return p;
}

Status TabulatedBsdf::finish(std::vector<Finding>& findings) {
  const std::size_t n = basis.size();
  if (n == 0) return make_error(name + ": the BSDF has no outgoing patches");
  if (front.empty() && back.empty()) return make_error(name + ": the BSDF holds no data");
  std::vector<double> omega(n);
  double total = 0.0;
  for (std::size_t p = 0; p < n; ++p) total += omega[p] = basis.projected_solid_angle(p);
  if (!(std::abs(total - kPi) < 1e-6 * kPi))
    return make_error(name + ": the patches do not cover the hemisphere (projected solid angle " +
                      format_number(total) + ", not π)");
  for (Side* side : {&front, &back}) {
    const char* which = side == &front ? "front" : "back";
    double last = -1.0;
    for (Row& r : side->rows) {
      if (!(r.theta_deg > last) || !(r.theta_deg <= 90.0) || !(r.theta_deg >= 0.0))
        return make_error(name + ": " + which + " incidence angles must increase within 0..90 degrees");
      last = r.theta_deg;
      for (const std::vector<float>* v : {&r.reflect, &r.transmit}) {
        if (!v->empty() && v->size() != n)
          return make_error(name + ": a " + which + " row at " + format_number(r.theta_deg) + " degrees has " +
                            std::to_string(v->size()) + " values for " + std::to_string(n) + " patches");
        for (float x : *v)
          if (!(std::isfinite(x) && x >= 0.0f))
            return make_error(name + ": a " + which + " row at " + format_number(r.theta_deg) +
                              " degrees holds a negative or non-finite value");
      }
    }
  }
  // A side with reflection data but without transmission takes the other
  // side's transmission by reciprocity (as Radiance does; tensor trees
  // store one of the two): f(wi → wo) arriving here = f(wo' → wi') arriving
  // there, where ' turns a direction into the other side's frame (z
  // negated). A side without any data uses the other side whole (side()).
  for (Side* side : {&front, &back}) {
    Side& other = side == &front ? back : front;
    const auto has_transmit = [](const Side& x) {
      return std::any_of(x.rows.begin(), x.rows.end(), [](const Row& r) { return !r.transmit.empty(); });
    };
    if (side->rows.empty() || has_transmit(*side) || !has_transmit(other)) continue;
    for (Row& r : side->rows) {
      const double ti = r.theta_deg * kDeg;
      const Vec3 wi{-std::sin(ti), 0.0, std::cos(ti)};
      r.transmit.resize(n);
      for (std::size_t p = 0; p < n; ++p) {
        const Vec3 c = basis.centre_of(p);
        const Vec3 wo{c.x, c.y, -c.z};
        const Vec3 wi_there{wo.x, wo.y, -wo.z}, wo_there{wi.x, wi.y, -wi.z};
        const double f = evaluate(side != &front, wi_there, wo_there) / std::abs(wo_there.z);
        r.transmit[p] = static_cast<float>(std::isfinite(f) ? f : 0.0);
      }
    }
    findings.push_back({Severity::Info, "bsdf-transmission-by-reciprocity",
                        name + ": transmission for light arriving at the " + (side == &front ? "front" : "back") +
                            " derived from the other side's by reciprocity",
                        {}});
  }
  for (Side* side : {&front, &back}) {
    const char* which = side == &front ? "front" : "back";
    for (Row& r : side->rows) {
      r.reflect_albedo = r.transmit_albedo = 0.0;
      for (std::size_t p = 0; p < n; ++p) {
        r.reflect_albedo += row_value(r, false, p) * omega[p];
        r.transmit_albedo += row_value(r, true, p) * omega[p];
      }
      const double a = r.reflect_albedo + r.transmit_albedo;
      if (a > 1.0 + 1e-3) {
        findings.push_back({Severity::Warning, "bsdf-albedo-above-1",
                            name + ": " + which + " side at " + format_number(r.theta_deg) +
                                " degrees incidence scatters " + format_number(a, 4) +
                                " of the light it receives (reflection " + format_number(r.reflect_albedo, 4) +
                                ", transmission " + format_number(r.transmit_albedo, 4) +
                                "); scaled to 1",
                            {}});
        const auto f = static_cast<float>(1.0 / a);
        for (float& x : r.reflect) x *= f;
        for (float& x : r.transmit) x *= f;
        r.reflect_albedo /= a;
        r.transmit_albedo /= a;
      }
      r.cdf.assign(2 * n, 0.0);
      double c = 0.0;
      for (std::size_t p = 0; p < 2 * n; ++p) {
        c += row_value(r, p >= n, p % n) * omega[p % n];
        r.cdf[p] = c;
      }
      if (c > 0.0)
        for (double& x : r.cdf) x /= c;
    }
  }
  return Ok{};
}

const TabulatedBsdf::Side& TabulatedBsdf::side(bool arrives_front) const {
  if (arrives_front) return front.empty() ? back : front;
  return back.empty() ? front : back;
}

double TabulatedBsdf::evaluate(bool arrives_front, const Vec3& wi, const Vec3& wo) const {
  const Side& s = side(arrives_front);
  if (!(wi.z > 0.0) || s.empty() || wo.z == 0.0) return 0.0;
  double c, sn;
  incident_azimuth(wi, &c, &sn);
  const Vec3 t = to_table(wo, c, sn);
  const bool transmit = wo.z < 0.0;
  const std::size_t p = basis.patch_of(Vec3{t.x, t.y, std::abs(t.z)});
  if (p == kNone) return 0.0;
  const Bracket b = bracket(s, theta_of(wi));
  const double f = (1.0 - b.t) * row_value(s.rows[b.a], transmit, p) + b.t * row_value(s.rows[b.b], transmit, p);
  return f * std::abs(wo.z);
}

double TabulatedBsdf::albedo(bool arrives_front, const Vec3& wi, double* reflect, double* transmit) const {
  const Side& s = side(arrives_front);
  double r = 0.0, t = 0.0;
  if (wi.z > 0.0 && !s.empty()) {
    const Bracket b = bracket(s, theta_of(wi));
    r = (1.0 - b.t) * s.rows[b.a].reflect_albedo + b.t * s.rows[b.b].reflect_albedo;
    t = (1.0 - b.t) * s.rows[b.a].transmit_albedo + b.t * s.rows[b.b].transmit_albedo;
  }
  if (reflect) *reflect = r;
  if (transmit) *transmit = t;
  return r + t;
}

Vec3 TabulatedBsdf::sample(bool arrives_front, const Vec3& wi, double u_row, double u_patch, double u,
                           double v) const {
  const Side& s = side(arrives_front);
  if (!(wi.z > 0.0) || s.empty()) return {};
  const Bracket b = bracket(s, theta_of(wi));
  const Row& ra = s.rows[b.a];
  const Row& rb = s.rows[b.b];
  const double wa = (1.0 - b.t) * (ra.reflect_albedo + ra.transmit_albedo);
  const double wb = b.t * (rb.reflect_albedo + rb.transmit_albedo);
  if (!(wa + wb > 0.0)) return {};
  const Row& row = u_row * (wa + wb) < wa ? ra : rb;
  const auto k = static_cast<std::size_t>(std::upper_bound(row.cdf.begin(), row.cdf.end(), u_patch) - row.cdf.begin());
  const std::size_t n = basis.size();
  const std::size_t pick = std::min(k, 2 * n - 1);
  Vec3 d = basis.direction_in(pick % n, u, v);
  if (pick >= n) d.z = -d.z;
  double c, sn;
  incident_azimuth(wi, &c, &sn);
  return from_table(d, c, sn);
}

double TabulatedBsdf::reciprocity_error(bool transmission) const {
  // Pairs of patch centres at the rows' own angles: f(a → b) against
  // f(b → a), each in its own frame (isotropic: only θa, θb and the
  // azimuth between them matter).
  const Side* forward = &side(true);
  if (transmission && (front.empty() || back.empty())) return -1.0;
  const std::size_t n = basis.size();
  double diff = 0.0, sum = 0.0;
  for (const Row& r : forward->rows) {
    const double ti = r.theta_deg * kDeg;
    const Vec3 wi{-std::sin(ti), 0.0, std::cos(ti)};
    for (std::size_t p = 0; p < n; ++p) {
      Vec3 wo = basis.centre_of(p);
      const double omega = basis.projected_solid_angle(p);
      if (transmission) wo.z = -wo.z;
      const double fab = evaluate(true, wi, wo) / std::abs(wo.z);
      // Reversed: light arrives along −wo's opposite, i.e. from wo's side,
      // and leaves towards wi's direction.
      Vec3 wi2 = wo, wo2 = wi;
      if (transmission) {
        wi2.z = -wi2.z;
        wo2.z = -wo2.z;
      }
      const double fba = evaluate(!transmission, wi2, wo2) / std::abs(wo2.z);
      const double m = 0.5 * (fab + fba);
      if (!(m > 0.0)) continue;
      const double weight = m * omega * std::cos(ti);
      diff += weight * std::abs(fab - fba) / m;
      sum += weight;
    }
  }
  return sum > 0.0 ? diff / sum : -1.0;
}

}  // namespace gonio::sim
