// The scene's triangles in an Embree 3 BVH, behind Gonio types only:
// sim/tracer/embree_scene.cpp is the one file that includes Embree.
//
// One Embree geometry per world sim::Mesh (geometry id = mesh index); an
// instanced mesh is one Embree scene of its own, placed by one Embree
// instance per sim::Instance (one level), so its BVH is built once however
// many copies there are. Built with high quality and robust triangle tests
// unless EmbreeSceneOptions says otherwise; single-ray incoherent queries
// (rtcIntersect1). Callers set
// flush-to-zero and denormals-are-zero on their threads (FloatModeGuard).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "photometry/diagnostics.h"
#include "sim/scene.h"

namespace gonio::sim {

struct EmbreeSceneOptions {
  // RTC_SCENE_FLAG_ROBUST: watertight triangle tests. Without it a ray
  // through a shared edge or vertex can miss both triangles and leave a
  // closed mesh (seen: photons trapped by total internal reflection in a
  // glass sphere escaping after ~90 reflections). Costs ~5 % of Embree's rate.
  bool robust = true;
  // Embree's BVH build quality (RTC_BUILD_QUALITY_LOW / MEDIUM / HIGH):
  // High adds spatial splits, the best trees for static scenes at the
  // highest build cost; gonio_sim_benchmarks' BM_BvhQuality measures both
  // sides on the large models. Low, the tree of short runs, is also built on
  // 4 KB pages rather than the huge pages Embree asks for: quicker to fault
  // in on virtual machines, slower to trace (sim/tracer/embree_scene.cpp).
  enum class Quality { Low, Medium, High };
  Quality quality = Quality::High;
};

// "low", "medium" or "high".
const char* to_string(EmbreeSceneOptions::Quality q);

// The build quality that makes setup and tracing quickest for a run of
// `planned_photons` photons on `unique_triangles` stored triangles: Low
// when the run is short for the model's size (fewer photons than half its
// triangles), else High. Measured (`gonio simulate --bvh-quality`, 2
// threads, medians of five runs): a glass part of 10⁶ triangles builds in
// 0.12 s with Low and 0.27 s with High and traces 2.73 against 3.12 M rays/s;
// at 10⁷, 2.0 against 2.8 s and 1.71 against 2.08 M rays/s (~2 rays a
// photon): Low pays off below 0.4–1.7 photons a triangle. Medium builds
// about as slowly as High and traces more slowly, so it is never chosen.
EmbreeSceneOptions::Quality bvh_quality_for(std::size_t unique_triangles, std::uint64_t planned_photons);

// A ray query: origin and direction (need not be unit; t is measured in
// direction lengths), and the interval (t_near, t_far).
struct RayQuery {
  float origin[3];
  float direction[3];
  float t_near = 0.0f;
  float t_far = 3.0e38f;
};
// The query for a ray given in doubles, over (0, ∞).
inline RayQuery ray_query(const Vec3& origin, const Vec3& direction) {
  return {{static_cast<float>(origin.x), static_cast<float>(origin.y), static_cast<float>(origin.z)},
          {static_cast<float>(direction.x), static_cast<float>(direction.y), static_cast<float>(direction.z)}};
}

struct RayHit {
  std::uint32_t mesh;      // index in SceneDesc::meshes
  std::uint32_t instance;  // index in SceneDesc::instances, or kNoInstance
  std::uint32_t triangle;  // index in that mesh
  float t;                 // distance along the ray, in direction lengths
  float u, v;              // barycentrics: p = (1 − u − v)·p0 + u·p1 + v·p2
  float ng[3];             // geometric normal in world space, unnormalised,
                           // towards the front side (counter-clockwise
                           // winding; for an instance, after its transform)
};

// Axis-aligned box [m].
struct Bounds {
  Vec3 lower, upper;
  double diagonal() const { return length(upper - lower); }
};

class EmbreeScene {
 public:
  // Errors: Embree's own (device creation, out of memory), named.
  // The meshes must be valid (indices in range, finite positions), and the
  // instances too (an instanced mesh, an invertible finite transform).
  static Result<EmbreeScene> build(const std::vector<Mesh>& meshes,
                                   const EmbreeSceneOptions& options = {},
                                   const std::vector<Instance>& instances = {});
  ~EmbreeScene();
  EmbreeScene(EmbreeScene&&) noexcept;
  EmbreeScene& operator=(EmbreeScene&&) noexcept;

  // Closest hit, if any.
  bool intersect(const RayQuery& ray, RayHit* hit) const;
  // Whether the ray meets any surface (Embree's occlusion query: the first
  // hit found ends it, cheaper than intersect; shadow rays).
  bool occluded(const RayQuery& ray) const;
  // The same for n rays at once, traced as Embree packets of the CPU's
  // native width (16, 8 or 4 lanes, chosen when the scene is built; single
  // rays where the device has no packet kernels): occluded[i] is 1 where
  // rays[i] meets a surface, else 0. The answers are those of occluded()
  // ray by ray (the same robust intersector; tested), in any order of the
  // packets' lanes. Shadow rays of one vertex (next-event estimation's
  // connections) share their origin and go as one packet.
  void occluded(const RayQuery* rays, std::size_t n, std::uint8_t* occluded) const;
  // Lanes per packet occluded(rays, n, ·) uses (1: single rays).
  int packet_width() const;

  // Bounds of every triangle (an instance: its mesh's box transformed, a
  // box around the box); empty scenes give a zero box at the origin.
  const Bounds& bounds() const;
  std::size_t triangle_count() const;  // as placed (instances counted)

  // The physical limit of the tracer on this scene: `count` rays with
  // origins uniform in the bounding box and uniform directions, traced with
  // bare rtcIntersect1 on `threads` threads (0: all). Returns the rays
  // that hit and the wall time of the tracing alone (rays generated first).
  struct RawRate {
    std::uint64_t rays = 0;
    std::uint64_t hits = 0;
    double seconds = 0.0;
    double rays_per_s() const { return seconds > 0.0 ? static_cast<double>(rays) / seconds : 0.0; }
  };
  RawRate measure_random_rays(std::uint64_t count, std::uint64_t seed, int threads) const;
  // The same for given rays (e.g. the tracer's own, recorded): the cost of
  // bare rtcIntersect1 on exactly the queries a simulation makes.
  RawRate measure_rays(const std::vector<RayQuery>& rays, int threads) const;

 private:
  struct Impl;
  explicit EmbreeScene(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// Sets flush-to-zero and denormals-are-zero on this thread for its lifetime
// (Embree's recommendation; denormal floats are slow) and restores the
// previous mode after.
class FloatModeGuard {
 public:
  FloatModeGuard();
  ~FloatModeGuard();
  FloatModeGuard(const FloatModeGuard&) = delete;
  FloatModeGuard& operator=(const FloatModeGuard&) = delete;

 private:
  unsigned int saved_;
};

}  // namespace gonio::sim
