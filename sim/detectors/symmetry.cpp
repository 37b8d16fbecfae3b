#include "sim/detectors/symmetry.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>

#include "photometry/format.h"
#include "sim/detectors/chi_square.h"

namespace gonio::sim {
namespace {

bool divides(double whole, double step) {
  const double n = whole / step;
  return std::abs(n - std::round(n)) <= 1e-9 * n;
}

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(a[i])) !=
        std::tolower(static_cast<unsigned char>(b[i])))
      return false;
  }
  return true;
}

// The C-plane indices equivalent to plane i (its orbit under the symmetry's
// group), sorted. Mirror images are looked up by angle, so non-uniform C
// lists work alike (grid_supports has checked that every image exists).
std::vector<int> plane_orbit(int i, const CGammaGrid& grid, Symmetry symmetry) {
  const int nc = grid.c_count();
  const bool mirror0 = symmetry == Symmetry::C0_C180 || symmetry == Symmetry::Quadrant;
  const bool mirror90 = symmetry == Symmetry::C90_C270 || symmetry == Symmetry::Quadrant;
  const bool rotate = symmetry == Symmetry::Rotational;
  std::vector<int> orbit = {i};
  for (std::size_t k = 0; k < orbit.size(); ++k) {
    const int c = orbit[k];
    std::vector<int> images;
    if (mirror0) images.push_back(grid.c_index_of(360.0 - grid.c_deg(c)));  // C → 360° − C
    if (mirror90) images.push_back(grid.c_index_of(180.0 - grid.c_deg(c)));  // C → 180° − C
    if (rotate) images.push_back((c + 1) % nc);
    for (int image : images)
      if (image >= 0 && std::find(orbit.begin(), orbit.end(), image) == orbit.end()) orbit.push_back(image);
  }
  std::sort(orbit.begin(), orbit.end());
  return orbit;
}

// Whether every C-plane's mirror image in the plane `mirror_deg` (C → 2·mirror
// − C) is a plane of the grid too, with the same bin width.
bool mirror_closed(const CGammaGrid& grid, double mirror_deg) {
  for (int i = 0; i < grid.c_count(); ++i) {
    const int k = grid.c_index_of(2.0 * mirror_deg - grid.c_deg(i));
    if (k < 0) return false;
    const double wi = grid.c_upper_deg(i) - grid.c_lower_deg(i), wk = grid.c_upper_deg(k) - grid.c_lower_deg(k);
    if (std::abs(wi - wk) > 1e-9) return false;
  }
  return true;
}

// The χ² value beyond which a test with `dof` degrees of freedom rejects at
// `significance`: the upper-tail quantile, by bisection (the tail falls
// monotonically in x).
double critical_value(double dof, double significance) {
  double lo = 0.0, hi = dof + 20.0 * std::sqrt(2.0 * dof) + 100.0;
  while (chi_square_upper_tail(hi, dof) > significance) hi *= 2.0;
  for (int i = 0; i < 200 && hi - lo > 1e-9 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (chi_square_upper_tail(mid, dof) > significance ? lo : hi) = mid;
  }
  return hi;
}

// The noncentrality λ at which χ² (dof, λ), taken as normal with mean
// dof + λ and variance 2(dof + 2λ), exceeds `critical` with probability
// kSymmetryTestPower: the larger root of (λ − c)² = 2z²(dof + 2λ), c =
// critical − dof, z the normal quantile of the power.
double noncentrality_for_power(double dof, double critical) {
  constexpr double z = 1.2815515655446004;  // Φ⁻¹(0.9)
  static_assert(kSymmetryTestPower == 0.9, "z is the normal quantile of kSymmetryTestPower");
  const double c = critical - dof, z2 = z * z;
  return c + 2.0 * z2 + std::sqrt(4.0 * z2 * c + 4.0 * z2 * z2 + 2.0 * z2 * dof);
}

