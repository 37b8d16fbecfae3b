// gonio_cad_setup_study: setup time from a CAD model to the first photon,
// cold and cached, against the same triangles as a .glb, in one run
// (docs/cad.md, "Setup time").
//
// The model: a lens array of 16 glass spheres of different radii written by
// FreeCAD (tests/cad/make_parts.py with GONIO_CAD_LARGE=1), about 10⁶
// triangles at the default tessellation. Each path runs the phases gonio
// runs before tracing: load (STEP: the helper gonio-cad reading and meshing,
// or the cache entry; glb: io::load_gltf), the model checks
// (io::check_model, cold or from their cache), the tracer's setup
// (sim::Simulation::create) and one photon. Printed: wall seconds per phase,
// and CPU seconds of this process and its children (the helper) together,
// which a loaded machine distorts less.
//
// Usage: gonio_cad_setup_study [--parts DIR] [--tessellation DEG]
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "benchmarks/cad_parts.h"
#include "io/model/cad.h"
#include "io/model/gltf.h"
#include "io/model/model_check.h"
#include "io/support/file_io.h"
#include "io/support/process.h"
#include "photometry/format.h"
#include "samples/gltf_writer.h"
#include "sim/simulation.h"

#ifndef GONIO_SOURCE_DIR
#error "GONIO_SOURCE_DIR must name the repository"
#endif
#ifndef GONIO_BINARY_DIR
#error "GONIO_BINARY_DIR must name the build folder"
#endif

namespace {

namespace fs = std::filesystem;
using namespace gonio;

double cpu_s() {
  double total = 0.0;
  for (int who : {RUSAGE_SELF, RUSAGE_CHILDREN}) {
    rusage u{};
    getrusage(who, &u);
    total += static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
             1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
  }
  return total;
}

struct Clock {
  std::chrono::steady_clock::time_point wall = std::chrono::steady_clock::now();
  double cpu = cpu_s();
  std::pair<double, double> lap() {
    const auto now = std::chrono::steady_clock::now();
    const double c = cpu_s();
    const std::pair<double, double> out{std::chrono::duration<double>(now - wall).count(), c - cpu};
    wall = now;
    cpu = c;
    return out;
  }
};

struct Phases {
  std::pair<double, double> load, checks, tracer;
  std::size_t triangles = 0;
  double wall() const { return load.first + checks.first + tracer.first; }
  double cpu() const { return load.second + checks.second + tracer.second; }
};

[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "gonio_cad_setup_study: %s\n", what.c_str());
  std::exit(1);
}

void checks_and_first_photon(sim::SceneDesc scene, const std::string& cache, Clock& clock, Phases& p) {
  io::ModelCheckOptions o;
  o.cache_dir = cache;
  for (const Finding& f : io::check_model(scene, o))
    if (f.severity == Severity::Error) fail("the model checks refuse the model: " + f.message);
  p.checks = clock.lap();
  sim::SimulationSettings s;
  s.photons_per_iteration = 1;
  s.iterations = 1;
  Result<sim::Simulation> simulation = sim::Simulation::create(std::move(scene), s);
  if (!simulation.ok()) fail(to_string(simulation.error()));
  simulation->run_iteration();
  p.tracer = clock.lap();
}

Phases from_step(const fs::path& model, const io::CadLoadOptions& o, const std::string& check_cache) {
  Phases p;
  Clock clock;
  Result<sim::SceneDesc> scene = io::load_cad(model.string(), o, nullptr);
  if (!scene.ok()) fail(to_string(scene.error()));
  p.load = clock.lap();
  p.triangles = scene->unique_triangle_count();
  checks_and_first_photon(std::move(*scene), check_cache, clock, p);
  return p;
}

Phases from_glb(const fs::path& glb, const std::string& check_cache) {
  Phases p;
  Clock clock;
  Result<sim::SceneDesc> scene = io::load_gltf(glb.string(), nullptr);
  if (!scene.ok()) fail(to_string(scene.error()));
  p.load = clock.lap();
  p.triangles = scene->unique_triangle_count();
  checks_and_first_photon(std::move(*scene), check_cache, clock, p);
  return p;
}

