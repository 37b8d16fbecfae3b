// gonio_cad_tessellation_study: the measurement behind the CAD reader's
// default tessellation (io/model/cad.h, docs/cad.md).
//
// Two optics whose far field is known, written by FreeCAD
// (tests/cad/make_parts.py) and read through gonio's own CAD path (the
// helper gonio-cad, OpenCASCADE's BRepMesh), meshed at angular deflections
// from 16° down to 0.25°, each with and without shading normals from the
// exact surface:
//
//   reflector  an ideal paraboloid (focal length 10 mm, lamp hole r = 4 mm,
//              aperture r = 30 mm, mirror reflectance 1) with an isotropic
//              point source at its focus. Every reflected ray leaves along
//              the axis, so the nadir cap of the C-γ grid (γ < Δγ/2) holds,
//              in closed form, I₀ = Φ (f_r + Ω_cap/4π) / Ω_cap with
//              f_r = (cos φ_hole − cos φ_aper)/2 the share of the sphere the
//              mirror subtends from the focus. Error: |I(0) − I₀| / I₀.
//   ball lens  a sphere of r = 5 mm, n = 1.5, with an isotropic point source
//              on its axis at the paraxial focus (7.5 mm from the centre,
//              f = nD/4(n − 1)): a beam along the axis with the ball's
//              spherical aberration. No closed form for the whole beam:
//              error is the RMS over γ ≤ 30° of I − I_ref, relative to
//              I_ref's peak, where I_ref is a finer mesh (--reference,
//              default 0.5°) with exact normals and 4× the photons; the
//              same mesh traced with another seed and 1× gives the floor
//              (the row "noise").
//
// For each it prints the triangles, the setup seconds (the helper's reading
// and meshing, and the tracer's setup), and the error, as the table
// docs/cad.md shows. The grid is the default 5° × 2.5°.
//
// Usage: gonio_cad_tessellation_study [--photons N] [--parts DIR] [--reference DEG] [--only reflector|lens]
//   N: photons per run (default 2²¹); DIR: the parts (default: made here
//   with freecadcmd into build/benchmarks/cad-parts).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "benchmarks/cad_parts.h"
#include "io/model/cad.h"
#include "io/support/file_io.h"
#include "photometry/format.h"
#include "sim/detectors/resample.h"
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

constexpr double kPi = std::numbers::pi;

struct Optic {
  const char* name;
  const char* file;
  const char* sidecar;
};

const Optic kReflector{"reflector", "reflector.step", R"(
[materials.mirror]
mirror = 1.0
[[parts]]
match = "*"
material = "mirror"
[[emitters]]
position = [0, 0, 0]
flux_lm = 1000
)"};

const Optic kBall{"ball lens", "ball_lens.step", R"(
[materials.glass]
dielectric = 1.0
ior = 1.5
[[parts]]
match = "*"
material = "glass"
[[emitters]]
position = [0, 0, 7.5]
flux_lm = 1000
)"};

struct Run {
  std::size_t triangles = 0;
  double tessellate_s = 0.0, tracer_setup_s = 0.0;
  sim::BinnedField field;
};

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

Run run(const fs::path& model, double angular_deg, bool exact, std::uint64_t photons, std::uint64_t seed) {
  io::CadLoadOptions o;
  o.tessellation.angular_deflection_deg = angular_deg;
  o.tessellation.chordal_relative = 0.5;  // the angle in charge: the study is of δ
  o.tessellation.exact_normals = exact;
  io::CadLoadInfo info;
  Result<sim::SceneDesc> scene = io::load_cad(model.string(), o, nullptr, &info);
  if (!scene.ok()) {
    std::fprintf(stderr, "%s\n", to_string(scene.error()).c_str());
    std::exit(1);
  }
  Run r;
  r.triangles = info.unique_triangles;
  r.tessellate_s = info.tessellate_s;
  sim::SimulationSettings s;
  s.photons_per_iteration = photons;
  s.iterations = 1;
  s.seed = seed;
  const photometry::PhotometricFrame frame = scene->frame;
  const auto t0 = std::chrono::steady_clock::now();
  Result<sim::Simulation> simulation = sim::Simulation::create(std::move(*scene), s);
  if (!simulation.ok()) {
    std::fprintf(stderr, "%s\n", to_string(simulation.error()).c_str());
    std::exit(1);
  }
  r.tracer_setup_s = seconds_since(t0);
  simulation->run_iteration();
  sim::CGammaGrid grid;
  const sim::Resampler resampler(sim::face_size_for(grid), frame, grid);
  r.field = resampler.bin(simulation->far_field());
  return r;
}

