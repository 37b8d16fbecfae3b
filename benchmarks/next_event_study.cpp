// gonio_next_event_study: issue 33's measurement of next-event estimation
// (sim/tracer/next_event.h) against today's default on the four samples.
//
// For each sample: a pseudo-random reference run of 2^R photons (seed
// 1000), then the default sampler (Owen-scrambled Sobol', 4 replicates,
// seed 1) traced progressively with next-event estimation off, on, and
// auto, its photon count growing by √2 per step; after each step the RMS
// candela error of the 5° × 2.5° table against the reference (its own noise
// taken out: sim/convergence.h, as `gonio bench`) and the run's own error
// estimate (the replicates', tools/run/progressive_run.h). The time to the
// target (1 %) is interpolated log-log between the steps around it, in CPU
// seconds of the process (user + sys, every thread; the machine is shared,
// CPU time is what the runs cost) spent tracing, and separately the setup
// (Simulation::create: BVH, emission tables and the next-event pilot).
// estimate ÷ measured is taken at the step nearest the target.
//
// Besides the samples, two held-out closed forms whose reference is exact
// (no reference run): "opal-sphere", a 1000 lm point lamp in an opal
// sphere (diffuse transmission 0.6, reflection 0.3): I = Φ·0.6/0.7/4π in
// every direction; "lambert-disc", a black Lambertian disc of 1000 lm
// facing down: I = (Φ/π) cos γ below it, nothing above.
//
// Usage: gonio_next_event_study [--reference-log2 R (24)] [--threads T (2)]
//          [--connections M (16)] [--target PCT (1)] [--max-log2 L (25)]
//          [--sample NAME]...   (NAME: a sample, opal-sphere, lambert-disc or
//          led-housing: the peer eulumdat-goniosim's LED in a white tube,
//          samples/peer_scenes.h; or bell-volume: the bell with its shade a
//          closed 3 mm shell of "opal PMMA 3 mm", the materials study's (b);
//          neither among the defaults)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "io/model/gltf.h"
#include "samples/luminaires.h"
#include "samples/peer_scenes.h"
#include "sim/convergence.h"
#include "sim/detectors/resample.h"
#include "sim/shapes.h"
#include "sim/simulation.h"
#include "tools/run/progressive_run.h"

namespace {

using namespace gonio;
namespace fs = std::filesystem;

double cpu_s() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

std::vector<double> intensities(const sim::FarField& f) {
  std::vector<double> out(f.texel_count());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = f.intensity_cd(i);
  return out;
}

struct Point {
  std::uint64_t photons;
  double cpu_s, rms_pct, estimate_pct;
};

struct Series {
  std::string mode;
  bool enabled = false;
  double covered_share = 0.0, multi_share = 0.0;
  std::vector<Point> points;
  double setup_cpu_s = 0.0;
  double photons_to_target = NAN, cpu_to_target = NAN, estimate_ratio = NAN;
};

// The closed forms above: the scene and its exact far field.
bool closed_form(const std::string& name, int face_size, sim::SceneDesc* scene, sim::FarField* exact) {
  constexpr double kPi = 3.14159265358979323846;
  const sim::CubeMapGrid grid(face_size);
  std::vector<double> flux(grid.texel_count());
  if (name == "opal-sphere") {
    sim::Material opal{"opal", 0.3, 0.6, 0.0};
    scene->materials = {opal};
    scene->meshes = {sim::sphere(0.1, 96, 48)};
    sim::Emitter e;
    e.flux_lm = 1000.0;
    scene->emitters = {e};
    const double i = 1000.0 * 0.6 / 0.7 / (4.0 * kPi);
    for (std::size_t t = 0; t < flux.size(); ++t) flux[t] = i * grid.texel_solid_angle(t);
  } else if (name == "lambert-disc") {
    sim::Material black;
    black.name = "black";
    scene->materials = {black};
    sim::Mesh d = sim::disc(0.05, 256);
    sim::flip(d);
    scene->meshes = {d};
    sim::Emitter e;
    e.kind = sim::Emitter::Kind::Area;
    e.flux_lm = 1000.0;
    scene->emitters = {e};
    // ∫ over each texel of (Φ/π) max(0, −y): sub-sampled 16 × 16.
    const int n = face_size;
    for (int face = 0; face < 6; ++face)
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
          double sum = 0.0;
          for (int j = 0; j < 16; ++j)
            for (int k = 0; k < 16; ++k) {
              const double a0 = -1.0 + 2.0 * (x + k / 16.0) / n, a1 = a0 + 2.0 / (16.0 * n);
              const double b0 = -1.0 + 2.0 * (y + j / 16.0) / n, b1 = b0 + 2.0 / (16.0 * n);
              const gonio::Vec3 d3 = normalize(sim::CubeMapGrid::direction(face, 0.5 * (a0 + a1), 0.5 * (b0 + b1)));
              sum += 1000.0 / kPi * std::max(0.0, -d3.y) * sim::CubeMapGrid::solid_angle(a0, b0, a1, b1);
            }
          flux[grid.index(face, x, y)] = sum;
        }
  } else {
    return false;
  }
  // Photons so many that the reference's noise term vanishes.
  *exact = sim::FarField(face_size, std::move(flux), std::vector<std::uint64_t>(grid.texel_count(), std::uint64_t{1} << 50));
  return true;
}

