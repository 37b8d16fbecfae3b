#include "sim/tracer/embree_scene.h"

#include <embree3/rtcore.h>
#include <sys/prctl.h>
#include <pmmintrin.h>
#include <xmmintrin.h>

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <mutex>
#include <string>

#include "sim/samplers/random.h"
#include "sim/samplers/sampling.h"

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
  std::vector<RTCScene> prototypes;  // one per instanced mesh that has instances
  Bounds bounds;
  std::size_t triangles = 0;
  ErrorSink errors;
  // Instances: top-level geometry id = instance_base + instance index.
  std::uint32_t instance_base = 0;
  std::vector<std::uint32_t> instance_mesh;
  std::vector<std::array<float, 9>> instance_normal;  // sign(det)·cofactor, row-major
  int packet_width = 1;  // lanes of occluded(rays, n, ·): 16, 8, 4 or 1

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    for (RTCScene p : prototypes) rtcReleaseScene(p);
    if (device) rtcReleaseDevice(device);
  }
};

EmbreeScene::EmbreeScene(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
EmbreeScene::~EmbreeScene() = default;
EmbreeScene::EmbreeScene(EmbreeScene&&) noexcept = default;
EmbreeScene& EmbreeScene::operator=(EmbreeScene&&) noexcept = default;

namespace {

// One mesh as an Embree triangle geometry attached to `scene` under `id`.
Status attach_mesh(RTCDevice device, RTCScene scene, const Mesh& mesh, unsigned id,
                   RTCBuildQuality quality, const ErrorSink& errors) {
  const std::size_t tris = mesh.triangle_count();
  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  if (!geom) return make_error("cannot create an Embree geometry: " + errors.first);
  // Embree's own buffers carry the padding its SIMD loads need.
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.positions.size()));
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), tris));
  if (!vertices || !indices) {
    rtcReleaseGeometry(geom);
    return make_error("Embree cannot allocate mesh '" + mesh.name + "': " + errors.first);
  }
  // In parallel: at 10⁶ triangles the copies (18 MB of fresh pages) took 11 ms.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.positions.size(), 65536),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t v = r.begin(); v != r.end(); ++v) {
                        const Vec3f& p = mesh.positions[v];
                        vertices[3 * v] = p.x;
                        vertices[3 * v + 1] = p.y;
                        vertices[3 * v + 2] = p.z;
                      }
                    });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, 3 * tris, 65536),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      std::copy(mesh.indices.begin() + static_cast<std::ptrdiff_t>(r.begin()),
                                mesh.indices.begin() + static_cast<std::ptrdiff_t>(r.end()),
                                indices + r.begin());
                    });
  rtcSetGeometryBuildQuality(geom, quality);
  rtcCommitGeometry(geom);
  rtcAttachGeometryByID(scene, geom, id);
  rtcReleaseGeometry(geom);
  return Ok{};
}

struct Box {
  Vec3 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
          std::numeric_limits<double>::infinity()};
  Vec3 hi{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
          -std::numeric_limits<double>::infinity()};
  void add(const Vec3& p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  bool empty() const { return !(lo.x <= hi.x); }
};

// The box of the triangles' corners (vertices no triangle uses left out).
Box mesh_box(const Mesh& mesh) {
  Box b;
  for (std::size_t i = 0; i < 3 * mesh.triangle_count(); ++i) {
    const Vec3f& p = mesh.positions[mesh.indices[i]];
    b.add({p.x, p.y, p.z});
  }
  return b;
}

