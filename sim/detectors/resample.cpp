#include "sim/detectors/resample.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "photometry/format.h"
#include "sim/detectors/symmetry.h"

namespace gonio::sim {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

// A piece of a texel is refined until its angular diameter is below this
// fraction of the narrowest bin width around it; such a leaf is then cut
// along the (locally straight) bin boundaries that cross it.
constexpr double kLeafFraction = 1.0 / 2.0;
// Hard limit on refinement: 2^-16 of a texel's edge.
constexpr int kMaxDepth = 16;

bool divides(double whole, double step) {
  const double n = whole / step;
  return std::abs(n - std::round(n)) <= 1e-9 * n;
}

// A polygon in face coordinates (a, b): a rectangle cut once along a
// γ-boundary and once along a C-boundary. Each cut adds one vertex per sign
// change, so even a boundary crossing every edge twice stays within 16.
struct Polygon {
  static constexpr int kMaxVertices = 16;
  struct Point {
    double a, b;
  };
  std::array<Point, kMaxVertices> v{};
  int n = 0;
  void push(Point p) {
    GONIO_CHECK(n < kMaxVertices);
    v[static_cast<std::size_t>(n++)] = p;
  }
};

// Splits `in` where `f` changes sign; `crossing(p, q, f(p), f(q))` gives the
// parameter t in [0, 1] where edge p → q crosses the boundary.
template <class F, class Crossing>
void cut(const Polygon& in, const F& f, const Crossing& crossing, Polygon& negative, Polygon& positive) {
  negative.n = positive.n = 0;
  std::array<double, Polygon::kMaxVertices> value{};
  for (int k = 0; k < in.n; ++k) value[static_cast<std::size_t>(k)] = f(in.v[static_cast<std::size_t>(k)]);
  for (int k = 0; k < in.n; ++k) {
    const auto cur = static_cast<std::size_t>(k), nxt = static_cast<std::size_t>((k + 1) % in.n);
    const Polygon::Point p = in.v[cur], q = in.v[nxt];
    const double fp = value[cur], fq = value[nxt];
    (fp < 0.0 ? negative : positive).push(p);
    if ((fp < 0.0) == (fq < 0.0)) continue;
    const double t = crossing(p, q, fp, fq);
    const Polygon::Point x{p.a + t * (q.a - p.a), p.b + t * (q.b - p.b)};
    negative.push(x);
    positive.push(x);
  }
}

// Where an edge crosses the cone γ = boundary, −d_z = c·|d| (c = cos of the
// boundary), d being the edge's direction, affine in t from dp to dq (cube
// coordinates map linearly to unnormalised directions): a root of
// (d_z² − c²|d|²)(t), a quadratic, on the nappe where −d_z has c's sign.
// Exact, where a root search along the curve took most of the build.
double cone_crossing(const Vec3& dp, const Vec3& dq, double c, double fp, double fq) {
  const double linear = fp / (fp - fq);  // the chord's estimate, and the fallback
  const Vec3 e = dq - dp;
  const double c2 = c * c;
  const double qa = e.z * e.z - c2 * dot(e, e);
  const double qb = 2.0 * (dp.z * e.z - c2 * dot(dp, e));
  const double qc = dp.z * dp.z - c2 * dot(dp, dp);
  std::array<double, 2> roots{};
  int n = 0;
  if (std::abs(qa) <= 1e-14 * (std::abs(qb) + std::abs(qc))) {
    if (qb != 0.0) roots[static_cast<std::size_t>(n++)] = -qc / qb;
  } else {
    const double disc = std::max(0.0, qb * qb - 4.0 * qa * qc);
    const double h = -0.5 * (qb + std::copysign(std::sqrt(disc), qb));
    roots[static_cast<std::size_t>(n++)] = h / qa;
    if (h != 0.0) roots[static_cast<std::size_t>(n++)] = qc / h;
  }
  double best = linear, best_gap = 2.0;
  constexpr double kSlack = 1e-9;
  for (int k = 0; k < n; ++k) {
    const double t = roots[static_cast<std::size_t>(k)];
    if (!(t >= -kSlack && t <= 1.0 + kSlack)) continue;
    if (-(dp.z + t * e.z) * c < 0.0) continue;  // the other nappe
    const double gap = std::abs(t - linear);
    if (gap < best_gap) {
      best = t;
      best_gap = gap;
    }
  }
  return std::clamp(best, 0.0, 1.0);
}

// Finds, for every texel, which bins its pieces fall into and with what
// solid angle.
class OverlapBuilder {
 public:
  OverlapBuilder(const photometry::PhotometricFrame& frame, const CGammaGrid& grid)
      : frame_(frame), grid_(grid), nc_(grid.c_count()), ng_(grid.gamma_count()) {
    // Bin edges [rad]: γ bin j spans [g_edge_[j], g_edge_[j + 1]]; C bin i
    // spans [c_edge_[i], c_edge_[i + 1]] (c_edge_[0] ≤ 0, c_edge_[nc_] =
    // c_edge_[0] + 2π). For uniform steps the same expressions as before
    // lists existed, (j − ½)·Δγ, so those grids' matrices keep their bits.
    g_edge_.resize(static_cast<std::size_t>(ng_) + 1);
    for (int j = 0; j <= ng_; ++j) {
      double e;
      if (j == 0) {
        e = 0.0;
      } else if (j == ng_) {
        e = kPi;
      } else if (grid.gamma_angles_deg.empty()) {
        e = (j - 0.5) * (grid.gamma_step_deg * kDeg);
      } else {
        e = grid.gamma_lower_deg(j) * kDeg;
      }
      g_edge_[static_cast<std::size_t>(j)] = e;
    }
    c_edge_.resize(static_cast<std::size_t>(nc_) + 1);
    for (int i = 0; i < nc_; ++i)
      c_edge_[static_cast<std::size_t>(i)] = grid.c_angles_deg.empty() ? (i - 0.5) * (grid.c_step_deg * kDeg)
                                                                      : grid.c_lower_deg(i) * kDeg;
    c_edge_[static_cast<std::size_t>(nc_)] = c_edge_[0] + 2.0 * kPi;
    cap_ = std::min(g_edge_[1], kPi - g_edge_[static_cast<std::size_t>(ng_ - 1)]);
  }

