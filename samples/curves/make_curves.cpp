// Writes the measured-style sample curves of samples/curves/ (see its
// README.md): a downlight and an asymmetric wall-washer, each as IES
// LM-63-2019 and EULUMDAT, through Gonio's own writers.
//
//   gonio_make_curves DIR
//
// The curves are formulas of our own, rounded the way measured files are
// (0.1 cd), so that the output is the same bytes on every run and machine.
// They are synthetic and say so in their keywords: nothing here was measured.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <string>

#include "io/photometric/photometric_file.h"

namespace {

using gonio::photometry::Distribution;
using gonio::photometry::LampSet;
using gonio::photometry::OpeningShape;
using gonio::photometry::Symmetry;

constexpr double kDeg = std::numbers::pi / 180.0;

double round_to_tenth(double cd) { return std::round(cd * 10.0) / 10.0; }

void common_keywords(Distribution& d, const std::string& catalogue, const std::string& name) {
  d.keywords = {
      {"TEST", "GS-" + catalogue},
      {"TESTLAB", "none: synthetic sample curve, not a measurement"},
      {"ISSUEDATE", "2025-01-31"},
      {"MANUFAC", "Gonio sample luminaires"},
      {"LUMCAT", catalogue},
      {"LUMINAIRE", name},
      {"FILEGENINFO", "Synthetic curve written by samples/curves/make_curves.cpp (Gonio)"},
  };
}

// A recessed LED downlight with a faceted reflector: a cos⁴ beam over a
// little diffuse spill, cut off at 85°; rotationally symmetric. Beam angle
// 67.5°, field angle 117.5°. 3000 lm module, 24.5 W; the reflector passes
// about 83 % of it.
Distribution downlight() {
  Distribution d;
  d.symmetry = Symmetry::Rotational;
  d.horizontal_deg = {0.0};
  for (int i = 0; i <= 36; ++i) d.vertical_deg.push_back(2.5 * i);
  for (double g : d.vertical_deg) {
    const double c = std::cos(g * kDeg);
    const double core = 1700.0 * std::pow(c, 4);
    const double spill = 110.0 * c;
    const double cutoff = g < 85.0 ? 1.0 : std::max(0.0, (90.0 - g) / 5.0);
    d.candela.push_back(round_to_tenth((core + spill) * cutoff));
  }
  d.lamps = {LampSet{1, "LED module 830", 3000.0, "3000 K", "Ra 80", 24.5}};
  d.input_watts = 24.5;
  d.opening.shape = OpeningShape::Circular;
  d.opening.length_m = d.opening.width_m = 0.15;
  d.luminaire = {0.2, 0.0, 0.11};  // round, 200 mm diameter
  d.file_generation = gonio::photometry::FileGenerationType::ComputerSimulation;
  common_keywords(d, "DL-68", "Sample downlight, 68 deg beam");
  return d;
}

// A ceiling wall-washer 1 m from the wall on its C0 side: a broad lobe
// thrown towards the wall (C0, γ ≈ 60°), a weaker downward component and
// almost nothing behind (C180). Mirror-symmetric about the C0-C180 plane.
// 2000 lm module, 19 W.
Distribution wall_washer() {
  Distribution d;
  d.symmetry = Symmetry::C0_C180;
  for (int i = 0; i <= 12; ++i) d.horizontal_deg.push_back(15.0 * i);
  for (int i = 0; i <= 36; ++i) d.vertical_deg.push_back(5.0 * i);
  for (double c : d.horizontal_deg) {
    const double towards_wall = std::pow(0.5 + 0.5 * std::cos(c * kDeg), 2);
    for (double g : d.vertical_deg) {
      double cd = 0.0;
      if (g < 90.0) {
        const double lobe = std::exp(-std::pow((g - 58.0) / 17.0, 2));
        cd = 820.0 * lobe * towards_wall + 150.0 * std::cos(g * kDeg);
        if (g > 80.0) cd *= (90.0 - g) / 10.0;  // the trim cuts off at the ceiling
      }
      d.candela.push_back(round_to_tenth(cd));
    }
  }
  d.lamps = {LampSet{1, "LED module 840", 2000.0, "4000 K", "Ra 90", 19.0}};
  d.input_watts = 19.0;
  d.opening.shape = OpeningShape::Rectangular;
  d.opening.length_m = 0.12;  // along C0-C180
  d.opening.width_m = 0.09;
  d.luminaire = {0.16, 0.12, 0.09};
  d.file_generation = gonio::photometry::FileGenerationType::ComputerSimulation;
  common_keywords(d, "WW-1", "Sample wall-washer, asymmetric");
  return d;
}

bool write(const std::filesystem::path& path, Distribution d) {
  if (gonio::io::format_for_path(path.string()) == gonio::io::PhotometricFormat::Ldt) {
    // EULUMDAT has no fields for these; leaving them out keeps the file clean.
    d.file_generation = gonio::photometry::FileGenerationType::Undefined;
    std::erase_if(d.keywords,
                  [](const auto& k) { return k.key == "TESTLAB" || k.key == "FILEGENINFO"; });
  }
  std::vector<gonio::Finding> warnings;
  const gonio::Status s = gonio::io::write_photometric_file(path.string(), d, {}, &warnings);
  for (const gonio::Finding& w : warnings)
    std::fprintf(stderr, "%s: %s: %s [%s]\n", path.string().c_str(), gonio::to_string(w.severity),
                 w.message.c_str(), w.code.c_str());
  if (!s.ok()) {
    std::fprintf(stderr, "%s\n", gonio::to_string(s.error()).c_str());
    return false;
  }
  std::printf("%s\n", path.string().c_str());
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "Usage: gonio_make_curves DIR\nWrites the sample curves into DIR.\n");
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  bool ok = true;
  ok = write(dir / "downlight.ies", downlight()) && ok;
  ok = write(dir / "downlight.ldt", downlight()) && ok;
  ok = write(dir / "wall_washer.ies", wall_washer()) && ok;
  ok = write(dir / "wall_washer.ldt", wall_washer()) && ok;
  return ok ? 0 : 1;
}