// Embree asks for transparent huge pages for its BVH (madvise). On the
// virtual machines this project runs on (and MPI jobs on cloud machines),
// faulting in a fresh 2 MB page costs the hypervisor's backing of it: 1 GB
// took 1.35–2.25 s where 4 KB pages took 0.35 s. Huge pages pay back while
// tracing (fewer TLB misses: the glass part at 10⁷ triangles traced 13–14 %
// slower on 4 KB pages), so the quick tree, the one for runs too short to
// repay a better build (bvh_quality_for), is also built on small pages:
// there its 10⁷-triangle build took 0.6–1.2 s (median of six 0.7 s) instead
// of 1.7–2.6 s (median 2.4 s). Linux's PR_SET_THP_DISABLE turns them off for
// the process during the build and back on after (docs/validation.md).
class HugePagesOffWhileBuilding {
 public:
  explicit HugePagesOffWhileBuilding(bool wanted)
      : switched_(wanted && prctl(PR_GET_THP_DISABLE, 0, 0, 0, 0) == 0) {
    if (switched_) switched_ = prctl(PR_SET_THP_DISABLE, 1, 0, 0, 0) == 0;
  }
  ~HugePagesOffWhileBuilding() {
    if (switched_) prctl(PR_SET_THP_DISABLE, 0, 0, 0, 0);
  }
  HugePagesOffWhileBuilding(const HugePagesOffWhileBuilding&) = delete;
  HugePagesOffWhileBuilding& operator=(const HugePagesOffWhileBuilding&) = delete;

 private:
  bool switched_;
};

}  // namespace

Result<EmbreeScene> EmbreeScene::build(const std::vector<Mesh>& meshes,
                                       const EmbreeSceneOptions& options,
                                       const std::vector<Instance>& instances) {
  const HugePagesOffWhileBuilding small_pages(options.quality == EmbreeSceneOptions::Quality::Low);
  auto impl = std::make_unique<Impl>();
  impl->device = rtcNewDevice(nullptr);
  if (!impl->device)
    return make_error("cannot create an Embree device (error " +
                      std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
  rtcSetDeviceErrorFunction(impl->device, on_embree_error, &impl->errors);
  // The widest packet the device runs natively (its ISA: AVX-512 16, AVX 8,
  // SSE 4); a wider packet than native is split by Embree into narrower ones.
  if (rtcGetDeviceProperty(impl->device, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED))
    impl->packet_width = 16;
  else if (rtcGetDeviceProperty(impl->device, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED))
    impl->packet_width = 8;
  else if (rtcGetDeviceProperty(impl->device, RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED))
    impl->packet_width = 4;
  // For measurement only (docs/validation.md, issue 43): GONIO_PACKET_WIDTH
  // 1, 4 or 8 caps the width (1: one rtcOccluded1 a ray, as before packets).
  // The answers are the same at every width, so the bytes are too.
  if (const char* cap = std::getenv("GONIO_PACKET_WIDTH"); cap && *cap) {
    const int w = std::atoi(cap);
    if (w == 1 || w == 4 || w == 8 || w == 16) impl->packet_width = std::min(impl->packet_width, w);
  }
  const RTCSceneFlags flags = options.robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE;
  const RTCBuildQuality quality = options.quality == EmbreeSceneOptions::Quality::Low      ? RTC_BUILD_QUALITY_LOW
                                  : options.quality == EmbreeSceneOptions::Quality::Medium ? RTC_BUILD_QUALITY_MEDIUM
                                                                                          : RTC_BUILD_QUALITY_HIGH;
  auto new_scene = [&]() -> RTCScene {
    RTCScene scene = rtcNewScene(impl->device);
    if (!scene) return nullptr;
    rtcSetSceneFlags(scene, flags);
    rtcSetSceneBuildQuality(scene, quality);
    return scene;
  };
  impl->scene = new_scene();
  if (!impl->scene) return make_error("cannot create an Embree scene: " + impl->errors.first);

  Box world;
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const Mesh& mesh = meshes[m];
    if (mesh.instanced || mesh.triangle_count() == 0) continue;
    if (Status s = attach_mesh(impl->device, impl->scene, mesh, static_cast<unsigned>(m), quality, impl->errors); !s.ok())
      return s.error();
    const Box b = mesh_box(mesh);
    world.add(b.lo);
    world.add(b.hi);
    impl->triangles += mesh.triangle_count();
  }

  // Instanced meshes: one Embree scene each, committed (built) once with
  // Embree's parallel builder, then one instance geometry per copy.
  impl->instance_base = static_cast<std::uint32_t>(meshes.size());
  std::vector<RTCScene> prototype(meshes.size(), nullptr);
  std::vector<Box> prototype_box(meshes.size());
  for (const Instance& inst : instances) {
    const std::uint32_t m = inst.mesh;
    if (m >= meshes.size() || !meshes[m].instanced || prototype[m] || meshes[m].triangle_count() == 0)
      continue;
    RTCScene child = new_scene();
    if (!child) return make_error("cannot create an Embree scene: " + impl->errors.first);
    impl->prototypes.push_back(child);
    if (Status s = attach_mesh(impl->device, child, meshes[m], 0, quality, impl->errors); !s.ok())
      return s.error();
    rtcCommitScene(child);
    prototype[m] = child;
    prototype_box[m] = mesh_box(meshes[m]);
  }
  impl->instance_mesh.reserve(instances.size());
  impl->instance_normal.reserve(instances.size());
  for (std::size_t k = 0; k < instances.size(); ++k) {
    const Instance& inst = instances[k];
    impl->instance_mesh.push_back(inst.mesh);
    const Affine& a = inst.to_world;
    // sign(det)·cofactor = |det|·inverse transpose: the front normal of the
    // placed triangle, winding turned under mirroring (sim/affine.h).
    const Vec3 c0 = a.normal({1, 0, 0}), c1 = a.normal({0, 1, 0}), c2 = a.normal({0, 0, 1});
    impl->instance_normal.push_back({static_cast<float>(c0.x), static_cast<float>(c1.x), static_cast<float>(c2.x),
                                     static_cast<float>(c0.y), static_cast<float>(c1.y), static_cast<float>(c2.y),
                                     static_cast<float>(c0.z), static_cast<float>(c1.z), static_cast<float>(c2.z)});
    if (inst.mesh >= meshes.size() || !prototype[inst.mesh]) continue;
    RTCGeometry geom = rtcNewGeometry(impl->device, RTC_GEOMETRY_TYPE_INSTANCE);
    if (!geom) return make_error("cannot create an Embree instance: " + impl->errors.first);
    rtcSetGeometryInstancedScene(geom, prototype[inst.mesh]);
    // Column-major 3×4: the linear part's columns, then the offset.
    const float xfm[12] = {static_cast<float>(a.m[0][0]), static_cast<float>(a.m[1][0]), static_cast<float>(a.m[2][0]),
                           static_cast<float>(a.m[0][1]), static_cast<float>(a.m[1][1]), static_cast<float>(a.m[2][1]),
                           static_cast<float>(a.m[0][2]), static_cast<float>(a.m[1][2]), static_cast<float>(a.m[2][2]),
                           static_cast<float>(a.offset.x), static_cast<float>(a.offset.y), static_cast<float>(a.offset.z)};
    rtcSetGeometryTransform(geom, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm);
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(impl->scene, geom, impl->instance_base + static_cast<unsigned>(k));
    rtcReleaseGeometry(geom);
    const Box& b = prototype_box[inst.mesh];
    for (int corner = 0; corner < 8; ++corner)
      world.add(a.point({corner & 1 ? b.hi.x : b.lo.x, corner & 2 ? b.hi.y : b.lo.y, corner & 4 ? b.hi.z : b.lo.z}));
    impl->triangles += meshes[inst.mesh].triangle_count();
  }
  rtcCommitScene(impl->scene);
  if (!impl->errors.first.empty())
    return make_error("building the Embree scene: " + impl->errors.first);
  impl->bounds = world.empty() ? Bounds{} : Bounds{world.lo, world.hi};
  return EmbreeScene(std::move(impl));
}