  struct Piece {
    std::size_t bin;
    double solid_angle_sr;
  };

  // Adds the pieces of face rectangle [a0, a1] × [b0, b1] to `out`, merged per bin.
  void split(int face, double a0, double b0, double a1, double b1, std::vector<Piece>& out) const {
    visit(face, a0, b0, a1, b1, 0, out);
  }

 private:
  struct Where {
    photometry::CGamma cg;
    int i, j;  // C index and γ index of the bin
  };

  Vec3 local(int face, double a, double b) const {
    return frame_.to_local(CubeMapGrid::direction(face, a, b));
  }

  Where where(const Vec3& local_dir) const {
    Where w;
    w.cg = photometry::c_gamma_from_direction(local_dir);
    // The bin whose edges hold γ: the last edge at or below it.
    const auto g_it = std::upper_bound(g_edge_.begin() + 1, g_edge_.end() - 1, w.cg.gamma_rad);
    w.j = static_cast<int>(g_it - g_edge_.begin()) - 1;
    double c = w.cg.c_rad;
    if (c >= c_edge_[static_cast<std::size_t>(nc_)]) c -= 2.0 * kPi;
    const auto c_it = std::upper_bound(c_edge_.begin() + 1, c_edge_.end() - 1, c);
    w.i = static_cast<int>(c_it - c_edge_.begin()) - 1;
    return w;
  }

  double g_lo(int j) const { return g_edge_[static_cast<std::size_t>(j)]; }
  double g_hi(int j) const { return g_edge_[static_cast<std::size_t>(j + 1)]; }
  // The γ-width of a ring of bins; the caps (one γ-boundary each) and
  // beyond count as wide, as a leaf cannot cross two of their boundaries.
  double g_width(int j) const {
    if (j <= 0 || j >= ng_ - 1) return kPi;
    return g_hi(j) - g_lo(j);
  }
  double c_width(int i) const {
    const int k = (i % nc_ + nc_) % nc_;
    return c_edge_[static_cast<std::size_t>(k + 1)] - c_edge_[static_cast<std::size_t>(k)];
  }
  // Signed C distances of the centre from its bin's lower and upper edge
  // [rad]: below ≥ 0, above ≥ 0 inside the bin.
  void c_distances(const Where& w, double* below, double* above) const {
    double c = w.cg.c_rad;
    const double lo = c_edge_[static_cast<std::size_t>(w.i)], hi = c_edge_[static_cast<std::size_t>(w.i + 1)];
    if (c > hi) c -= 2.0 * kPi;
    if (c < lo && c + 2.0 * kPi <= hi) c += 2.0 * kPi;
    *below = c - lo;
    *above = hi - c;
  }

  void add(std::size_t bin, double sa, std::vector<Piece>& out) const {
    for (Piece& p : out) {
      if (p.bin == bin) {
        p.solid_angle_sr += sa;
        return;
      }
    }
    out.push_back({bin, sa});
  }