// The nadir cap's closed form for the paraboloid (see above).
double reflector_nadir_cd(double flux_lm, const sim::CGammaGrid& grid) {
  const double f = 10.0, r0 = 4.0, r1 = 30.0;
  auto polar = [&](double r) { return std::atan2(r, f - r * r / (4 * f)); };  // from +Z, at the focus
  const double share = (std::cos(polar(r0)) - std::cos(polar(r1))) / 2.0;
  const double cap = 2 * kPi * (1 - std::cos(grid.gamma_step_deg / 2 * kPi / 180));
  return flux_lm * (share + cap / (4 * kPi)) / cap;
}

// RMS over γ ≤ 30° (every C-plane) of a − b, over b's peak there.
double beam_rms(const sim::BinnedField& a, const sim::BinnedField& b) {
  const sim::CGammaGrid& g = a.grid;
  double sum = 0.0, peak = 0.0;
  int n = 0;
  for (int j = 0; j * g.gamma_step_deg <= 30.0; ++j)
    for (int i = 0; i < g.c_count(); ++i) {
      const std::size_t bin = g.bin(i, j);
      const double d = a.intensity_cd(bin) - b.intensity_cd(bin);
      sum += d * d;
      peak = std::max(peak, b.intensity_cd(bin));
      ++n;
    }
  return std::sqrt(sum / n) / peak;
}

}  // namespace

int main(int argc, char** argv) {
  std::uint64_t photons = std::uint64_t{1} << 21;
  fs::path parts = fs::path(GONIO_BINARY_DIR) / "benchmarks" / "cad-parts";
  double reference_deg = 0.5;
  std::string only;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--photons") == 0 && i + 1 < argc) {
      photons = std::strtoull(argv[++i], nullptr, 10);
    } else if (std::strcmp(argv[i], "--reference") == 0 && i + 1 < argc) {
      reference_deg = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--only") == 0 && i + 1 < argc) {
      only = argv[++i];
    } else if (std::strcmp(argv[i], "--parts") == 0 && i + 1 < argc) {
      parts = argv[++i];
    } else {
      std::fprintf(stderr, "usage: gonio_cad_tessellation_study [--photons N] [--parts DIR] [--reference DEG] "
                           "[--only reflector|lens]\n");
      return 2;
    }
  }
  bench::make_cad_parts(parts, "reflector.step", false);
  io::ScratchDir scratch("gonio-cad-study");
  const std::vector<double> angles = {16, 8, 4, 2, 1};
  std::printf("# %llu photons per run, grid 5° x 2.5°; setup = meshing (gonio-cad) + tracer setup [s]\n",
              static_cast<unsigned long long>(photons));
  std::printf("| optic | angular deflection | normals | triangles | setup s | error |\n");
  std::printf("|---|---|---|---|---|---|\n");
  for (const Optic* optic : {&kReflector, &kBall}) {
    if ((only == "reflector" && optic != &kReflector) || (only == "lens" && optic != &kBall)) continue;
    const fs::path model = scratch.path() / optic->file;
    fs::copy_file(parts / optic->file, model, fs::copy_options::overwrite_existing);
    const std::string stem = fs::path(optic->file).stem().string();
    if (!io::write_file_atomic((scratch.path() / (stem + ".gonio.toml")).string(), optic->sidecar).ok()) return 1;

    const bool lens = optic == &kBall;
    sim::BinnedField reference;
    if (lens) {
      reference = run(model, reference_deg, true, photons * 4, 99).field;
      const Run again = run(model, reference_deg, true, photons, 98);
      std::printf("| %s | %s° (reference, 4× photons) | exact | – | – | noise %s |\n", optic->name,
                  format_number(reference_deg).c_str(), format_number(beam_rms(again.field, reference), 3).c_str());
    }
    for (bool exact : {false, true})
      for (double deg : angles) {
        if (lens && deg <= reference_deg) continue;
        const Run r = run(model, deg, exact, photons, 1);
        double error = 0.0;
        if (lens) {
          error = beam_rms(r.field, reference);
        } else {
          const double expected = reflector_nadir_cd(1000.0, r.field.grid);
          error = std::abs(r.field.intensity_cd(0) - expected) / expected;
        }
        std::printf("| %s | %s° | %s | %zu | %s | %s |\n", optic->name, format_number(deg).c_str(),
                    exact ? "exact" : "facets", r.triangles,
                    format_fixed(r.tessellate_s + r.tracer_setup_s, 2).c_str(), format_number(error, 3).c_str());
        std::fflush(stdout);
      }
  }
  return 0;
}