const char* to_string(EmbreeSceneOptions::Quality q) {
  switch (q) {
    case EmbreeSceneOptions::Quality::Low: return "low";
    case EmbreeSceneOptions::Quality::Medium: return "medium";
    case EmbreeSceneOptions::Quality::High: return "high";
  }
  return "high";
}

EmbreeSceneOptions::Quality bvh_quality_for(std::size_t unique_triangles, std::uint64_t planned_photons) {
  return 2.0 * static_cast<double>(planned_photons) < static_cast<double>(unique_triangles)
             ? EmbreeSceneOptions::Quality::Low
             : EmbreeSceneOptions::Quality::High;
}

bool EmbreeScene::occluded(const RayQuery& ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay r;
  r.org_x = ray.origin[0];
  r.org_y = ray.origin[1];
  r.org_z = ray.origin[2];
  r.tnear = ray.t_near;
  r.dir_x = ray.direction[0];
  r.dir_y = ray.direction[1];
  r.dir_z = ray.direction[2];
  r.time = 0.0f;
  r.tfar = ray.t_far;
  r.mask = ~0u;
  r.id = 0;
  r.flags = 0;
  rtcOccluded1(impl_->scene, &context, &r);
  // Embree marks an occluded ray by setting tfar to −∞.
  return r.tfar < 0.0f;
}