  void visit(int face, double a0, double b0, double a1, double b1, int depth,
             std::vector<Piece>& out) const {
    const double am = 0.5 * (a0 + a1), bm = 0.5 * (b0 + b1);
    const Vec3 centre = normalize(local(face, am, bm));
    // Angular radius of the piece around its centre direction: the farthest
    // point of a spherical quadrilateral (within a hemisphere) is a corner.
    // acos loses precision near 1 (about 1e-8 rad), hence the margin.
    const double min_cos = std::min({dot(centre, normalize(local(face, a0, b0))),
                                     dot(centre, normalize(local(face, a1, b0))),
                                     dot(centre, normalize(local(face, a0, b1))),
                                     dot(centre, normalize(local(face, a1, b1)))});
    const double r = std::acos(std::clamp(min_cos, -1.0, 1.0)) * (1.0 + 1e-9) + 1e-7;
    const Where w = where(centre);
    const double g = w.cg.gamma_rad;

    // Does the cap of radius r around the centre stay inside this bin? γ is
    // 1-Lipschitz in angular distance; C moves by at most asin(sin r / sin γ)
    // while the cap keeps clear of the poles.
    bool inside = true;
    if (w.j > 0 && g - r <= g_lo(w.j)) inside = false;
    if (w.j < ng_ - 1 && g + r >= g_hi(w.j)) inside = false;
    double c_below = 0.0, c_above = 0.0;
    c_distances(w, &c_below, &c_above);
    if (inside && w.j > 0 && w.j < ng_ - 1 && std::min(c_below, c_above) <= c_reach(g, r)) inside = false;
    const double sa = CubeMapGrid::solid_angle(a0, b0, a1, b1);
    if (inside) {
      add(grid_.bin(w.i, w.j), sa, out);
      return;
    }

    // Narrowest bin width near the piece: the γ-widths of its bin and the
    // two beside it, or the C-width (its plane's and the neighbours') of the
    // ring nearest the pole it approaches.
    const double pole_distance = std::max(cap_, std::min(g, kPi - g) - r);
    const double dg = std::min({g_width(w.j - 1), g_width(w.j), g_width(w.j + 1)});
    const double dc = std::min({c_width(w.i - 1), c_width(w.i), c_width(w.i + 1)});
    const double feature = std::min(dg, dc * std::sin(pole_distance));
    // A γ-boundary is a circle of geodesic curvature cot γ; its chord across
    // a leaf of diameter L strays by about L² cot γ / 8 from it, which the
    // second bound keeps below L/400.
    const double chord_limit = 0.02 * std::tan(pole_distance);
    if (depth >= kMaxDepth || 2.0 * r <= std::min(kLeafFraction * feature, chord_limit)) {
      cut_leaf(face, a0, b0, a1, b1, sa, w, r, out);
      return;
    }
    visit(face, a0, b0, am, bm, depth + 1, out);
    visit(face, am, b0, a1, bm, depth + 1, out);
    visit(face, a0, bm, am, b1, depth + 1, out);
    visit(face, am, bm, a1, b1, depth + 1, out);
  }

  // How far C can move within angular distance r of a point at polar angle g.
  static double c_reach(double g, double r) {
    const double sin_g = std::sin(g);
    return std::sin(r) >= sin_g ? kPi : std::asin(std::sin(r) / sin_g);
  }

