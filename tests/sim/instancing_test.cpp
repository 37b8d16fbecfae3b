// Instanced meshes (sim::Instance): traced through Embree instances, they
// must give what the same copies as world geometry (sim::flattened) give —
// the same hits, the same ledger per mesh, the same far field — and bad
// instances are named.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <cstdlib>
#include <string>
#include <vector>

#include "sim/tracer/embree_scene.h"
#include "sim/emitters/emission.h"
#include "sim/samplers/random.h"
#include "sim/samplers/sampling.h"
#include "sim/shapes.h"
#include "sim/simulation.h"
#include "sim/tracer/tracer.h"

namespace gonio::sim {
namespace {

// A lamp in a ring of glass ellipsoids (one instanced mesh, six copies:
// turned, scaled unevenly, one mirrored), under two brushed reflectors (one
// instanced paraboloid, the second copy mirrored), above a white floor
// (world geometry), with two glowing tiles (one instanced slab) as area
// emitters.
SceneDesc ring_scene() {
  SceneDesc s;
  Material glass;
  glass.name = "glass";
  glass.dielectric = 1.0;
  glass.ior = 1.5;
  glass.attenuation_per_m = 3.0;
  Material brushed;
  brushed.name = "brushed";
  brushed.glossy = 0.85;
  brushed.glossy_mx = 0.3;
  brushed.glossy_my = 0.05;
  Material white{"white", 0.8};
  Material tile{"tile", 0.3, 0.0, 0.0};
  s.materials = {glass, brushed, white, tile};

  Mesh lens = sphere(0.02, 24, 12);
  lens.name = "lens";
  lens.material = 0;
  lens.instanced = true;
  Mesh reflector = paraboloid(0.03, 0.08, 0.01, 12, 32);
  reflector.name = "reflector";
  reflector.material = 1;
  reflector.instanced = true;
  // Tangents along x, so the anisotropic lobe depends on the instance's turn.
  reflector.tangents.assign(reflector.positions.size(), Vec3f{1.0f, 0.0f, 0.0f});
  Mesh floor = disc(0.3, 32);
  transform(floor, translation({0.0, -0.12, 0.0}));
  floor.name = "floor";
  floor.material = 2;
  Mesh glow = slab(0.02, 0.02, 0.004);
  glow.name = "glow";
  glow.material = 3;
  glow.instanced = true;
  s.meshes = {lens, reflector, floor, glow};

  for (int k = 0; k < 6; ++k) {
    const double a = k * std::numbers::pi / 3.0;
    Affine place = translation({0.07 * std::cos(a), -0.02, 0.07 * std::sin(a)}) *
                   rotation({0.3, 1.0, 0.2}, 0.4 * k) * scaling(1.0, 0.6 + 0.1 * k, 1.2);
    if (k == 4) place = place * scaling(-1.0, 1.0, 1.0);
    s.instances.push_back({0, place, "lens-" + std::to_string(k)});
  }
  s.instances.push_back({1, translation({0.0, 0.05, 0.0}) * rotation({0, 1, 0}, 0.3), "reflector-a"});
  s.instances.push_back(
      {1, translation({0.0, 0.05, 0.0}) * scaling(-1.0, 1.0, 1.0) * rotation({0, 1, 0}, 0.3), "reflector-b"});
  s.instances.push_back({3, translation({0.12, -0.05, 0.0}) * rotation({0, 0, 1}, 2.5), "tile-a"});
  s.instances.push_back({3, translation({-0.12, -0.05, 0.0}) * scaling(1.5, 1.0, 0.7), "tile-b"});

  Emitter lamp;
  lamp.name = "lamp";
  lamp.position = {0.0, 0.0, 0.0};
  lamp.flux_lm = 1000.0;
  s.emitters.push_back(lamp);
  for (std::uint32_t i : {8u, 9u}) {
    Emitter e;
    e.name = s.instances[i].name;
    e.kind = Emitter::Kind::Area;
    e.mesh = 3;
    e.instance = i;
    e.flux_lm = 100.0;
    s.emitters.push_back(e);
  }
  return s;
}

// For each mesh of flattened(s), the mesh of `s` it comes from.
std::vector<std::uint32_t> source_mesh(const SceneDesc& s) {
  std::vector<std::uint32_t> out;
  for (std::uint32_t m = 0; m < s.meshes.size(); ++m) {
    if (!s.meshes[m].instanced) {
      out.push_back(m);
      continue;
    }
    for (const Instance& i : s.instances)
      if (i.mesh == m) out.push_back(m);
  }
  return out;
}

TEST(Instancing, FlattenedPlacesEveryCopyAsWorldGeometry) {
  const SceneDesc s = ring_scene();
  EXPECT_EQ(s.placed_triangle_count(),
            s.meshes[2].triangle_count() + 6 * s.meshes[0].triangle_count() +
                2 * s.meshes[1].triangle_count() + 2 * s.meshes[3].triangle_count());
  EXPECT_EQ(s.unique_triangle_count(), s.meshes[0].triangle_count() + s.meshes[1].triangle_count() +
                                           s.meshes[2].triangle_count() + s.meshes[3].triangle_count());
  const SceneDesc f = flattened(s);
  ASSERT_EQ(f.meshes.size(), 11u);
  EXPECT_TRUE(f.instances.empty());
  EXPECT_EQ(f.placed_triangle_count(), s.placed_triangle_count());
  EXPECT_EQ(f.meshes[0].name, "lens-0/lens");
  EXPECT_EQ(f.meshes[8].name, "floor");
  EXPECT_EQ(f.meshes[10].name, "tile-b/glow");
  ASSERT_EQ(f.emitters.size(), 3u);
  EXPECT_EQ(f.emitters[1].mesh, 9u);
  EXPECT_EQ(f.emitters[2].mesh, 10u);
  EXPECT_EQ(f.emitters[2].instance, kNoInstance);
  // Mirrored copies keep their front outward: the enclosed volume of the
  // mirrored ellipsoid is positive, like the others'.
  for (std::size_t m = 0; m < 6; ++m) EXPECT_GT(enclosed_volume_m3(f.meshes[m]), 0.0) << m;
}

TEST(Instancing, EmbreeHitsEqualTheFlattenedScene) {
  const SceneDesc s = ring_scene();
  const SceneDesc f = flattened(s);
  auto inst = EmbreeScene::build(s.meshes, {}, s.instances);
  auto flat = EmbreeScene::build(f.meshes);
  ASSERT_TRUE(inst.ok()) << inst.error().message;
  ASSERT_TRUE(flat.ok());
  EXPECT_EQ(inst->triangle_count(), flat->triangle_count());
  // The instanced box holds the flat one (boxes of transformed boxes).
  EXPECT_LE(inst->bounds().lower.x, flat->bounds().lower.x + 1e-7);
  EXPECT_GE(inst->bounds().upper.y, flat->bounds().upper.y - 1e-7);

  const std::vector<std::uint32_t> from = source_mesh(s);
  // flattened mesh index → instance index (kNoInstance for world meshes).
  std::vector<std::uint32_t> instance_of;
  for (std::uint32_t m = 0; m < s.meshes.size(); ++m) {
    if (!s.meshes[m].instanced) {
      instance_of.push_back(kNoInstance);
      continue;
    }
    for (std::uint32_t i = 0; i < s.instances.size(); ++i)
      if (s.instances[i].mesh == m) instance_of.push_back(i);
  }
  int hits = 0, agree = 0;
  for (std::uint64_t k = 0; k < 20000; ++k) {
    PhotonRandom rng(5, k);
    const Vec3 origin = sample_uniform_sphere(rng) * 0.05;
    const RayQuery ray = ray_query(origin, sample_uniform_sphere(rng));
    RayHit a, b;
    const bool ha = inst->intersect(ray, &a), hb = flat->intersect(ray, &b);
    ASSERT_EQ(ha, hb) << k;
    if (!ha) continue;
    ++hits;
    // Float rounding in the instance transform may pick the neighbour
    // triangle at an edge, never another mesh or a far surface.
    ASSERT_EQ(a.mesh, from[b.mesh]) << k;
    ASSERT_EQ(a.instance, instance_of[b.mesh]) << k;
    const double ta = a.t, tb = b.t;
    ASSERT_NEAR(ta, tb, 1e-5 * (1.0 + tb)) << k;
    const Vec3 na = normalize(Vec3{a.ng[0], a.ng[1], a.ng[2]});
    const Vec3 nb = normalize(Vec3{b.ng[0], b.ng[1], b.ng[2]});
    if (a.triangle == b.triangle) {
      ++agree;
      EXPECT_GT(dot(na, nb), 1.0 - 1e-5) << k;
    }
  }
  EXPECT_GT(hits, 10000);
  EXPECT_GT(agree, hits - hits / 1000);
}

TEST(Instancing, TracedLikeTheFlattenedScene) {
  const SceneDesc s = ring_scene();
  const SceneDesc f = flattened(s);
  SimulationSettings settings;
  settings.threads = 2;
  settings.photons_per_iteration = 100000;
  settings.iterations = 2;
  settings.face_size = 16;
  settings.seed = 11;
  auto a = simulate(s, settings);
  auto b = simulate(f, settings);
  ASSERT_TRUE(a.ok()) << a.error().message;
  ASSERT_TRUE(b.ok()) << b.error().message;
  const Ledger la = a->ledger(), lb = b->ledger();
  EXPECT_TRUE(la.photons_close());
  ASSERT_EQ(la.emitters.size(), lb.emitters.size());
  for (std::size_t e = 0; e < la.emitters.size(); ++e)
    EXPECT_EQ(la.emitters[e].emitted.photons, lb.emitters[e].emitted.photons);
  // Per mesh: the instanced mesh's line is the sum over its copies. Photons
  // follow the same random numbers in both, but float rounding differs in
  // the instance transforms, and paths through the glass (many internal
  // reflections) amplify it: about 1 % of the photons end elsewhere. So the
  // measure is photon noise: each count within 3σ of an independent run's
  // Poisson noise, and the far field moved far less than by a new seed.
  const std::vector<std::uint32_t> from = source_mesh(s);
  std::vector<double> hits(s.meshes.size(), 0.0), absorbed(s.meshes.size(), 0.0);
  for (std::size_t m = 0; m < lb.meshes.size(); ++m) {
    hits[from[m]] += static_cast<double>(lb.meshes[m].hits);
    absorbed[from[m]] += static_cast<double>(lb.meshes[m].absorbed.photons);
  }
  for (std::size_t m = 0; m < s.meshes.size(); ++m) {
    SCOPED_TRACE(s.meshes[m].name);
    EXPECT_GT(hits[m], 1000.0);
    EXPECT_NEAR(static_cast<double>(la.meshes[m].hits), hits[m], 3.0 * std::sqrt(hits[m]));
    EXPECT_NEAR(static_cast<double>(la.meshes[m].absorbed.photons), absorbed[m], 3.0 * std::sqrt(absorbed[m] + 1.0));
  }
  EXPECT_EQ(la.meshes[0].placements, 6u);
  EXPECT_EQ(la.meshes[2].placements, 1u);
  SimulationSettings reseeded = settings;
  reseeded.seed = 12;
  auto c = simulate(f, reseeded);
  ASSERT_TRUE(c.ok());
  const FarField fa = a->far_field(), fb = b->far_field(), fc = c->far_field();
  auto moved = [](const FarField& x, const FarField& y) {
    double sum = 0.0;
    for (std::size_t t = 0; t < x.texel_count(); ++t)
      sum += std::abs(static_cast<double>(x.photons(t)) - static_cast<double>(y.photons(t)));
    return sum / static_cast<double>(y.total_photons());
  };
  const double by_instancing = moved(fa, fb), by_seed = moved(fc, fb);
  std::printf("  far field moved by instancing %.4f, by a new seed %.4f\n", by_instancing, by_seed);
  EXPECT_LT(by_instancing, 0.25 * by_seed);
  EXPECT_NEAR(fa.total_flux_lm(), fb.total_flux_lm(), 3.0 * fb.total_flux_lm() / std::sqrt(static_cast<double>(fb.total_photons())));
}

TEST(Instancing, AnAreaEmitterEmitsFromItsInstance) {
  const SceneDesc s = ring_scene();
  auto sampler = EmissionSampler::create(s);
  ASSERT_TRUE(sampler.ok()) << sampler.error().message;
  const Affine& tile_b = s.instances[9].to_world;
  // tile-b's box: the slab (±0.01, ±0.002, ±0.01) scaled 1.5 × 1 × 0.7 around (−0.12, −0.05, 0).
  int seen = 0;
  for (std::uint64_t k = 0; k < 20000; ++k) {
    PhotonRandom rng(3, k);
    const EmittedPhoton p = sampler->sample(rng);
    if (p.emitter != 2) continue;
    ++seen;
    const Vec3 local = p.origin - tile_b.offset;
    ASSERT_LE(std::abs(local.x), 0.015 + 1e-7);
    ASSERT_LE(std::abs(local.y), 0.002 + 1e-7);
    ASSERT_LE(std::abs(local.z), 0.007 + 1e-7);
    ASSERT_GT(dot(p.direction, p.surface_normal), 0.0);
  }
  EXPECT_GT(seen, 500);
}

TEST(Instancing, BadInstancesAreNamed) {
  auto error = [](const SceneDesc& s) {
    auto t = Tracer::create(s, 8);
    return t.ok() ? std::string() : t.error().message;
  };
  SceneDesc s = ring_scene();
  s.instances[2].mesh = 2;  // the floor is world geometry
  EXPECT_NE(error(s).find("instance 2 'lens-2': mesh 2 'floor' is world geometry"), std::string::npos)
      << error(s);
  s = ring_scene();
  s.instances[3].mesh = 17;
  EXPECT_NE(error(s).find("instance 3 'lens-3': mesh 17 does not exist"), std::string::npos) << error(s);
  s = ring_scene();
  s.instances[1].to_world = scaling(1.0, 0.0, 1.0);
  EXPECT_NE(error(s).find("instance 1 'lens-1': the transform is singular"), std::string::npos) << error(s);
  s = ring_scene();
  s.instances[1].to_world.offset.x = std::nan("");
  EXPECT_NE(error(s).find("not finite"), std::string::npos) << error(s);
  s = ring_scene();
  s.emitters[1].instance = kNoInstance;
  EXPECT_NE(error(s).find("names no instance"), std::string::npos) << error(s);
  s = ring_scene();
  s.emitters[1].instance = 0;  // an instance of the lens, not of the tile
  EXPECT_NE(error(s).find("names no instance"), std::string::npos) << error(s);
}

}  // namespace
}  // namespace gonio::sim
