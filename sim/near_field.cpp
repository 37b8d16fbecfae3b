#include "sim/near_field.h"

#include <algorithm>
#include <cmath>

#include "sim/ledger.h"
#include "sim/ray_set_emitter.h"

namespace gonio::sim {

Vec3 luminaire_centre(const SceneDesc& scene) {
  // The bounding box in the photometric frame (C0, C90, up components).
  const photometry::PhotometricFrame& f = scene.frame;
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  const auto take = [&](const Vec3& world) {
    const Vec3 p = f.to_local(world);
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  };
  for_each_placed_vertex(scene, take);
  for (const Emitter& e : scene.emitters) {
    if (e.kind == Emitter::Kind::RaySet && e.rays) {
      for (const Vec3f& p : e.rays->position_m) take(to_double(p));
    } else if (e.kind == Emitter::Kind::Point) {
      take(e.position);
    }
  }
  if (!(lo.x <= hi.x)) return Vec3{0.0, 0.0, 0.0};
  return f.to_world({0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), lo.z});
}

void NearFieldTally::reset(const NearFieldPlanes& planes) {
  const std::size_t n = planes.distances_m.size() * planes.pixel_count();
  near_units.assign(n, 0);
  far_units.assign(n, 0);
  moved.assign(n, 0);
}

void NearFieldTally::clear() {
  std::fill(near_units.begin(), near_units.end(), std::uint64_t{0});
  std::fill(far_units.begin(), far_units.end(), std::uint64_t{0});
  std::fill(moved.begin(), moved.end(), std::uint64_t{0});
}

void NearFieldTally::add(const NearFieldTally& other) {
  for (std::size_t i = 0; i < near_units.size(); ++i) near_units[i] += other.near_units[i];
  for (std::size_t i = 0; i < far_units.size(); ++i) far_units[i] += other.far_units[i];
  for (std::size_t i = 0; i < moved.size(); ++i) moved[i] += other.moved[i];
}

namespace {

constexpr std::size_t kOutside = ~std::size_t{0};

// The pixel of a point at local (x along C0, y along C90) on a plane of the
// given half width, or kOutside.
std::size_t pixel_of(double x, double y, double half_width) {
  const double n = kNearFieldPixels;
  const double u = (x + half_width) / (2.0 * half_width) * n;
  const double v = (half_width - y) / (2.0 * half_width) * n;
  if (!(u >= 0.0 && u < n && v >= 0.0 && v < n)) return kOutside;
  return static_cast<std::size_t>(v) * kNearFieldPixels + static_cast<std::size_t>(u);
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
  const std::size_t per_plane = planes.pixel_count();
  for (std::size_t k = 0; k < planes.distances_m.size(); ++k) {
    const double d = planes.distances_m[k], w = planes.half_width_m(k);
    const double t_far = d / down;
    const std::size_t far = pixel_of(t_far * d_x, t_far * d_y, w);
    // A photon starting beyond the plane never crosses it.
    const double t_near = (d - o_down) / down;
    const std::size_t near = t_near >= 0.0 ? pixel_of(o_x + t_near * d_x, o_y + t_near * d_y, w) : kOutside;
    const std::size_t base = k * per_plane;
    if (near != kOutside) near_units[base + near] += power_units;
    if (far != kOutside) far_units[base + far] += power_units;
    if (near != far) {
      if (near != kOutside) ++moved[base + near];
      if (far != kOutside) ++moved[base + far];
    }
  }
}

std::vector<NearFieldPlane> near_field_planes(const NearFieldPlanes& planes, const NearFieldTally& sum,
                                              double lm_per_unit) {
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
      if (far_max <= 0.0 || p.far_lx[i] < 0.1 * far_max) continue;
      const double far_units = static_cast<double>(sum.far_units[k * per_plane + i]);
      // Photons in the pixel, in nominal photons (power units / kPowerUnits).
      const double photons = far_units / static_cast<double>(kPowerUnits);
      const double dev = std::abs(p.near_lx[i] - p.far_lx[i]) / p.far_lx[i] * 100.0;
      const double sigma = std::sqrt(static_cast<double>(sum.moved[k * per_plane + i])) / photons * 100.0;
      p.max_deviation_pct = std::max(p.max_deviation_pct, dev);
      p.max_deviation_bound_pct = std::max(p.max_deviation_bound_pct, dev + 2.0 * sigma);
      const auto n = static_cast<std::uint64_t>(photons);
      p.min_photons = any ? std::min(p.min_photons, n) : n;
      any = true;
    }
    out.push_back(std::move(p));
  }
  return out;
}

std::optional<double> far_field_distance_m(const std::vector<NearFieldPlane>& planes, double limit_pct) {
  std::vector<const NearFieldPlane*> sorted;
  for (const NearFieldPlane& p : planes) sorted.push_back(&p);
  std::sort(sorted.begin(), sorted.end(),
            [](const NearFieldPlane* a, const NearFieldPlane* b) { return a->distance_m < b->distance_m; });
  std::optional<double> best;
  for (auto it = sorted.rbegin(); it != sorted.rend(); ++it) {
    if (!((*it)->max_deviation_bound_pct <= limit_pct)) break;
    best = (*it)->distance_m;
  }
  return best;
}

}  // namespace gonio::sim