  // A leaf is smaller than half of every bin around it, so at most one
  // γ-boundary and one C-boundary cross it, each close to a straight line:
  // C-boundaries are planes through the vertical axis, exactly straight on a
  // cube face; γ-boundaries are cones, straight to second order in the
  // leaf's size. The leaf is cut along both; each part goes to the bin of
  // its vertex mean with its share of the leaf's solid angle.
  void cut_leaf(int face, double a0, double b0, double a1, double b1, double sa, const Where& w,
                double r, std::vector<Piece>& out) const {
    const double g = w.cg.gamma_rad;
    double gamma_boundary = -1.0;  // none
    int gamma_above = w.j;         // the bin on the boundary's larger-γ side
    if (w.j == 0) {
      gamma_boundary = g_hi(0);
      gamma_above = 1;
    } else if (w.j == ng_ - 1) {
      gamma_boundary = g_lo(w.j);
    } else if (g - g_lo(w.j) < g_hi(w.j) - g) {
      gamma_boundary = g_lo(w.j);
    } else {
      gamma_boundary = g_hi(w.j);
      gamma_above = w.j + 1;
    }
    if (std::abs(g - gamma_boundary) > r) gamma_boundary = -1.0;

    bool c_cut = false;
    Vec3 c_normal;
    int c_above = w.i;  // the C index on the boundary's positive side (larger C)
    if (g + r > g_hi(0) && g - r < g_lo(ng_ - 1)) {
      double below = 0.0, above = 0.0;
      c_distances(w, &below, &above);
      const bool upper = above <= below;
      const double c_b = upper ? c_edge_[static_cast<std::size_t>(w.i + 1)] : c_edge_[static_cast<std::size_t>(w.i)];
      if (std::min(below, above) <= c_reach(g, r)) {
        c_cut = true;
        c_normal = {-std::sin(c_b), std::cos(c_b), 0.0};
        if (upper) c_above = (w.i + 1) % nc_;
      }
    }

    if (gamma_boundary < 0.0 && !c_cut) {  // no boundary within reach
      add(grid_.bin(w.i, w.j), sa, out);
      return;
    }
    Polygon rect;
    rect.push({a0, b0});
    rect.push({a1, b0});
    rect.push({a1, b1});
    rect.push({a0, b1});
    std::array<Polygon, 4> parts;
    int count = 0;
    if (gamma_boundary >= 0.0) {
      const double cos_b = std::cos(gamma_boundary);
      const auto f = [&](Polygon::Point p) {
        const Vec3 d = local(face, p.a, p.b);
        return -d.z - cos_b * length(d);  // > 0 where γ < boundary
      };
      const auto crossing = [&](Polygon::Point p, Polygon::Point q, double fp, double fq) {
        return cone_crossing(local(face, p.a, p.b), local(face, q.a, q.b), cos_b, fp, fq);
      };
      cut(rect, f, crossing, parts[0], parts[1]);
      count = 2;
    } else {
      parts[0] = rect;
      count = 1;
    }
    if (c_cut) {
      // C-boundaries are planes through the axis: f is affine on a face.
      const auto f = [&](Polygon::Point p) { return dot(local(face, p.a, p.b), c_normal); };
      const auto crossing = [](Polygon::Point, Polygon::Point, double fp, double fq) {
        return fp / (fp - fq);
      };
      for (int k = count - 1; k >= 0; --k) {
        const Polygon whole = parts[static_cast<std::size_t>(k)];
        cut(whole, f, crossing, parts[static_cast<std::size_t>(k)],
            parts[static_cast<std::size_t>(k + count)]);
      }
      count *= 2;
    }

    // Each part's bin from the sides of the cuts it lies on: parts[k] is on
    // the γ cut's side k % γ-parts (0: larger γ) and the C cut's side
    // k / γ-parts (0: smaller C).
    const int gamma_parts = gamma_boundary >= 0.0 ? 2 : 1;
    const auto part_bin = [&](int k) {
      const int j = gamma_parts == 1 ? w.j : gamma_above - k % gamma_parts;
      const int i = !c_cut ? w.i : k / gamma_parts == 1 ? c_above : (c_above + nc_ - 1) % nc_;
      return grid_.bin(i, j);
    };
    std::array<std::size_t, 4> bins{};
    std::array<double, 4> weights{};
    double total = 0.0;
    for (int k = 0; k < count; ++k) {
      const Polygon& p = parts[static_cast<std::size_t>(k)];
      if (p.n < 3) continue;
      // Exact solid angle of the spherical polygon (the face polygon seen
      // from the centre), by a fan of signed triangles (Van Oosterom &
      // Strackee), which also holds for the rare non-convex part.
      std::array<Vec3, Polygon::kMaxVertices> u;
      for (int m = 0; m < p.n; ++m) {
        const auto mi = static_cast<std::size_t>(m);
        u[mi] = normalize(CubeMapGrid::direction(face, p.v[mi].a, p.v[mi].b));
      }
      double omega = 0.0;
      for (int m = 1; m + 1 < p.n; ++m) {
        const Vec3& v1 = u[static_cast<std::size_t>(m)];
        const Vec3& v2 = u[static_cast<std::size_t>(m + 1)];
        const double num = dot(u[0], cross(v1, v2));
        const double den = 1.0 + dot(u[0], v1) + dot(v1, v2) + dot(v2, u[0]);
        omega += 2.0 * std::atan2(num, den);
      }
      omega = std::abs(omega);
      if (!(omega > 0.0)) continue;
      bins[static_cast<std::size_t>(k)] = part_bin(k);
      weights[static_cast<std::size_t>(k)] = omega;
      total += omega;
    }
    if (!(total > 0.0)) {
      add(grid_.bin(w.i, w.j), sa, out);
      return;
    }
    for (int k = 0; k < count; ++k) {
      if (weights[static_cast<std::size_t>(k)] > 0.0)
        add(bins[static_cast<std::size_t>(k)], sa * weights[static_cast<std::size_t>(k)] / total, out);
    }
  }

