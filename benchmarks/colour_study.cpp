// The measurements issue 24 asks for (run on a quiet machine; figures in the
// closing note say under what load they were taken):
//
//  1. Photons per second of each sample luminaire with a spectrum (every
//     emitter a 3000 K blackbody) against the same model without one, in
//     the same run, interleaved.
//  2. Colour over angle of a white-LED luminaire whose phosphor LED changes
//     colour with angle — bare, behind an opal diffuser, behind a clear
//     polycarbonate ball lens (dispersive: Abbe number 30): Δu′v′ max
//     (sim/detectors/colour_over_angle.h) and how many photons it takes to know it
//     within 0.001 (every one of three seeds within 0.001 of a 2²³-photon
//     reference).
//
// The LED's spectrum is built from the corpus' OSRAM LERTDUW S2WP white-chip
// spectra (../shared/corpus/spectra: the blue chip's part and the
// phosphor's, each normalised to unit Y here) mixed with a blue share of Y
// falling from 0.085 on the axis to 0.052 at 90° — the yellow ring of
// phosphor LEDs (the study prints the CCT this gives at each angle).
//
// Usage: gonio_colour_study [CORPUS_DIR] [--quick] [--speed (part 1 only)]
//        [--lens --reference-log2=K (the lens alone, a 2^K-photon reference, runs of 2^(K-2) and 2^(K-1))]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "io/model/gltf.h"
#include "photometry/colour.h"
#include "samples/luminaires.h"
#include "sim/detectors/colour_over_angle.h"
#include "sim/shapes.h"
#include "sim/simulation.h"

namespace fs = std::filesystem;
using namespace gonio;

namespace {

photometry::SampledSpectrum read_two_columns(const fs::path& path) {
  std::ifstream in(path);
  photometry::SampledSpectrum s;
  double w = 0.0, v = 0.0;
  while (in >> w >> v) {
    s.wavelengths_nm.push_back(w);
    s.values.push_back(v);
  }
  return s;
}

sim::SimulationSettings settings(std::uint64_t photons, std::uint64_t seed) {
  sim::SimulationSettings s;
  s.photons_per_iteration = photons;
  s.iterations = 1;
  s.seed = seed;
  s.threads = 2;
  s.face_size = 128;
  return s;
}

double photons_per_s(const sim::SceneDesc& scene, std::uint64_t photons) {
  auto sim = sim::simulate(scene, settings(photons, 1));
  if (!sim.ok()) {
    std::fprintf(stderr, "%s\n", sim.error().message.c_str());
    std::exit(1);
  }
  return sim->stats().photons_per_s();
}

// The white LED's spectrum at a blue share w of Y.
photometry::SampledSpectrum led_mix(const photometry::SampledSpectrum& blue,
                                    const photometry::SampledSpectrum& yellow, double w) {
  const double yb = photometry::tristimulus(blue).Y, yy = photometry::tristimulus(yellow).Y;
  photometry::SampledSpectrum s;
  for (double nm = 390.0; nm <= 810.0; nm += 1.0) {
    s.wavelengths_nm.push_back(nm);
    const double b = nm <= 510.0 ? blue.at(nm) : 0.0;
    const double y = nm > 510.0 || nm == 510.0 ? yellow.at(nm) : 0.0;
    s.values.push_back(w * b / yb + (1.0 - w) * (nm == 510.0 ? 0.0 : y) / yy);
  }
  return s;
}

enum class Optic { Bare, Opal, Lens };

sim::SceneDesc led_luminaire(const sim::EmitterSpectrum& spectrum, Optic optic) {
  sim::SceneDesc s;
  s.name = optic == Optic::Bare ? "bare LED" : optic == Optic::Opal ? "LED + opal" : "LED + PC ball lens";
  sim::Material package;
  package.name = "package";  // black
  s.materials.push_back(package);
  sim::Mesh chip = sim::disc(0.0015, 32);
  sim::flip(chip);  // faces −Y, the nadir
  chip.material = 0;
  s.meshes.push_back(chip);
  if (optic == Optic::Opal) {
    sim::Material opal;
    opal.name = "opal";
    opal.diffuse_transmit = 0.55;
    opal.diffuse_reflect = 0.40;
    sim::Material white;
    white.name = "white";
    white.diffuse_reflect = 0.9;
    s.materials.push_back(opal);
    s.materials.push_back(white);
    sim::Mesh diffuser = sim::disc(0.04, 96);
    sim::transform(diffuser, sim::translation({0.0, -0.015, 0.0}));
    diffuser.material = 1;
    sim::Mesh back = sim::disc(0.04, 96);
    sim::flip(back);
    sim::transform(back, sim::translation({0.0, 0.0005, 0.0}));
    back.material = 2;
    s.meshes.push_back(diffuser);
    s.meshes.push_back(back);
  } else if (optic == Optic::Lens) {
    sim::Material pc;
    pc.name = "polycarbonate";
    pc.dielectric = 1.0;
    pc.ior = 1.585;
    pc.abbe_number = 30.0;
    s.materials.push_back(pc);
    sim::Mesh ball = sim::sphere(0.008, 128, 64);
    sim::transform(ball, sim::translation({0.0, -0.0095, 0.0}));
    ball.material = 1;
    s.meshes.push_back(ball);
  }
  sim::Emitter e;
  e.kind = sim::Emitter::Kind::Area;
  e.name = "white LED";
  e.mesh = 0;
  e.flux_lm = 100.0;
  e.spectrum = spectrum;
  s.emitters.push_back(e);
  return s;
}

double delta_uv_max(const sim::SceneDesc& scene, std::uint64_t photons, std::uint64_t seed,
                    const sim::Resampler& r, double* rate) {
  auto sim = sim::simulate(scene, settings(photons, seed));
  if (!sim.ok()) {
    std::fprintf(stderr, "%s\n", sim.error().message.c_str());
    std::exit(1);
  }
  if (rate) *rate = sim->stats().photons_per_s();
  return sim::colour_over_angle(r, sim->far_field(), sim->colour_far_field()).delta_uv_max;
}

}  // namespace

