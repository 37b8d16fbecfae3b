#include "sim/detectors/near_field.h"

#include <algorithm>
#include <cmath>

#include <limits>

#include "sim/ledger.h"

namespace gonio::sim {

void for_each_luminaire_point(const SceneDesc& scene, const std::function<void(const Vec3&)>& f) {
  for_each_placed_vertex(scene, f);
  for (const Emitter& e : scene.emitters) {
    if (e.kind == Emitter::Kind::RaySet && e.rays) {
      for (const Vec3f& p : e.rays->position_m) f(to_double(p));
    } else if (e.kind == Emitter::Kind::Point) {
      f(e.position);
    }
  }
}

Vec3 luminaire_centre(const SceneDesc& scene) {
  // The bounding box in the photometric frame (C0, C90, up components).
  const photometry::PhotometricFrame& f = scene.frame;
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  const auto take = [&](const Vec3& world) {
    const Vec3 p = f.to_local(world);
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  };
  for_each_luminaire_point(scene, take);
  if (!(lo.x <= hi.x)) return Vec3{0.0, 0.0, 0.0};
  return f.to_world({0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), lo.z});
}

Vec3 luminous_centre(const std::vector<EscapedRay>& escaped, const photometry::PhotometricFrame& frame,
                     const Vec3& fallback) {
  // In power units × metres: doubles summed in photon order (the list is
  // sorted by photon), so the same escapes give the same centre.
  Vec3 sum{0.0, 0.0, 0.0};
  double weight = 0.0;
  for (const EscapedRay& r : escaped) {
    if (!(dot(r.direction, frame.up) < 0.0)) continue;
    const auto w = static_cast<double>(r.power_units);
    sum = sum + w * r.origin;
    weight += w;
  }
  return weight > 0.0 ? sum / weight : fallback;
}

void NearFieldTally::reset(const NearFieldPlanes& planes) {
  const std::size_t n = planes.distances_m.size() * planes.pixel_count();
  near_units.assign(n, 0);
  far_units.assign(n, 0);
  moved.assign(n, 0);
  const std::size_t c = planes.distances_m.size() * planes.cell_count();
  cell_near_units.assign(c, 0);
  cell_far_units.assign(c, 0);
  cell_moved.assign(c, 0);
}

void NearFieldTally::clear() {
  for (auto* v : {&near_units, &far_units, &moved, &cell_near_units, &cell_far_units, &cell_moved})
    std::fill(v->begin(), v->end(), std::uint64_t{0});
}

void NearFieldTally::add(const NearFieldTally& other) {
  const std::vector<std::uint64_t>* from[] = {&other.near_units, &other.far_units, &other.moved,
                                              &other.cell_near_units, &other.cell_far_units, &other.cell_moved};
  std::vector<std::uint64_t>* to[] = {&near_units, &far_units, &moved, &cell_near_units, &cell_far_units, &cell_moved};
  for (int k = 0; k < 6; ++k)
    for (std::size_t i = 0; i < to[k]->size(); ++i) (*to[k])[i] += (*from[k])[i];
}

namespace {

constexpr std::size_t kOutside = ~std::size_t{0};

// The pixel of a point at local (x along C0, y along C90) on a plane of the
// given half width, `side` pixels a side, or kOutside.
std::size_t pixel_of(double x, double y, double half_width, int side = kNearFieldPixels) {
  const double n = side;
  const double u = (x + half_width) / (2.0 * half_width) * n;
  const double v = (half_width - y) / (2.0 * half_width) * n;
  if (!(u >= 0.0 && u < n && v >= 0.0 && v < n)) return kOutside;
  return static_cast<std::size_t>(v) * static_cast<std::size_t>(side) + static_cast<std::size_t>(u);
}

// Adds one photon to a near/far/moved triple.
void bin(std::size_t near, std::size_t far, std::size_t base, std::uint64_t power_units,
         std::vector<std::uint64_t>& near_units, std::vector<std::uint64_t>& far_units,
         std::vector<std::uint64_t>& moved) {
  if (near != kOutside) near_units[base + near] += power_units;
  if (far != kOutside) far_units[base + far] += power_units;
  if (near != far) {
    if (near != kOutside) ++moved[base + near];
    if (far != kOutside) ++moved[base + far];
  }
}

}  // namespace