namespace {

// One packet of W lanes (RTCRay4/8/16) from rays[0, n), n ≤ W; inactive
// lanes are masked off.
template <int W, typename Packet, typename Occluded>
void occluded_packet(RTCScene scene, const RayQuery* rays, std::size_t n, std::uint8_t* out,
                     Occluded occluded) {
  alignas(64) int valid[W];
  alignas(64) Packet r;
  for (int i = 0; i < W; ++i) {
    const bool on = static_cast<std::size_t>(i) < n;
    valid[i] = on ? -1 : 0;
    const RayQuery& q = rays[on ? i : 0];
    r.org_x[i] = q.origin[0];
    r.org_y[i] = q.origin[1];
    r.org_z[i] = q.origin[2];
    r.tnear[i] = q.t_near;
    r.dir_x[i] = q.direction[0];
    r.dir_y[i] = q.direction[1];
    r.dir_z[i] = q.direction[2];
    r.time[i] = 0.0f;
    r.tfar[i] = q.t_far;
    r.mask[i] = ~0u;
    r.id[i] = static_cast<unsigned>(i);
    r.flags[i] = 0;
  }
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  occluded(valid, scene, &context, &r);
  for (std::size_t i = 0; i < n; ++i) out[i] = r.tfar[i] < 0.0f ? 1 : 0;
}

}  // namespace

int EmbreeScene::packet_width() const { return impl_->packet_width; }

void EmbreeScene::occluded(const RayQuery* rays, std::size_t n, std::uint8_t* occluded) const {
  const auto width = static_cast<std::size_t>(impl_->packet_width);
  for (std::size_t i = 0; i < n; i += width) {
    const std::size_t m = std::min(width, n - i);
    if (m == 1 || width == 1) {
      for (std::size_t j = 0; j < m; ++j) occluded[i + j] = this->occluded(rays[i + j]) ? 1 : 0;
    } else if (width == 16) {
      occluded_packet<16, RTCRay16>(impl_->scene, rays + i, m, occluded + i, rtcOccluded16);
    } else if (width == 8) {
      occluded_packet<8, RTCRay8>(impl_->scene, rays + i, m, occluded + i, rtcOccluded8);
    } else {
      occluded_packet<4, RTCRay4>(impl_->scene, rays + i, m, occluded + i, rtcOccluded4);
    }
  }
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
  hit->triangle = rh.hit.primID;
  hit->t = rh.ray.tfar;
  hit->u = rh.hit.u;
  hit->v = rh.hit.v;
  // Embree's triangle Ng points to the side where the corners run
  // counter-clockwise, Gonio's front (pinned down by a test).
  const std::uint32_t inst = rh.hit.instID[0];
  if (inst == RTC_INVALID_GEOMETRY_ID) {
    hit->mesh = rh.hit.geomID;
    hit->instance = kNoInstance;
    hit->ng[0] = rh.hit.Ng_x;
    hit->ng[1] = rh.hit.Ng_y;
    hit->ng[2] = rh.hit.Ng_z;
    return true;
  }
  // An instance reports Ng in the mesh's frame.
  const std::uint32_t k = inst - impl_->instance_base;
  hit->mesh = impl_->instance_mesh[k];
  hit->instance = k;
  const std::array<float, 9>& n = impl_->instance_normal[k];
  hit->ng[0] = n[0] * rh.hit.Ng_x + n[1] * rh.hit.Ng_y + n[2] * rh.hit.Ng_z;
  hit->ng[1] = n[3] * rh.hit.Ng_x + n[4] * rh.hit.Ng_y + n[5] * rh.hit.Ng_z;
  hit->ng[2] = n[6] * rh.hit.Ng_x + n[7] * rh.hit.Ng_y + n[8] * rh.hit.Ng_z;
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