  photometry::PhotometricFrame frame_;
  CGammaGrid grid_;
  int nc_, ng_;
  std::vector<double> g_edge_, c_edge_;  // bin edges [rad], see the constructor
  double cap_;                           // the smaller cap's radius [rad]
};

}  // namespace

int CGammaGrid::c_count() const {
  if (!c_angles_deg.empty()) return static_cast<int>(c_angles_deg.size());
  return static_cast<int>(std::lround(360.0 / c_step_deg));
}
int CGammaGrid::gamma_count() const {
  if (!gamma_angles_deg.empty()) return static_cast<int>(gamma_angles_deg.size());
  return static_cast<int>(std::lround(180.0 / gamma_step_deg)) + 1;
}
std::size_t CGammaGrid::bin_count() const {
  return 2 + static_cast<std::size_t>(c_count()) * static_cast<std::size_t>(gamma_count() - 2);
}
std::size_t CGammaGrid::bin(int c_index, int gamma_index) const {
  if (gamma_index == 0) return 0;
  if (gamma_index == gamma_count() - 1) return 1;
  return 2 + static_cast<std::size_t>(gamma_index - 1) * static_cast<std::size_t>(c_count()) +
         static_cast<std::size_t>(c_index);
}

double CGammaGrid::gamma_lower_deg(int j) const {
  if (j <= 0) return 0.0;
  return 0.5 * (gamma_deg(j - 1) + gamma_deg(j));
}
double CGammaGrid::gamma_upper_deg(int j) const {
  if (j >= gamma_count() - 1) return 180.0;
  return 0.5 * (gamma_deg(j) + gamma_deg(j + 1));
}
double CGammaGrid::c_lower_deg(int i) const {
  if (i == 0) return 0.5 * (c_deg(c_count() - 1) - 360.0);
  return 0.5 * (c_deg(i - 1) + c_deg(i));
}
double CGammaGrid::c_upper_deg(int i) const {
  if (i == c_count() - 1) return 0.5 * (c_deg(i) + 360.0);
  return 0.5 * (c_deg(i) + c_deg(i + 1));
}
int CGammaGrid::c_index_of(double c) const {
  c = std::fmod(c, 360.0);
  if (c < 0.0) c += 360.0;
  if (c > 360.0 - 1e-9) c -= 360.0;
  if (c_angles_deg.empty()) {
    const double k = c / c_step_deg;
    const long i = std::lround(k);
    if (std::abs(k - static_cast<double>(i)) > 1e-9 * std::max(1.0, k)) return -1;
    return static_cast<int>(i % c_count());
  }
  const auto it = std::lower_bound(c_angles_deg.begin(), c_angles_deg.end(), c - 1e-9);
  if (it == c_angles_deg.end() || std::abs(*it - c) > 1e-9) return -1;
  return static_cast<int>(it - c_angles_deg.begin());
}
double CGammaGrid::finest_gamma_step_deg() const {
  if (gamma_angles_deg.empty()) return gamma_step_deg;
  double step = 180.0;
  for (std::size_t k = 1; k < gamma_angles_deg.size(); ++k)
    step = std::min(step, gamma_angles_deg[k] - gamma_angles_deg[k - 1]);
  return step;
}
double CGammaGrid::finest_c_step_deg() const {
  if (c_angles_deg.empty()) return c_step_deg;
  double step = 360.0 - c_angles_deg.back() + c_angles_deg.front();
  for (std::size_t k = 1; k < c_angles_deg.size(); ++k)
    step = std::min(step, c_angles_deg[k] - c_angles_deg[k - 1]);
  return step;
}
std::string CGammaGrid::describe() const {
  const auto axis = [](const char* name, const std::vector<double>& list, double step, int count, double finest) {
    if (list.empty()) return std::string(name) + " step " + format_number(step) + " deg";
    return std::string(name) + " " + std::to_string(count) + " angles " + format_number(list.front()) + "-" +
           format_number(list.back()) + " deg (finest step " + format_number(finest) + " deg)";
  };
  return axis("C", c_angles_deg, c_step_deg, c_count(), finest_c_step_deg()) + ", " +
         axis("gamma", gamma_angles_deg, gamma_step_deg, gamma_count(), finest_gamma_step_deg());
}