SymmetryTest run_test(const BinnedField& field, Symmetry symmetry,
                      const SymmetryTestOptions& options) {
  SymmetryTest t;
  t.symmetry = symmetry;
  const double eps2 = options.tolerance * options.tolerance;
  double sensitivity = 0.0;  // Σ Ī² / σ_i²: the χ² a relative deviation of 1 in every bin would add
  for (const std::vector<std::size_t>& group : equivalent_bins(field.grid, symmetry)) {
    if (group.size() < 2) continue;
    double flux = 0.0, sa = 0.0, var = 0.0, photons = 0.0;
    for (std::size_t b : group) {
      flux += field.flux_lm[b];
      sa += field.solid_angle_sr[b];
      var += field.variance_lm2[b];
      photons += field.photons[b];
    }
    if (!(flux > 0.0)) continue;
    const double k = static_cast<double>(group.size());
    const bool counted = photons > 0.0;
    if (counted && photons / k < options.min_photons) continue;
    const double mean = flux / sa;                // Ī [cd]
    const double var_per_lm = counted ? var / flux : 0.0;  // pooled [lm]
    for (std::size_t b : group) {
      const double omega = field.solid_angle_sr[b];
      const double diff = field.flux_lm[b] / omega - mean;
      const double sigma2 = var_per_lm * mean / omega + eps2 * mean * mean;
      if (sigma2 > 0.0) {
        t.chi_square += diff * diff / sigma2;
        sensitivity += mean * mean / sigma2;
      } else {
        sensitivity = std::numeric_limits<double>::infinity();
        if (diff != 0.0) t.chi_square = std::numeric_limits<double>::infinity();
      }
    }
    t.degrees_of_freedom += k - 1.0;
    ++t.groups;
  }
  if (t.groups == 0) {
    t.p_value = std::numeric_limits<double>::quiet_NaN();
    t.rejected = true;  // nothing to test: no claim
    return t;
  }
  t.p_value = chi_square_upper_tail(t.chi_square, t.degrees_of_freedom);
  t.rejected = t.p_value < options.significance;
  const double lambda =
      noncentrality_for_power(t.degrees_of_freedom, critical_value(t.degrees_of_freedom, options.significance));
  t.detectable_deviation = std::sqrt(lambda / sensitivity);
  return t;
}

std::string describe(const SymmetryTest& t) {
  std::string s = photometry::to_string(t.symmetry);
  if (t.groups == 0) return s + " untestable (too few photons)";
  s += t.rejected ? " rejected" : " not rejected";
  s += " (chi2 " + format_fixed(t.chi_square, 1) + " for " + format_number(t.degrees_of_freedom) +
       " dof, p " + format_number(t.p_value, 2) + ")";
  return s;
}

}  // namespace

std::optional<Symmetry> parse_symmetry(std::string_view name) {
  for (Symmetry s : {Symmetry::None, Symmetry::C0_C180, Symmetry::C90_C270, Symmetry::Quadrant,
                     Symmetry::Rotational}) {
    if (iequals(name, photometry::to_string(s))) return s;
  }
  return std::nullopt;
}

bool grid_supports(const CGammaGrid& grid, Symmetry symmetry) {
  if (grid.c_angles_deg.empty()) {
    switch (symmetry) {
      case Symmetry::None:
      case Symmetry::Rotational: return true;
      case Symmetry::C0_C180: return divides(180.0, grid.c_step_deg);
      case Symmetry::C90_C270:
      case Symmetry::Quadrant: return divides(90.0, grid.c_step_deg);
      case Symmetry::Lateral: return false;
    }
    return false;
  }
  // A C list: the planes the output range starts and ends at, and a set of
  // planes closed under the symmetry's mirrors.
  const auto has = [&](double c) { return grid.c_index_of(c) >= 0; };
  switch (symmetry) {
    case Symmetry::None:
    case Symmetry::Rotational: return true;
    case Symmetry::C0_C180: return has(180.0) && mirror_closed(grid, 0.0);
    case Symmetry::C90_C270: return has(90.0) && has(270.0) && mirror_closed(grid, 90.0);
    case Symmetry::Quadrant: return has(90.0) && mirror_closed(grid, 0.0) && mirror_closed(grid, 90.0);
    case Symmetry::Lateral: return false;
  }
  return false;
}

Status check_grid_supports(const CGammaGrid& grid, Symmetry symmetry) {
  if (grid_supports(grid, symmetry)) return Ok{};
  Error e;
  if (symmetry == Symmetry::Lateral) {
    e.message = "lateral symmetry belongs to Types A and B; simulations write Type C";
  } else if (!grid.c_angles_deg.empty()) {
    const char* what = symmetry == Symmetry::C0_C180    ? "C = 180° and planes mirrored about C0-C180"
                       : symmetry == Symmetry::C90_C270 ? "C = 90°, 270° and planes mirrored about C90-C270"
                                                        : "C = 90° and planes mirrored about C0-C180 and C90-C270";
    e.message = std::string("symmetry ") + photometry::to_string(symmetry) + " needs C angles with " + what;
  } else {
    const char* whole = symmetry == Symmetry::C0_C180 ? "180" : "90";
    e.message = std::string("symmetry ") + photometry::to_string(symmetry) +
                " needs a C step dividing " + whole + "°, not " + format_number(grid.c_step_deg) +
                "°";
  }
  return e;
}