int main(int argc, char** argv) {
  fs::path corpus = fs::path(GONIO_SOURCE_DIR) / ".." / "shared" / "corpus";
  bool quick = false, speed_only = false, lens_only = false;
  int reference_log2 = 23;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") quick = true;
    else if (a == "--speed") speed_only = true;
    else if (a == "--lens") lens_only = true;
    else if (a.rfind("--reference-log2=", 0) == 0) reference_log2 = std::stoi(a.substr(17));
    else corpus = argv[i];
  }
  std::printf("load: %s\n", [] {
    std::ifstream f("/proc/loadavg");
    std::string l;
    std::getline(f, l);
    return l;
  }().c_str());

  // 1. Photons/s with and without a spectrum on the samples.
  const fs::path tmp = fs::temp_directory_path() / "gonio_colour_study";
  fs::create_directories(tmp);
  if (Status st = samples::write_samples(tmp.string()); !st.ok()) {
    std::fprintf(stderr, "%s\n", st.error().message.c_str());
    return 1;
  }
  if (!lens_only) std::printf("\n1. photons/s, 2 threads, 10^6 photons a run, three interleaved rounds (median)\n");
  if (!lens_only) std::printf("%-10s %12s %12s %7s\n", "sample", "grey", "spectral", "ratio");
  for (const char* name : {"bell", "downlight", "spotlight", "led-array"}) {
    if (lens_only) break;
    auto scene = io::load_gltf((tmp / name / (std::string(name) + ".gltf")).string(), nullptr);
    if (!scene.ok()) {
      std::fprintf(stderr, "%s\n", scene.error().message.c_str());
      return 1;
    }
    sim::SceneDesc spectral = *scene;
    for (sim::Emitter& e : spectral.emitters)
      e.spectrum.over_gamma = {{0.0, photometry::blackbody_spectrum(3000.0)}};
    std::vector<double> g, s, ratio;
    for (int round = 0; round < 3; ++round) {
      g.push_back(photons_per_s(*scene, quick ? 200000 : 1000000));
      s.push_back(photons_per_s(spectral, quick ? 200000 : 1000000));
      ratio.push_back(s.back() / g.back());
    }
    std::sort(g.begin(), g.end());
    std::sort(s.begin(), s.end());
    std::sort(ratio.begin(), ratio.end());
    std::printf("%-10s %12.0f %12.0f %7.3f\n", name, g[1], s[1], ratio[1]);
  }

  if (speed_only) return 0;

  // 2. Colour over angle of a white LED, bare, behind opal and behind a lens.
  const auto blue = read_two_columns(corpus / "spectra" / "LERTDUW_S2WP_binBQ_white-blue_20110706_spectrum.txt");
  const auto yellow = read_two_columns(corpus / "spectra" / "LERTDUW_S2WP_binBQ_white-yellow_20110706_spectrum.txt");
  if (blue.empty() || yellow.empty()) {
    std::fprintf(stderr, "missing: the corpus spectra under %s\n", corpus.string().c_str());
    return 1;
  }
  sim::EmitterSpectrum led;
  for (const auto& [gamma, w] : std::vector<std::pair<double, double>>{
           {0.0, 0.085}, {30.0, 0.082}, {60.0, 0.072}, {80.0, 0.060}, {90.0, 0.052}})
    led.over_gamma.push_back({gamma, led_mix(blue, yellow, w)});
  std::printf("\n2. the LED's own spectrum over gamma:\n");
  for (const auto& a : led.over_gamma) {
    const photometry::CctDuv cd = photometry::cct_duv(photometry::tristimulus(a.spectrum));
    std::printf("   gamma %4.0f deg: CCT %6.0f K, Duv %+.4f\n", a.gamma_deg, cd.cct_k, cd.duv);
  }
  const sim::CGammaGrid grid{5.0, 2.5};
  const sim::Resampler resampler(128, photometry::PhotometricFrame{}, grid);
  const std::uint64_t reference_n = quick ? (1u << 20) : (std::uint64_t{1} << reference_log2);
  std::vector<std::uint64_t> ns;
  for (std::uint64_t n = lens_only ? reference_n / 4 : (1u << 17); n <= reference_n / 2; n *= 2) ns.push_back(n);
  for (Optic optic : {Optic::Bare, Optic::Opal, Optic::Lens}) {
    if (lens_only && optic != Optic::Lens) continue;
    const sim::SceneDesc scene = led_luminaire(led, optic);
    double rate = 0.0;
    const auto t0 = std::chrono::steady_clock::now();
    const double ref = delta_uv_max(scene, reference_n, 1000, resampler, &rate);
    auto reference = sim::simulate(scene, settings(reference_n, 1000));
    const sim::ColourOverAngle c =
        sim::colour_over_angle(resampler, reference->far_field(), reference->colour_far_field());
    std::printf("\n%s: reference %llu photons (%.0f photons/s): delta_uv_max %.4f over %zu bins; "
                "whole luminaire u'v' (%.4f, %.4f), CCT %.0f K, Duv %+.4f\n",
                scene.name.c_str(), static_cast<unsigned long long>(reference_n), rate, ref, c.bins_counted,
                c.uv.u_prime, c.uv.v_prime, c.cct.cct_k, c.cct.duv);
    for (const sim::ColourPlane& p : c.planes) {
      if (p.c_deg != 0.0) continue;
      std::printf("   C0: ");
      for (const sim::ColourAtGamma& a : p.points)
        if (std::fmod(a.gamma_deg, 15.0) == 0.0 && a.gamma_deg <= 90.0)
          std::printf("g%.0f %.0fK/%.0fcd  ", a.gamma_deg, a.cct.cct_k, a.intensity_cd);
      std::printf("\n");
    }
    std::uint64_t known = 0;
    for (std::uint64_t n : ns) {
      double worst = 0.0, sum = 0.0;
      for (std::uint64_t seed : {1, 2, 3}) {
        const double d = delta_uv_max(scene, n, seed, resampler, nullptr);
        worst = std::max(worst, std::abs(d - ref));
        sum += d;
      }
      std::printf("   %9llu photons: delta_uv_max mean %.4f, worst |error| %.4f\n",
                  static_cast<unsigned long long>(n), sum / 3.0, worst);
      if (!known && worst <= 0.001) known = n;
    }
    std::printf("   within 0.001 (3 seeds) from %s photons; %.0f s\n",
                known ? std::to_string(known).c_str() : "more than the largest run's",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return 0;
}
