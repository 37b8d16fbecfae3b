#include "sim/embree_scene.h"

#include <embree3/rtcore.h>
#include <pmmintrin.h>
#include <xmmintrin.h>

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <string>

#include "sim/random.h"
#include "sim/sampling.h"

namespace gonio::sim {

namespace {

// Embree reports errors through a callback; keep the first one.
struct ErrorSink {
  std::mutex mutex;
  std::string first;
};

void on_embree_error(void* user, RTCError code, const char* message) {
  auto* sink = static_cast<ErrorSink*>(user);
  std::lock_guard<std::mutex> lock(sink->mutex);
  if (sink->first.empty())
    sink->first = "Embree error " + std::to_string(static_cast<int>(code)) + ": " +
                  (message ? message : "(no message)");
}

}  // namespace

struct EmbreeScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  Bounds bounds;
  std::size_t triangles = 0;
  ErrorSink errors;

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

EmbreeScene::EmbreeScene(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
EmbreeScene::~EmbreeScene() = default;
EmbreeScene::EmbreeScene(EmbreeScene&&) noexcept = default;
EmbreeScene& EmbreeScene::operator=(EmbreeScene&&) noexcept = default;

Result<EmbreeScene> EmbreeScene::build(const std::vector<Mesh>& meshes,
                                       const EmbreeSceneOptions& options) {
  auto impl = std::make_unique<Impl>();
  impl->device = rtcNewDevice(nullptr);
  if (!impl->device)
    return make_error("cannot create an Embree device (error " +
                      std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
  rtcSetDeviceErrorFunction(impl->device, on_embree_error, &impl->errors);
  impl->scene = rtcNewScene(impl->device);
  if (!impl->scene) return make_error("cannot create an Embree scene: " + impl->errors.first);
  rtcSetSceneFlags(impl->scene, options.robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE);
  const RTCBuildQuality quality = options.quality == EmbreeSceneOptions::Quality::Low      ? RTC_BUILD_QUALITY_LOW
                                  : options.quality == EmbreeSceneOptions::Quality::Medium ? RTC_BUILD_QUALITY_MEDIUM
                                                                                          : RTC_BUILD_QUALITY_HIGH;
  rtcSetSceneBuildQuality(impl->scene, quality);

  constexpr double kInf = std::numeric_limits<double>::infinity();
  Vec3 lo{kInf, kInf, kInf}, hi{-kInf, -kInf, -kInf};
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const Mesh& mesh = meshes[m];
    const std::size_t tris = mesh.triangle_count();
    if (tris == 0) continue;
    RTCGeometry geom = rtcNewGeometry(impl->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    if (!geom) return make_error("cannot create an Embree geometry: " + impl->errors.first);
    // Embree's own buffers carry the padding its SIMD loads need.
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.positions.size()));
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), tris));
    if (!vertices || !indices) {
      rtcReleaseGeometry(geom);
      return make_error("Embree cannot allocate mesh '" + mesh.name + "': " + impl->errors.first);
    }
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
      const Vec3f& p = mesh.positions[v];
      vertices[3 * v] = p.x;
      vertices[3 * v + 1] = p.y;
      vertices[3 * v + 2] = p.z;
    }
    for (std::size_t i = 0; i < 3 * tris; ++i) {
      indices[i] = mesh.indices[i];
      const Vec3f& p = mesh.positions[mesh.indices[i]];
      lo = {std::min(lo.x, double{p.x}), std::min(lo.y, double{p.y}), std::min(lo.z, double{p.z})};
      hi = {std::max(hi.x, double{p.x}), std::max(hi.y, double{p.y}), std::max(hi.z, double{p.z})};
    }
    rtcSetGeometryBuildQuality(geom, quality);
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(impl->scene, geom, static_cast<unsigned>(m));
    rtcReleaseGeometry(geom);
    impl->triangles += tris;
  }
  rtcCommitScene(impl->scene);
  if (!impl->errors.first.empty())
    return make_error("building the Embree scene: " + impl->errors.first);
  impl->bounds = impl->triangles > 0 ? Bounds{lo, hi} : Bounds{};
  return EmbreeScene(std::move(impl));
}

