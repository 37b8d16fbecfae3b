#include "tests/support/photometry_fixtures.h"

#include <cmath>

#include "photometry/angles.h"

namespace gonio::test {
using namespace photometry;

std::vector<double> angles(double from, double to, double step) {
  std::vector<double> out;
  const long n = std::lround((to - from) / step);
  for (long i = 0; i <= n; ++i) out.push_back(from + static_cast<double>(i) * step);
  out.back() = to;
  return out;
}

Distribution sample_direction(PhotometricType type, Symmetry symmetry,
                              std::vector<double> horizontal_deg, std::vector<double> vertical_deg,
                              const std::function<double(const Vec3&)>& f) {
  Distribution d;
  d.type = type;
  d.symmetry = symmetry;
  d.horizontal_deg = std::move(horizontal_deg);
  d.vertical_deg = std::move(vertical_deg);
  for (double h : d.horizontal_deg)
    for (double v : d.vertical_deg) d.candela.push_back(f(direction_from_grid(type, h, v)));
  d.lamps = {LampSet{1, "test", 1000.0, "", "", kNaN}};
  return d;
}

Distribution sample_c(Symmetry symmetry, std::vector<double> c_deg, std::vector<double> gamma_deg,
                      const std::function<double(double, double)>& f) {
  Distribution d;
  d.type = PhotometricType::C;
  d.symmetry = symmetry;
  d.horizontal_deg = std::move(c_deg);
  d.vertical_deg = std::move(gamma_deg);
  for (double c : d.horizontal_deg)
    for (double g : d.vertical_deg) d.candela.push_back(f(c, g));
  d.lamps = {LampSet{1, "test", 1000.0, "", "", kNaN}};
  return d;
}

std::function<double(const Vec3&)> cos_lobe(double i0_cd, double n) {
  return [=](const Vec3& d) {
    const double c = -d.z / length(d);
    return c > 0.0 ? i0_cd * std::pow(c, n) : 0.0;
  };
}

}  // namespace gonio::test
