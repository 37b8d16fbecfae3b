// What the command-line suites share: running the gonio executable and
// photometric files with closed-form properties to run it on.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "photometry/distribution.h"
#include "tests/support/test_support.h"

namespace gonio::test {

// Runs the gonio executable under test with these arguments.
ProcessResult gonio(std::vector<std::string> args);

// A Lambertian downlight, I = I0 cos γ below the horizon and 0 above, on a
// 5° (C, C0-C180 symmetry) × 2.5° (γ) grid, relative photometry with one
// 1000 lm lamp of 10 W and I0 = 800/π cd, so that
//   flux 800 lm, LOR 0.8, DFF 1, peak I0 at γ 0, beam angle 120°, field angle
//   2 acos 0.1 = 168.52°, CIE flux code 43.75 75 93.75 100 80, efficacy 80 lm/W.
photometry::Distribution lambertian_downlight();
inline constexpr double kDownlightFluxLm = 800.0;

// Writes `d` to `path` in the format of its extension (io/photometric/photometric_file.h).
void write_distribution(const std::filesystem::path& path, const photometry::Distribution& d);

// Every entry in a directory, by name.
std::vector<std::string> directory_entries(const std::filesystem::path& dir);

bool contains(const std::string& text, const std::string& part);

}  // namespace gonio::test
