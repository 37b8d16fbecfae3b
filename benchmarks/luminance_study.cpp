// gonio_luminance_study: issue 33's luminance images of the samples from
// the UGR viewing directions (CIE 232:2019's γ 65° and 50°, C0 and C90),
// written as gonio simulate writes them (io/outputs/luminance_images.h:
// EXR, PNG) with CIE 232's figures per view.
//
// Usage: gonio_luminance_study OUT_DIR [--photons N (4e6)] [--threads T]
//          [--next-event off|on|auto (auto)] [--sample NAME]...
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <string>
#include <vector>

#include "io/model/gltf.h"
#include "io/outputs/luminance_images.h"
#include "samples/luminaires.h"
#include "sim/simulation.h"
#include "tools/run/simulation_outputs.h"

int main(int argc, char** argv) {
  using namespace gonio;
  namespace fs = std::filesystem;
  if (argc < 2) {
    std::fprintf(stderr, "usage: gonio_luminance_study OUT_DIR [--photons N] [--threads T] [--sample NAME]...\n");
    return 2;
  }
  const std::string out = argv[1];
  double photons = 4e6;
  int threads = 2;
  sim::NextEventMode mode = sim::NextEventMode::Auto;
  std::vector<std::string> names;
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--photons") photons = std::atof(argv[i + 1]);
    else if (a == "--threads") threads = std::atoi(argv[i + 1]);
    else if (a == "--next-event") mode = *sim::parse_next_event_mode(argv[i + 1]);
    else if (a == "--sample") names.push_back(argv[i + 1]);
  }
  if (names.empty()) names = {"bell", "downlight", "spotlight", "led-array"};
  const fs::path tmp = fs::temp_directory_path() / "gonio_luminance_study";
  fs::create_directories(tmp);
  fs::create_directories(out);
  if (Status st = samples::write_samples(tmp.string()); !st.ok()) return 1;
  for (const std::string& name : names) {
    auto scene = io::load_gltf((tmp / name / (name + ".gltf")).string(), nullptr);
    if (!scene.ok()) return 1;
    sim::SimulationSettings s;
    s.threads = threads;
    s.sampler = sim::SamplerKind::Sobol;
    s.next_event = mode;
    s.iterations = 4;
    s.photons_per_iteration = static_cast<std::uint64_t>(photons / 4);
    s.luminance.views = sim::ugr_luminance_views();
    const std::clock_t c0 = std::clock();
    auto run = sim::simulate(*scene, s);
    if (!run.ok()) {
      std::fprintf(stderr, "%s\n", run.error().message.c_str());
      return 1;
    }
    const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    const app::SimulatedOpening opening = app::simulated_opening(run->tracer(), run->scene(), s.seed);
    const io::LuminanceOutputs o = io::write_luminance_images(out, name, run->luminance_images(), opening.opening,
                                                              s.luminance.cone_deg);
    for (const Error& e : o.failures) std::fprintf(stderr, "%s\n", e.message.c_str());
    std::printf("%s: %.3g photons, %.1f CPU s, next-event %s; opening %s %.3f x %.3f m\n", name.c_str(),
                double(run->stats().photons), cpu, run->next_event().enabled ? "on" : "off",
                photometry::to_string(opening.opening.shape), opening.opening.length_m, opening.opening.width_m);
    std::printf("  %-12s %9s %9s %10s %10s %10s %11s %8s %8s %7s\n", "view", "pixels", "I cd", "A_p cm2", "L_s",
                "A_eff cm2", "L_eff", "k2", "dUGR", "max L");
    for (const auto& img : o.images) {
      const auto& g = img["cie232"];
      const auto num = [&](const char* k) { return g.contains(k) && g[k].is_number() ? g[k].get<double>() : std::nan(""); };
      std::printf("  C%-3.0f g%-6.0f %9d %9.2f %10.1f %10.0f %10.1f %11.0f %8.3f %8.2f %7.0f\n", img["c_deg"].get<double>(),
                  img["gamma_deg"].get<double>(), img["pixels"].get<int>(), img["intensity_cd"].get<double>(),
                  num("projected_area_m2") * 1e4, num("mean_luminance_cd_m2"), num("glare_area_m2") * 1e4,
                  num("glare_luminance_cd_m2"), num("k2"), num("delta_ugr"), img["max_cd_m2"].get<double>());
    }
    std::printf("  largest dUGR %s\n", o.cie232["delta_ugr"].dump().c_str());
    std::fflush(stdout);
  }
  return 0;
}