void NearFieldTally::add(const NearFieldPlanes& planes, const Vec3& origin, const Vec3& direction,
                         std::uint64_t power_units) {
  const Vec3 nadir = -1.0 * planes.frame.up;
  const double down = dot(direction, nadir);
  if (down <= 0.0) return;
  const Vec3 o = origin - planes.centre;
  const double o_down = dot(o, nadir), o_x = dot(o, planes.frame.c0), o_y = dot(o, planes.frame.c90);
  const double d_x = dot(direction, planes.frame.c0), d_y = dot(direction, planes.frame.c90);
  const std::size_t per_plane = planes.pixel_count(), per_plane_cells = planes.cell_count();
  for (std::size_t k = 0; k < planes.distances_m.size(); ++k) {
    const double d = planes.distances_m[k], w = planes.half_width_m(k);
    const double t_far = d / down;
    const double far_x = t_far * d_x, far_y = t_far * d_y;
    // A photon starting beyond the plane never crosses it.
    const double t_near = (d - o_down) / down;
    const bool crosses = t_near >= 0.0;
    const double near_x = o_x + t_near * d_x, near_y = o_y + t_near * d_y;
    bin(crosses ? pixel_of(near_x, near_y, w) : kOutside, pixel_of(far_x, far_y, w), k * per_plane, power_units,
        near_units, far_units, moved);
    bin(crosses ? pixel_of(near_x, near_y, w, kCriterionCells) : kOutside, pixel_of(far_x, far_y, w, kCriterionCells),
        k * per_plane_cells, power_units, cell_near_units, cell_far_units, cell_moved);
  }
}

const char* to_string(PlaneVerdict v) {
  switch (v) {
    case PlaneVerdict::Passes: return "passes";
    case PlaneVerdict::Fails: return "fails";
    case PlaneVerdict::Undecided: break;
  }
  return "undecided";
}

double normal_upper_quantile(double p) {
  // Bisection on P(Z > z) = erfc(z/√2)/2, which falls from 1 to 0: 200
  // halvings of [−40, 40] reach the doubles' resolution.
  double lo = -40.0, hi = 40.0;
  for (int i = 0; i < 200 && hi - lo > 1e-15; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (0.5 * std::erfc(mid / std::sqrt(2.0)) > p) lo = mid;
    else hi = mid;
  }
  return 0.5 * (lo + hi);
}

namespace {

// The criterion on plane k's cells (near_field.h).
void judge(const NearFieldPlanes& planes, const NearFieldTally& sum, std::size_t k, double photons_so_far,
           NearFieldPlane* p) {
  const std::size_t n_cells = planes.cell_count(), base = k * n_cells;
  std::uint64_t far_max = 0;
  for (std::size_t i = 0; i < n_cells; ++i) far_max = std::max(far_max, sum.cell_far_units[base + i]);
  std::vector<std::size_t> compared;
  for (std::size_t i = 0; i < n_cells; ++i)
    if (far_max > 0 && static_cast<double>(sum.cell_far_units[base + i]) >= kComparedFraction * static_cast<double>(far_max))
      compared.push_back(i);
  p->cells_compared = static_cast<int>(compared.size());
  if (compared.empty()) {
    p->verdict = PlaneVerdict::Undecided;
    p->photons_to_tell = std::numeric_limits<double>::infinity();
    return;
  }
  const double alpha = 1.0 - kConfidence;
  const double z_pass = normal_upper_quantile(alpha);
  // Šidák: each of n two-sided tests at 1 − (1 − α)^(1/n).
  const double per_cell = 1.0 - std::pow(kConfidence, 1.0 / static_cast<double>(compared.size()));
  p->z_fail = normal_upper_quantile(0.5 * per_cell);
  const double limit = kFarFieldLimitPct;
  p->upper_bound_pct = 0.0;
  p->lower_bound_pct = -std::numeric_limits<double>::infinity();
  double scale_needed = 0.0;  // largest (zσ / (1 % − |δ|))² over undecided cells
  bool any_fails = false, all_pass = true;
  for (std::size_t i : compared) {
    const double far = static_cast<double>(sum.cell_far_units[base + i]);
    const double near = static_cast<double>(sum.cell_near_units[base + i]);
    const double photons = far / static_cast<double>(kPowerUnits);
    const double dev = std::abs(near - far) / far * 100.0;
    const double sigma = std::sqrt(static_cast<double>(sum.cell_moved[base + i])) / photons * 100.0;
    p->cell_deviation_pct = std::max(p->cell_deviation_pct, dev);
    p->upper_bound_pct = std::max(p->upper_bound_pct, dev + z_pass * sigma);
    p->lower_bound_pct = std::max(p->lower_bound_pct, dev - p->z_fail * sigma);
    if (dev - p->z_fail * sigma > limit) any_fails = true;
    if (dev + z_pass * sigma > limit) {
      all_pass = false;
      // With σ' = σ·√(N/N'): if the cell's deviation stayed d, passing
      // needs z₁σ' ≤ 1 % − d, failing z_nσ' < d − 1 %; d = |δ| below 1 %,
      // above it the lower bound max(0, |δ| − z₁σ) (noise lifts |δ|).
      const double d = dev < limit ? dev : std::max(0.0, dev - z_pass * sigma);
      const double margin = std::abs(limit - d);
      const double z = d < limit ? z_pass : p->z_fail;
      scale_needed = std::max(scale_needed, margin > 0.0 ? (z * sigma / margin) * (z * sigma / margin)
                                                         : std::numeric_limits<double>::infinity());
    }
  }
  p->max_deviation_bound_pct = p->upper_bound_pct;
  p->verdict = any_fails ? PlaneVerdict::Fails : all_pass ? PlaneVerdict::Passes : PlaneVerdict::Undecided;
  p->photons_to_tell = p->verdict == PlaneVerdict::Undecided ? scale_needed * photons_so_far : 0.0;
}

}  // namespace