namespace {

Status check_list(const std::vector<double>& list, double last_max, bool ends_at_max, const char* what) {
  const auto fail = [&](const std::string& why) -> Status {
    Error e;
    e.message = std::string(what) + " angles: " + why;
    return e;
  };
  if (list.size() < 2) return fail("need at least two angles");
  if (list.size() > kMaxGridAngles)
    return fail(std::to_string(list.size()) + " angles, more than " + std::to_string(kMaxGridAngles));
  for (std::size_t k = 0; k < list.size(); ++k)
    if (!std::isfinite(list[k])) return fail("angle " + std::to_string(k + 1) + " is not a number");
  if (list.front() != 0.0) return fail("the first angle must be 0, not " + format_number(list.front()));
  for (std::size_t k = 1; k < list.size(); ++k) {
    if (!(list[k] > list[k - 1]))
      return fail("not in ascending order: " + format_number(list[k]) + " after " + format_number(list[k - 1]));
    if (list[k] - list[k - 1] < kMinGammaStepDeg - 1e-9)
      return fail(format_number(list[k - 1]) + " and " + format_number(list[k]) + " are closer than " +
                  format_number(kMinGammaStepDeg) + "°");
  }
  if (ends_at_max && list.back() != last_max)
    return fail("the last angle must be " + format_number(last_max) + ", not " + format_number(list.back()));
  if (!ends_at_max && !(list.back() < last_max))
    return fail(format_number(list.back()) + " is outside 0…" + format_number(last_max) + "° (" +
                format_number(last_max) + " repeats 0)");
  if (!ends_at_max && last_max - list.back() < kMinGammaStepDeg - 1e-9)
    return fail(format_number(list.back()) + " and 360 (C = 0) are closer than " +
                format_number(kMinGammaStepDeg) + "°");
  // As for steps, no gap wider than kMaxGridStepDeg (C: the wrap to 360 too).
  for (std::size_t k = 0; k < list.size(); ++k) {
    const double next = k + 1 < list.size() ? list[k + 1] : ends_at_max ? list[k] : last_max;
    if (next - list[k] > kMaxGridStepDeg + 1e-9)
      return fail("the gap from " + format_number(list[k]) + " to " + format_number(next) + "° is more than " +
                  format_number(kMaxGridStepDeg) + "°");
  }
  return Ok{};
}

}  // namespace

Status validate(const CGammaGrid& grid) {
  const auto check = [](double step, double whole, double min, const char* what) -> Status {
    Error e;
    if (!std::isfinite(step) || step < min - 1e-12 || step > kMaxGridStepDeg) {
      e.message = std::string(what) + " step " + format_number(step) + "° is outside " + format_number(min) +
                  "…" + format_number(kMaxGridStepDeg) + "°";
      return e;
    }
    if (!divides(whole, step)) {
      e.message = std::string(what) + " step " + format_number(step) + "° does not divide " +
                  format_number(whole) + "° into whole steps (e.g. 1, 2.5, 5, 10, 15)";
      return e;
    }
    return Ok{};
  };
  if (grid.c_angles_deg.empty()) {
    if (Status s = check(grid.c_step_deg, 360.0, kMinGridStepDeg, "C"); !s.ok()) return s;
  } else if (Status s = check_list(grid.c_angles_deg, 360.0, false, "C"); !s.ok()) {
    return s;
  }
  if (grid.gamma_angles_deg.empty()) return check(grid.gamma_step_deg, 180.0, kMinGammaStepDeg, "gamma");
  return check_list(grid.gamma_angles_deg, 180.0, true, "gamma");
}

int face_size_for(const CGammaGrid& grid) {
  return std::min(kMaxAutoFaceSize,
                  CubeMapGrid::face_size_for_step(std::min(grid.finest_c_step_deg(), grid.finest_gamma_step_deg())));
}

double exact_bin_solid_angle(const CGammaGrid& grid, std::size_t bin) {
  const int ng = grid.gamma_count();
  if (bin == 0) return 2.0 * kPi * (1.0 - std::cos(grid.gamma_upper_deg(0) * kDeg));
  if (bin == 1) return 2.0 * kPi * (1.0 + std::cos(grid.gamma_lower_deg(ng - 1) * kDeg));
  const auto nc = static_cast<std::size_t>(grid.c_count());
  const int j = static_cast<int>((bin - 2) / nc) + 1;
  const int i = static_cast<int>((bin - 2) % nc);
  const double dc = (grid.c_upper_deg(i) - grid.c_lower_deg(i)) * kDeg;
  return dc * (std::cos(grid.gamma_lower_deg(j) * kDeg) - std::cos(grid.gamma_upper_deg(j) * kDeg));
}