// The scene's meshes as a .glb: one node each, the glass as extras, a point
// light with its flux.
void write_glb(const sim::SceneDesc& scene, const fs::path& path) {
  samples::GltfWriter w;
  const int glass = w.material({{"name", "glass"}, {"extras", {{"gonio", {{"dielectric", 1.0}, {"ior", 1.5}}}}}});
  for (const sim::Mesh& m : scene.meshes) w.node({{"mesh", w.mesh(m, glass, m.name)}, {"name", m.name}});
  w.use("KHR_lights_punctual");
  w.doc()["extensions"]["KHR_lights_punctual"]["lights"] = nlohmann::json::array(
      {{{"type", "point"}, {"intensity", 100.0}, {"extras", {{"gonio", {{"flux_lm", 1000.0}}}}}}});
  w.node({{"name", "light"},
          {"translation", {0.0225, 0.0225, 0.02}},
          {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  std::string bin;
  std::string json = w.finish("", bin);
  nlohmann::json doc = nlohmann::json::parse(json);
  doc["buffers"][0].erase("uri");
  json = doc.dump();
  while (json.size() % 4) json.push_back(' ');
  while (bin.size() % 4) bin.push_back('\0');
  std::string glb;
  auto u32 = [&](std::uint32_t v) { glb.append(reinterpret_cast<const char*>(&v), 4); };
  u32(0x46546C67);
  u32(2);
  u32(static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + bin.size()));
  u32(static_cast<std::uint32_t>(json.size()));
  u32(0x4E4F534A);
  glb += json;
  u32(static_cast<std::uint32_t>(bin.size()));
  u32(0x004E4942);
  glb += bin;
  if (!io::write_file_atomic(path.string(), glb).ok()) fail("cannot write " + path.string());
}

void print(const char* what, const Phases& p, double reference_cpu) {
  std::printf("| %s | %zu | %s / %s | %s / %s | %s / %s | %s / %s | %s |\n", what, p.triangles,
              format_fixed(p.load.first, 2).c_str(), format_fixed(p.load.second, 2).c_str(),
              format_fixed(p.checks.first, 2).c_str(), format_fixed(p.checks.second, 2).c_str(),
              format_fixed(p.tracer.first, 2).c_str(), format_fixed(p.tracer.second, 2).c_str(),
              format_fixed(p.wall(), 2).c_str(), format_fixed(p.cpu(), 2).c_str(),
              format_number(p.cpu() / reference_cpu, 3).c_str());
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  fs::path parts = fs::path(GONIO_BINARY_DIR) / "benchmarks" / "cad-parts-large";
  double tessellation = io::CadTessellation{}.angular_deflection_deg;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--parts") == 0 && i + 1 < argc) {
      parts = argv[++i];
    } else if (std::strcmp(argv[i], "--tessellation") == 0 && i + 1 < argc) {
      tessellation = std::atof(argv[++i]);
    } else {
      std::fprintf(stderr, "usage: gonio_cad_setup_study [--parts DIR] [--tessellation DEG]\n");
      return 2;
    }
  }
  bench::make_cad_parts(parts, "lens_array.step", true);
  io::ScratchDir scratch("gonio-cad-setup");
  const fs::path model = scratch.path() / "lens_array.step";
  fs::copy_file(parts / "lens_array.step", model);
  if (!io::write_file_atomic((scratch.path() / "lens_array.gonio.toml").string(),
                             "[materials.glass]\ndielectric = 1.0\nior = 1.5\n"
                             "[[parts]]\nmatch = \"*\"\nmaterial = \"glass\"\n"
                             "[[emitters]]\nposition = [22.5, 22.5, 20]\nflux_lm = 1000\n")
           .ok())
    fail("cannot write the sidecar");
  const std::string cad_cache = (scratch.path() / "cache-step").string();
  const std::string glb_cache = (scratch.path() / "cache-glb").string();
  io::CadLoadOptions o;
  o.tessellation.angular_deflection_deg = tessellation;
  o.cache_dir = cad_cache;

  std::printf("# lens_array.step, tessellation %s°; wall s / CPU s (this process and the helper)\n",
              format_number(tessellation).c_str());
  std::printf("| path | triangles | load | checks | tracer setup + 1 photon | total | CPU ÷ glb cold |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  const Phases step_cold = from_step(model, o, cad_cache);
  const Phases step_cached = from_step(model, o, cad_cache);
  // The same triangles as a glb.
  Result<sim::SceneDesc> scene = io::load_cad(model.string(), o, nullptr);
  if (!scene.ok()) fail(to_string(scene.error()));
  const fs::path glb = scratch.path() / "lens_array.glb";
  write_glb(*scene, glb);
  const Phases glb_cold = from_glb(glb, glb_cache);
  const Phases glb_cached = from_glb(glb, glb_cache);
  print("STEP, cold", step_cold, glb_cold.cpu());
  print("STEP, cached", step_cached, glb_cold.cpu());
  print("glb, cold", glb_cold, glb_cold.cpu());
  print("glb, checks cached", glb_cached, glb_cold.cpu());
  return 0;
}