bool EmbreeScene::intersect(const RayQuery& ray, RayHit* hit) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  rh.ray.org_x = ray.origin[0];
  rh.ray.org_y = ray.origin[1];
  rh.ray.org_z = ray.origin[2];
  rh.ray.tnear = ray.t_near;
  rh.ray.dir_x = ray.direction[0];
  rh.ray.dir_y = ray.direction[1];
  rh.ray.dir_z = ray.direction[2];
  rh.ray.time = 0.0f;
  rh.ray.tfar = ray.t_far;
  rh.ray.mask = ~0u;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  hit->mesh = rh.hit.geomID;
  hit->triangle = rh.hit.primID;
  hit->t = rh.ray.tfar;
  hit->u = rh.hit.u;
  hit->v = rh.hit.v;
  // Embree's triangle Ng points to the side where the corners run
  // counter-clockwise, Gonio's front (pinned down by a test).
  hit->ng[0] = rh.hit.Ng_x;
  hit->ng[1] = rh.hit.Ng_y;
  hit->ng[2] = rh.hit.Ng_z;
  return true;
}

const Bounds& EmbreeScene::bounds() const { return impl_->bounds; }
std::size_t EmbreeScene::triangle_count() const { return impl_->triangles; }

EmbreeScene::RawRate EmbreeScene::measure_random_rays(std::uint64_t count, std::uint64_t seed,
                                                     int threads) const {
  // Rays first, so that only rtcIntersect1 is timed.
  std::vector<RayQuery> rays(count);
  const Bounds& box = impl_->bounds;
  for (std::uint64_t i = 0; i < count; ++i) {
    PhotonRandom rng(seed, i);
    const Vec3 o{box.lower.x + rng.uniform() * (box.upper.x - box.lower.x),
                 box.lower.y + rng.uniform() * (box.upper.y - box.lower.y),
                 box.lower.z + rng.uniform() * (box.upper.z - box.lower.z)};
    rays[i] = ray_query(o, sample_uniform_sphere(rng));
  }
  return measure_rays(rays, threads);
}

EmbreeScene::RawRate EmbreeScene::measure_rays(const std::vector<RayQuery>& rays,
                                              int threads) const {
  RawRate out;
  const std::uint64_t count = rays.size();
  out.rays = count;
  constexpr std::uint64_t kChunk = 4096;
  const std::uint64_t chunks = (count + kChunk - 1) / kChunk;
  tbb::combinable<std::uint64_t> hits([] { return std::uint64_t{0}; });
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  const auto start = std::chrono::steady_clock::now();
  arena.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<std::uint64_t>(0, chunks, 1),
        [&](const tbb::blocked_range<std::uint64_t>& range) {
          FloatModeGuard float_mode;
          std::uint64_t local = 0;
          RTCIntersectContext context;
          rtcInitIntersectContext(&context);
          for (std::uint64_t c = range.begin(); c != range.end(); ++c) {
            const std::uint64_t end = std::min(count, (c + 1) * kChunk);
            for (std::uint64_t i = c * kChunk; i < end; ++i) {
              const RayQuery& r = rays[i];
              RTCRayHit rh;
              rh.ray.org_x = r.origin[0];
              rh.ray.org_y = r.origin[1];
              rh.ray.org_z = r.origin[2];
              rh.ray.tnear = r.t_near;
              rh.ray.dir_x = r.direction[0];
              rh.ray.dir_y = r.direction[1];
              rh.ray.dir_z = r.direction[2];
              rh.ray.time = 0.0f;
              rh.ray.tfar = r.t_far;
              rh.ray.mask = ~0u;
              rh.ray.id = 0;
              rh.ray.flags = 0;
              rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
              rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
              rtcIntersect1(impl_->scene, &context, &rh);
              local += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
            }
          }
          hits.local() += local;
        },
        tbb::simple_partitioner());
  });
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.hits = hits.combine([](std::uint64_t a, std::uint64_t b) { return a + b; });
  return out;
}

FloatModeGuard::FloatModeGuard() : saved_(_mm_getcsr()) {
  _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
  _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
}
FloatModeGuard::~FloatModeGuard() { _mm_setcsr(saved_); }

}  // namespace gonio::sim
