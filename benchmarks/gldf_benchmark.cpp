// What `gonio simulate --format gldf` adds: a GLDF container for the LED
// array sample (product.xml, the LDT and IES of a 5° × 2.5° Type C table,
// the model as L3D), against writing the LDT and IES alone in the same run.
// Counters give the size of each part in bytes.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "io/photometric/gldf.h"
#include "io/model/gltf.h"
#include "io/photometric/ies.h"
#include "io/photometric/ldt.h"
#include "photometry/distribution.h"

namespace {

using namespace gonio;

// A Lambertian table on the grid simulate writes by default (C 0…360 every
// 5°, γ every 2.5°): the writers' cost depends on the grid, not the values.
photometry::Distribution table() {
  photometry::Distribution d;
  for (int i = 0; i <= 72; ++i) d.horizontal_deg.push_back(5.0 * i);
  for (int j = 0; j <= 72; ++j) d.vertical_deg.push_back(2.5 * j);
  for (int i = 0; i <= 72; ++i)
    for (double g : d.vertical_deg)
      d.candela.push_back(g < 90 ? 900.0 / std::numbers::pi * std::cos(g * std::numbers::pi / 180.0) : 0.0);
  d.lamps = {photometry::LampSet{9, "LED die", 900.0, "", "", photometry::kNaN}};
  return d;
}

const sim::SceneDesc& led_array() {
  static const sim::SceneDesc scene = [] {
    auto s = io::load_gltf(GONIO_SAMPLES_DIR "/led-array/led-array.gltf", nullptr);
    if (!s.ok()) {
      std::fprintf(stderr, "%s\n", to_string(s.error()).c_str());
      std::abort();
    }
    return std::move(s).value();
  }();
  return scene;
}

void BM_LdtAndIes(benchmark::State& state) {
  const photometry::Distribution d = table();
  for (auto _ : state) {
    auto ldt = io::write_ldt(d, {}, nullptr);
    std::string ies = io::write_ies(d, {}, nullptr);
    benchmark::DoNotOptimize(ldt);
    benchmark::DoNotOptimize(ies);
  }
}
BENCHMARK(BM_LdtAndIes)->Unit(benchmark::kMillisecond);

void BM_GldfLedArray(benchmark::State& state) {
  const photometry::Distribution d = table();
  const sim::SceneDesc& scene = led_array();
  std::size_t total = 0, product = 0, ldt_bytes = 0, ies_bytes = 0, l3d_bytes = 0, obj_bytes = 0;
  for (auto _ : state) {
    io::GldfProduct p;
    p.name = "led-array";
    auto ldt = io::write_ldt(d, {}, nullptr);
    p.photometries.push_back({"led-array.ldt", "ldc/eulumdat", *ldt, d});
    p.photometries.push_back({"led-array.ies", "ldc/ies", io::write_ies(d, {}, nullptr), d});
    p.geometry = io::l3d_from_scene(scene);
    p.created_unix = 1764620000;
    auto bytes = io::write_gldf(p);
    if (!bytes.ok()) state.SkipWithError(bytes.error().message.c_str());
    total = bytes->size();
    product = io::gldf_product_xml(p).size();
    ldt_bytes = p.photometries[0].bytes.size();
    ies_bytes = p.photometries[1].bytes.size();
    obj_bytes = p.geometry->obj.size();
    l3d_bytes = io::write_l3d(*p.geometry, "Gonio", p.created_unix)->size();
    benchmark::DoNotOptimize(bytes);
  }
  state.counters["gldf_bytes"] = static_cast<double>(total);
  state.counters["product_xml_bytes"] = static_cast<double>(product);
  state.counters["ldt_bytes"] = static_cast<double>(ldt_bytes);
  state.counters["ies_bytes"] = static_cast<double>(ies_bytes);
  state.counters["obj_bytes"] = static_cast<double>(obj_bytes);
  state.counters["l3d_bytes"] = static_cast<double>(l3d_bytes);
  state.counters["triangles"] = [&] {
    double n = 0;
    for (const auto& m : scene.meshes) n += static_cast<double>(m.triangle_count());
    return n;
  }();
}
BENCHMARK(BM_GldfLedArray)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