int symmetry_order(const CGammaGrid& grid, Symmetry symmetry) {
  switch (symmetry) {
    case Symmetry::None: return 1;
    case Symmetry::C0_C180:
    case Symmetry::C90_C270: return 2;
    case Symmetry::Quadrant: return 4;
    case Symmetry::Rotational: return grid.c_count();
    case Symmetry::Lateral: return 2;
  }
  return 1;
}

std::vector<std::vector<std::size_t>> equivalent_bins(const CGammaGrid& grid, Symmetry symmetry) {
  GONIO_CHECK_MSG(grid_supports(grid, symmetry), "the grid does not support this symmetry");
  const int nc = grid.c_count(), ng = grid.gamma_count();
  std::vector<std::vector<std::size_t>> groups = {{grid.bin(0, 0)}, {grid.bin(0, ng - 1)}};
  std::vector<std::vector<int>> orbits;
  std::vector<bool> seen(static_cast<std::size_t>(nc), false);
  for (int i = 0; i < nc; ++i) {
    if (seen[static_cast<std::size_t>(i)]) continue;
    orbits.push_back(plane_orbit(i, grid, symmetry));
    for (int c : orbits.back()) seen[static_cast<std::size_t>(c)] = true;
  }
  for (int j = 1; j < ng - 1; ++j) {
    for (const std::vector<int>& orbit : orbits) {
      std::vector<std::size_t> group;
      for (int c : orbit) group.push_back(grid.bin(c, j));
      groups.push_back(std::move(group));
    }
  }
  return groups;
}

std::vector<double> symmetric_intensity_cd(const BinnedField& field, Symmetry symmetry) {
  std::vector<double> out(field.flux_lm.size(), 0.0);
  for (const std::vector<std::size_t>& group : equivalent_bins(field.grid, symmetry)) {
    double flux = 0.0, sa = 0.0;
    for (std::size_t b : group) {
      flux += field.flux_lm[b];
      sa += field.solid_angle_sr[b];
    }
    for (std::size_t b : group) out[b] = flux / sa;
  }
  return out;
}

SymmetryDecision detect_symmetry(const BinnedField& field, const SymmetryTestOptions& options) {
  SymmetryDecision d;
  const std::string how = "significance " + format_number(options.significance) + ", tolerance " +
                          format_number(100.0 * options.tolerance) + " %";
  if (!(field.total_flux_lm() > 0.0)) {
    d.explanation = "symmetry auto: none (the far field holds no flux)";
    return d;
  }
  for (Symmetry s :
       {Symmetry::Rotational, Symmetry::Quadrant, Symmetry::C0_C180, Symmetry::C90_C270}) {
    if (grid_supports(field.grid, s)) d.tests.push_back(run_test(field, s, options));
  }
  const SymmetryTest* best = nullptr;
  for (const SymmetryTest& t : d.tests) {
    if (t.rejected) continue;
    if (t.symmetry == Symmetry::Rotational || t.symmetry == Symmetry::Quadrant) {
      best = &t;
      break;
    }
    if (best == nullptr || t.p_value > best->p_value) best = &t;
  }
  d.symmetry = best ? best->symmetry : Symmetry::None;
  d.explanation = std::string("symmetry auto: ") + photometry::to_string(d.symmetry) + " (";
  for (std::size_t k = 0; k < d.tests.size(); ++k)
    d.explanation += (k ? "; " : "") + describe(d.tests[k]);
  d.explanation += "; " + how + ")";
  if (best != nullptr)
    d.explanation +=
        std::string("; power: ") + photometry::to_string(best->symmetry) +
        " is rejected 9 times in 10 when equivalent directions deviate from their mean by " +
        format_number(100.0 * best->detectable_deviation, 2) +
        " % RMS or more at these photon counts; smaller asymmetries may go unseen";
  return d;
}

}  // namespace gonio::sim
