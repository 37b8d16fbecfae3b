#include "tests/tools/cli/cli_fixtures.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "io/photometric/photometric_file.h"

namespace gonio::test {

ProcessResult gonio(std::vector<std::string> args) {
  args.insert(args.begin(), GONIO_EXECUTABLE);
  return run_process(args);
}

photometry::Distribution lambertian_downlight() {
  photometry::Distribution d;
  d.symmetry = photometry::Symmetry::C0_C180;
  for (int i = 0; i <= 36; ++i) d.horizontal_deg.push_back(5.0 * i);
  for (int i = 0; i <= 72; ++i) d.vertical_deg.push_back(2.5 * i);
  const double i0 = kDownlightFluxLm / std::numbers::pi;
  for ([[maybe_unused]] double c : d.horizontal_deg)
    for (double g : d.vertical_deg)
      d.candela.push_back(g < 90.0 ? i0 * std::cos(g * std::numbers::pi / 180.0) : 0.0);
  d.lamps = {photometry::LampSet{1, "LED module", 1000.0, "", "", 10.0}};
  d.input_watts = 10.0;
  d.keywords = {
      {"TEST", "T-1"},      {"TESTLAB", "Gonio test suite"},       {"ISSUEDATE", "2025-01-31"},
      {"MANUFAC", "Gonio"}, {"LUMINAIRE", "Lambertian downlight"}, {"LUMCAT", "DL-800"}};
  d.opening.shape = photometry::OpeningShape::Circular;
  d.opening.length_m = d.opening.width_m = 0.1;
  return d;
}

void write_distribution(const std::filesystem::path& path, const photometry::Distribution& d) {
  const Status s = io::write_photometric_file(path.string(), d, {}, nullptr);
  if (!s.ok()) throw std::runtime_error(to_string(s.error()));
}

std::vector<std::string> directory_entries(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace gonio::test