std::vector<NearFieldPlane> near_field_planes(const NearFieldPlanes& planes, const NearFieldTally& sum,
                                              double lm_per_unit, double photons) {
  std::vector<NearFieldPlane> out;
  const std::size_t per_plane = planes.pixel_count();
  const std::size_t centre = per_plane / 2;  // odd side: the middle pixel
  for (std::size_t k = 0; k < planes.distances_m.size(); ++k) {
    NearFieldPlane p;
    p.distance_m = planes.distances_m[k];
    p.half_width_m = planes.half_width_m(k);
    p.pixel_size_m = planes.pixel_size_m(k);
    p.pixels = planes.pixels();
    const double per_area = lm_per_unit / (p.pixel_size_m * p.pixel_size_m);
    p.near_lx.resize(per_plane);
    p.far_lx.resize(per_plane);
    double far_max = 0.0;
    for (std::size_t i = 0; i < per_plane; ++i) {
      p.near_lx[i] = static_cast<double>(sum.near_units[k * per_plane + i]) * per_area;
      p.far_lx[i] = static_cast<double>(sum.far_units[k * per_plane + i]) * per_area;
      far_max = std::max(far_max, p.far_lx[i]);
    }
    p.on_axis_lx = p.near_lx[centre];
    p.far_field_on_axis_lx = p.far_lx[centre];
    bool any = false;
    for (std::size_t i = 0; i < per_plane; ++i) {
      if (far_max <= 0.0 || p.far_lx[i] < kComparedFraction * far_max) continue;
      const double far_units = static_cast<double>(sum.far_units[k * per_plane + i]);
      const double dev = std::abs(p.near_lx[i] - p.far_lx[i]) / p.far_lx[i] * 100.0;
      p.max_deviation_pct = std::max(p.max_deviation_pct, dev);
      const auto n = static_cast<std::uint64_t>(far_units / static_cast<double>(kPowerUnits));
      p.min_photons = any ? std::min(p.min_photons, n) : n;
      any = true;
    }
    judge(planes, sum, k, photons, &p);
    out.push_back(std::move(p));
  }
  return out;
}

FarFieldDistance far_field_distance(const std::vector<NearFieldPlane>& planes) {
  std::vector<const NearFieldPlane*> sorted;
  for (const NearFieldPlane& p : planes) sorted.push_back(&p);
  std::sort(sorted.begin(), sorted.end(),
            [](const NearFieldPlane* a, const NearFieldPlane* b) { return a->distance_m < b->distance_m; });
  FarFieldDistance out;
  if (sorted.empty()) return out;
  out.farthest = sorted.back()->verdict;
  for (auto it = sorted.rbegin(); it != sorted.rend(); ++it) {
    if ((*it)->verdict != PlaneVerdict::Passes) {
      if (out.distance_m) out.nearer_plane_m = (*it)->distance_m;
      else out.photons_to_tell = (*it)->verdict == PlaneVerdict::Undecided ? (*it)->photons_to_tell : 0.0;
      break;
    }
    out.distance_m = (*it)->distance_m;
  }
  return out;
}

std::optional<double> far_field_distance_m(const std::vector<NearFieldPlane>& planes) {
  return far_field_distance(planes).distance_m;
}

}  // namespace gonio::sim