double BinnedField::total_flux_lm() const {
  double sum = 0.0;
  for (double f : flux_lm) sum += f;
  return sum;
}

Resampler::Resampler(int face_size, const photometry::PhotometricFrame& frame,
                     const CGammaGrid& grid)
    : face_size_(face_size), grid_(grid) {
  GONIO_CHECK_MSG(validate(grid).ok(), "Resampler needs a valid grid");
  GONIO_CHECK_MSG(std::abs(dot(frame.c0, frame.c90)) < 1e-9 && std::abs(length(frame.up) - 1.0) < 1e-9 &&
                      dot(cross(frame.c0, frame.c90), frame.up) > 1.0 - 1e-9,
                  "the photometric frame must be orthonormal and right-handed");
  const CubeMapGrid cube(face_size);
  const OverlapBuilder builder(frame, grid);
  const std::size_t bins = grid.bin_count();

  struct Entry {
    std::size_t bin;
    std::uint32_t texel;
    double fraction;
  };
  // Rows of texels in parallel, each into its own list, joined in map order:
  // the matrix does not depend on the thread count.
  const int rows = kCubeFaces * face_size;
  std::vector<std::vector<Entry>> row_entries(static_cast<std::size_t>(rows));
  const double step = 2.0 / face_size;
  tbb::parallel_for(tbb::blocked_range<int>(0, rows), [&](const tbb::blocked_range<int>& range) {
    std::vector<OverlapBuilder::Piece> pieces;
    for (int row = range.begin(); row != range.end(); ++row) {
      const int face = row / face_size, y = row % face_size;
      std::vector<Entry>& list = row_entries[static_cast<std::size_t>(row)];
      for (int x = 0; x < face_size; ++x) {
        pieces.clear();
        const double a0 = -1.0 + x * step, b0 = -1.0 + y * step;
        builder.split(face, a0, b0, a0 + step, b0 + step, pieces);
        double total = 0.0;
        for (const auto& p : pieces) total += p.solid_angle_sr;
        const auto texel = static_cast<std::uint32_t>(cube.index(face, x, y));
        for (const auto& p : pieces) list.push_back({p.bin, texel, p.solid_angle_sr / total});
      }
    }
  });
  std::vector<Entry> entries;
  std::size_t count = 0;
  for (const auto& list : row_entries) count += list.size();
  entries.reserve(count);
  for (auto& list : row_entries) {
    entries.insert(entries.end(), list.begin(), list.end());
    std::vector<Entry>().swap(list);
  }

  // Counting sort into rows by bin; within a row, texels stay in map order.
  row_start_.assign(bins + 1, 0);
  for (const Entry& e : entries) ++row_start_[e.bin + 1];
  for (std::size_t b = 0; b < bins; ++b) row_start_[b + 1] += row_start_[b];
  texel_.resize(entries.size());
  fraction_.resize(entries.size());
  solid_angle_sr_.assign(bins, 0.0);
  std::vector<std::size_t> next(row_start_.begin(), row_start_.end() - 1);
  for (const Entry& e : entries) {
    const std::size_t k = next[e.bin]++;
    texel_[k] = e.texel;
    fraction_[k] = e.fraction;
    solid_angle_sr_[e.bin] += e.fraction * cube.texel_solid_angle(e.texel);
  }
}

Resampler::Rows Resampler::rows() const {
  return {std::vector<std::uint64_t>(row_start_.begin(), row_start_.end()), texel_, fraction_,
          solid_angle_sr_};
}

Result<Resampler> Resampler::from_rows(int face_size, const CGammaGrid& grid, Rows rows) {
  if (!validate(grid).ok()) return make_error("stored resampler: invalid grid");
  if (face_size < 1 || face_size > 16384) return make_error("stored resampler: face size out of range");
  const std::size_t bins = grid.bin_count();
  const std::size_t texels = static_cast<std::size_t>(kCubeFaces) * face_size * face_size;
  const std::size_t nonzeros = rows.texel.size();
  if (rows.row_start.size() != bins + 1 || rows.fraction.size() != nonzeros ||
      rows.solid_angle_sr.size() != bins || rows.row_start.front() != 0 || rows.row_start.back() != nonzeros)
    return make_error("stored resampler: sizes do not agree with the grid");
  for (std::size_t b = 0; b < bins; ++b) {
    if (rows.row_start[b] > rows.row_start[b + 1]) return make_error("stored resampler: rows out of order");
    if (!(rows.solid_angle_sr[b] > 0.0) || !std::isfinite(rows.solid_angle_sr[b]))
      return make_error("stored resampler: a bin without solid angle");
  }
  for (std::size_t k = 0; k < nonzeros; ++k) {
    if (rows.texel[k] >= texels) return make_error("stored resampler: texel out of range");
    if (!(rows.fraction[k] >= 0.0 && rows.fraction[k] <= 1.0))
      return make_error("stored resampler: fraction outside [0, 1]");
  }
  Resampler r(face_size, grid);
  r.row_start_.assign(rows.row_start.begin(), rows.row_start.end());
  r.texel_ = std::move(rows.texel);
  r.fraction_ = std::move(rows.fraction);
  r.solid_angle_sr_ = std::move(rows.solid_angle_sr);
  return r;
}