void finish(Series& s, double target) {
  for (std::size_t k = 1; k < s.points.size(); ++k) {
    const Point &a = s.points[k - 1], &b = s.points[k];
    if (!(a.rms_pct > target && b.rms_pct <= target)) continue;
    const double t = std::log(a.rms_pct / target) / std::log(a.rms_pct / b.rms_pct);
    s.photons_to_target = std::exp(std::log(double(a.photons)) + t * std::log(double(b.photons) / double(a.photons)));
    s.cpu_to_target = std::exp(std::log(a.cpu_s) + t * std::log(b.cpu_s / a.cpu_s));
    const Point& near = t < 0.5 ? a : b;
    s.estimate_ratio = near.estimate_pct / near.rms_pct;
    return;
  }
}

}  // namespace

int main(int argc, char** argv) {
  int reference_log2 = 24, threads = 2, connections = sim::kDefaultConnections, max_log2 = 25;
  double target = 1.0;
  std::vector<std::string> names;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--reference-log2") reference_log2 = std::atoi(argv[i + 1]);
    else if (a == "--threads") threads = std::atoi(argv[i + 1]);
    else if (a == "--connections") connections = std::atoi(argv[i + 1]);
    else if (a == "--target") target = std::atof(argv[i + 1]);
    else if (a == "--max-log2") max_log2 = std::atoi(argv[i + 1]);
    else if (a == "--sample") names.push_back(argv[i + 1]);
  }
  if (names.empty()) names = {"bell", "downlight", "spotlight", "led-array", "opal-sphere", "lambert-disc"};
  std::printf("load: %s\n", [] {
    std::ifstream f("/proc/loadavg");
    std::string l;
    std::getline(f, l);
    return l;
  }().c_str());
  const fs::path tmp = fs::temp_directory_path() / "gonio_next_event_study";
  fs::create_directories(tmp);
  Status st = samples::write_samples(tmp.string());
  if (st.ok()) st = samples::write_peer_samples(tmp.string());
  if (!st.ok()) {
    std::fprintf(stderr, "%s\n", st.error().message.c_str());
    return 1;
  }
  const sim::CGammaGrid grid{5.0, 2.5};
  const int face_size = sim::face_size_for(grid);
  std::printf("reference 2^%d random photons (seed 1000); series Sobol' x4 replicates, seed 1, %d threads, M = %d, "
              "target %.3g %% RMS (5 x 2.5 deg table)\n",
              reference_log2, threads, connections, target);
  std::printf("%-10s %-5s %4s %7s %7s %12s %12s %9s %9s %10s %11s\n", "sample", "mode", "on", "share", "multi", "photons",
              "trace CPU s", "est/meas", "ratio", "setup CPU", "with setup");
  for (const std::string& name : names) {
    sim::SceneDesc closed;
    sim::FarField exact(face_size);
    const bool is_closed = closed_form(name, face_size, &closed, &exact);
    // "bell-volume": the bell with its shade a closed 3 mm shell of "opal
    // PMMA 3 mm" (the materials study's (b), samples::bell_with_volume_shade).
    const bool volume_bell = name == "bell-volume";
    const std::string file = volume_bell ? "bell" : name;
    auto scene = is_closed ? Result<sim::SceneDesc>(closed) : io::load_gltf((tmp / file / (file + ".gltf")).string(), nullptr);
    if (volume_bell && scene.ok()) {
      std::optional<sim::SceneDesc> shell = samples::bell_with_volume_shade(*scene);
      if (!shell) {
        std::fprintf(stderr, "no shade mesh in the bell sample\n");
        return 1;
      }
      scene = std::move(*shell);
    }
    if (!scene.ok()) {
      std::fprintf(stderr, "%s\n", scene.error().message.c_str());
      return 1;
    }
    auto resampler = std::make_shared<const sim::Resampler>(face_size, scene->frame, grid);
    sim::FarField reference_field = exact;
    if (!is_closed) {
      sim::SimulationSettings rs;
      rs.threads = threads;
      rs.face_size = face_size;
      rs.seed = 1000;
      rs.sampler = sim::SamplerKind::Random;
      rs.iterations = std::max(1, 1 << std::max(0, reference_log2 - 22));
      rs.photons_per_iteration = (std::uint64_t{1} << reference_log2) / static_cast<std::uint64_t>(rs.iterations);
      auto reference_run = sim::simulate(*scene, rs);
      if (!reference_run.ok()) {
        std::fprintf(stderr, "%s\n", reference_run.error().message.c_str());
        return 1;
      }
      reference_field = reference_run->far_field();
    }
    auto reference = sim::ConvergenceReference::create(reference_field, resampler);
    if (!reference.ok()) return 1;
    std::vector<Series> all;
    for (sim::NextEventMode mode : {sim::NextEventMode::Off, sim::NextEventMode::On, sim::NextEventMode::Auto}) {
      Series s;
      s.mode = sim::to_string(mode);
      sim::SimulationSettings ss;
      ss.threads = threads;
      ss.face_size = face_size;
      ss.seed = 1;
      ss.sampler = sim::SamplerKind::Sobol;
      ss.next_event = mode;
      ss.next_event_connections = connections;
      ss.iterations = 1 << 20;
      ss.photons_per_iteration = 4096;
      const double t0 = cpu_s();
      auto sim = sim::Simulation::create(*scene, ss);
      if (!sim.ok()) {
        std::fprintf(stderr, "%s\n", sim.error().message.c_str());
        return 1;
      }
      s.setup_cpu_s = cpu_s() - t0;
      s.enabled = sim->next_event().enabled;
      s.covered_share = sim->next_event().pilot_covered_share;
      s.multi_share = sim->next_event().pilot_multi_share;
      std::uint64_t done = 0;
      for (double n = 2048.0; n <= std::ldexp(1.0, max_log2); n *= std::sqrt(2.0)) {
        const auto want = static_cast<std::uint64_t>(n / 512.0 + 0.5) * 512;
        while (done < want) {
          const std::uint64_t step = std::min<std::uint64_t>(want - done, std::uint64_t{1} << 22);
          sim->run_iteration(step);
          done += step;
        }
        const double cpu = cpu_s() - t0 - s.setup_cpu_s;
        const sim::FarField f = sim->far_field();
        const double rms = reference->table_error(intensities(f)).rms_pct;
        const double est = app::estimated_rms_error_pct(*sim, *resampler);
        s.points.push_back({done, cpu, rms, est});
        if (rms < 0.6 * target) break;
      }
      finish(s, target);
      all.push_back(s);
    }
    for (const Series& s : all)
      std::printf("%-10s %-5s %4s %7.3f %7.3f %12.4g %12.4g %9.3f %9.3f %10.3f %11.3f\n", name.c_str(), s.mode.c_str(),
                  s.enabled ? "yes" : "no", s.covered_share, s.multi_share, s.photons_to_target, s.cpu_to_target, s.estimate_ratio,
                  s.cpu_to_target / all[0].cpu_to_target, s.setup_cpu_s,
                  (s.cpu_to_target + s.setup_cpu_s) / (all[0].cpu_to_target + all[0].setup_cpu_s));
    std::fflush(stdout);
    // The series themselves, for the docs' charts.
    for (const Series& s : all)
      for (const Point& p : s.points)
        std::fprintf(stderr, "%s,%s,%llu,%.6g,%.6g,%.6g\n", name.c_str(), s.mode.c_str(),
                     static_cast<unsigned long long>(p.photons), p.cpu_s, p.rms_pct, p.estimate_pct);
  }
  return 0;
}