BinnedField Resampler::bin(const FarField& field) const {
  GONIO_CHECK_MSG(field.face_size() == face_size_, "far field and resampler differ in face size");
  const std::size_t bins = grid_.bin_count();
  BinnedField out;
  out.grid = grid_;
  out.flux_lm.assign(bins, 0.0);
  out.variance_lm2.assign(bins, 0.0);
  out.photons.assign(bins, 0.0);
  out.solid_angle_sr = solid_angle_sr_;
  const std::span<const double> flux = field.flux_lm();
  const std::span<const std::uint64_t> photons = field.photons();
  for (std::size_t b = 0; b < bins; ++b) {
    double f = 0.0, v = 0.0, n = 0.0;
    for (std::size_t k = row_start_[b]; k < row_start_[b + 1]; ++k) {
      const std::size_t t = texel_[k];
      const double w = fraction_[k];
      f += w * flux[t];
      if (photons[t] > 0) {
        const double count = static_cast<double>(photons[t]);
        v += w * w * flux[t] * flux[t] / count;
        n += w * count;
      }
    }
    out.flux_lm[b] = f;
    out.variance_lm2[b] = v;
    out.photons[b] = n;
  }
  return out;
}

std::vector<double> Resampler::bin_flux(std::span<const double> flux) const {
  GONIO_CHECK_MSG(flux.size() == 6 * static_cast<std::size_t>(face_size_) * static_cast<std::size_t>(face_size_),
                  "far field and resampler differ in face size");
  const std::size_t bins = grid_.bin_count();
  std::vector<double> out(bins, 0.0);
  for (std::size_t b = 0; b < bins; ++b) {
    double f = 0.0;
    for (std::size_t k = row_start_[b]; k < row_start_[b + 1]; ++k) f += fraction_[k] * flux[texel_[k]];
    out[b] = f;
  }
  return out;
}

photometry::Distribution to_distribution(const BinnedField& field, photometry::Symmetry symmetry) {
  using photometry::Symmetry;
  const CGammaGrid& g = field.grid;
  GONIO_CHECK_MSG(grid_supports(g, symmetry), "the grid does not support this symmetry");
  const std::vector<double> intensity = symmetric_intensity_cd(field, symmetry);
  const int nc = g.c_count(), ng = g.gamma_count();

  std::vector<int> planes;  // C indices; nc stands for C = 360 (a copy of 0)
  const auto range = [&](double from, double to) {
    const int a = g.c_index_of(from), b = to >= 360.0 ? nc : g.c_index_of(to);
    for (int i = a; i <= b; ++i) planes.push_back(i);
  };
  switch (symmetry) {
    case Symmetry::None: range(0.0, 360.0); break;
    case Symmetry::Rotational: planes = {0}; break;
    case Symmetry::C0_C180: range(0.0, 180.0); break;
    case Symmetry::C90_C270: range(90.0, 270.0); break;
    case Symmetry::Quadrant: range(0.0, 90.0); break;
    case Symmetry::Lateral: GONIO_CHECK_MSG(false, "lateral symmetry is not Type C");
  }
  photometry::Distribution d;
  d.type = photometry::PhotometricType::C;
  d.symmetry = symmetry;
  d.absolute = true;
  for (int j = 0; j < ng; ++j) d.vertical_deg.push_back(g.gamma_deg(j));
  for (int i : planes) d.horizontal_deg.push_back(i == nc ? 360.0 : g.c_deg(i));
  d.candela.reserve(planes.size() * static_cast<std::size_t>(ng));
  for (int i : planes) {
    for (int j = 0; j < ng; ++j) d.candela.push_back(intensity[g.bin(i % nc, j)]);
  }
  return d;
}

}  // namespace gonio::sim
