#include "photometry/validation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "photometry/flux.h"
#include "photometry/format.h"
#include "photometry/summary.h"

namespace gonio::photometry {
namespace {

constexpr double kTol = 1e-9;  // [deg]

bool near(double a, double b) { return std::abs(a - b) <= kTol; }

struct Report {
  std::vector<Finding> findings;
  void add(Severity s, const char* code, std::string message) {
    findings.push_back({s, code, std::move(message), {}});
  }
  void error(const char* code, std::string message) {
    add(Severity::Error, code, std::move(message));
  }
  void warning(const char* code, std::string message) {
    add(Severity::Warning, code, std::move(message));
  }
};

// "γ" / "C" for Type C, "V" / "H" otherwise.
const char* vertical_name(const Distribution& d) {
  return d.type == PhotometricType::C ? "gamma" : "V";
}
const char* horizontal_name(const Distribution& d) {
  return d.type == PhotometricType::C ? "C" : "H";
}

std::string where(const Distribution& d, std::size_t h, std::size_t v) {
  return std::string(horizontal_name(d)) + " " + format_number(d.horizontal_deg[h]) + " deg, " +
         vertical_name(d) + " " + format_number(d.vertical_deg[v]) + " deg";
}

bool check_angle_list(Report& r, const std::vector<double>& a, const char* which,
                      const char* order_code) {
  if (a.empty()) {
    r.error("no-angles", std::string("no ") + which + " angles; expected at least one");
    return false;
  }
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!std::isfinite(a[i])) {
      r.error("angle-not-finite", std::string(which) + " angle " + std::to_string(i + 1) + " is " +
                                      format_number(a[i]) +
                                      "; expected a finite number of degrees");
      return false;
    }
  }
  for (std::size_t i = 1; i < a.size(); ++i) {
    if (!(a[i] > a[i - 1])) {
      r.error(order_code, std::string(which) + " angles must increase strictly, but angle " +
                              std::to_string(i + 1) + " (" + format_number(a[i]) +
                              " deg) follows " + format_number(a[i - 1]) + " deg");
      return false;
    }
  }
  return true;
}

void check_ranges(Report& r, const Distribution& d) {
  const auto& v = d.vertical_deg;
  const auto& h = d.horizontal_deg;
  const bool c = d.type == PhotometricType::C;
  const double vlo = c ? 0.0 : -90.0, vhi = c ? 180.0 : 90.0;
  if (v.front() < vlo - kTol || v.back() > vhi + kTol)
    r.error("vertical-angle-range",
            std::string(vertical_name(d)) + " runs from " + format_number(v.front()) + " to " +
                format_number(v.back()) + " deg; Type " + to_string(d.type) + " allows " +
                format_number(vlo) + " to " + format_number(vhi) + " deg");
  const double hlo = c ? 0.0 : -90.0, hhi = c ? 360.0 : 90.0;
  if (h.front() < hlo - kTol || h.back() > hhi + kTol)
    r.error("horizontal-angle-range",
            std::string(horizontal_name(d)) + " runs from " + format_number(h.front()) + " to " +
                format_number(h.back()) + " deg; Type " + to_string(d.type) + " allows " +
                format_number(hlo) + " to " + format_number(hhi) + " deg");
  auto span = [&](double lo, double hi) {
    if (!near(h.front(), lo) || !near(h.back(), hi))
      r.error("symmetry-range", std::string("symmetry ") + to_string(d.symmetry) +
                                    " needs C-planes from " + format_number(lo) + " to " +
                                    format_number(hi) + " deg, found " + format_number(h.front()) +
                                    " to " + format_number(h.back()) + " deg");
  };
  if (c) {
    switch (d.symmetry) {
      case Symmetry::Rotational:
        if (h.size() != 1)
          r.error("symmetry-range",
                  "a rotationally symmetric distribution has exactly one C-plane, found " +
                      std::to_string(h.size()));
        break;
      case Symmetry::Quadrant:
        span(0.0, 90.0);
        break;
      case Symmetry::C0_C180:
        span(0.0, 180.0);
        break;
      case Symmetry::C90_C270:
        span(90.0, 270.0);
        break;
      case Symmetry::None:
        if (h.size() < 2)
          r.error("symmetry-range",
                  "a distribution without symmetry needs at least two C-planes, found 1");
        break;
      case Symmetry::Lateral:
        r.error("symmetry-range",
                "lateral symmetry belongs to Types A and B; a Type C distribution has symmetry "
                "none, rotational, C0-C180, C90-C270 or quadrant");
        break;
    }
  } else if (d.symmetry == Symmetry::Lateral) {
    if (!near(h.front(), 0.0))
      r.error("symmetry-range", "lateral symmetry needs horizontal angles from 0 deg, found " +
                                    format_number(h.front()) + " deg");
  } else if (d.symmetry != Symmetry::None) {
    r.error("symmetry-range",
            std::string("symmetry ") + to_string(d.symmetry) +
                " belongs to Type C; Types A and B have symmetry none or lateral");
  }
}

void check_structure(Report& r, const Distribution& d) {
  const bool v_ok = check_angle_list(r, d.vertical_deg, "vertical", "vertical-angles-order");
  const bool h_ok = check_angle_list(r, d.horizontal_deg, "horizontal", "horizontal-angles-order");
  if (v_ok && h_ok) check_ranges(r, d);
  const std::size_t expected = d.vertical_deg.size() * d.horizontal_deg.size();
  if (d.candela.size() != expected) {
    r.error("candela-count", "found " + std::to_string(d.candela.size()) +
                                 " intensities; expected " +
                                 std::to_string(d.horizontal_deg.size()) + " horizontal x " +
                                 std::to_string(d.vertical_deg.size()) +
                                 " vertical angles = " + std::to_string(expected));
  }
  std::size_t bad = 0, first = 0;
  for (std::size_t i = 0; i < d.candela.size(); ++i)
    if (!std::isfinite(d.candela[i]) && bad++ == 0) first = i;
  if (bad > 0) {
    std::string at = "value " + std::to_string(first + 1);
    if (d.candela.size() == expected && !d.vertical_deg.empty())
      at = where(d, first / d.vertical_deg.size(), first % d.vertical_deg.size());
    r.error("non-finite-intensity",
            std::to_string(bad) + " intensities are not finite (the first, " +
                format_number(d.candela[first]) + ", at " + at + "); expected finite candela");
  }
  for (std::size_t i = 0; i < d.lamps.size(); ++i) {
    const LampSet& l = d.lamps[i];
    if (l.count <= 0)
      r.error("lamp-count", "lamp set " + std::to_string(i + 1) + " has " +
                                std::to_string(l.count) + " lamps; expected a positive count");
    if (!d.absolute && !(std::isfinite(l.flux_lm) && l.flux_lm > 0.0))
      r.error("lamp-flux", "lamp set " + std::to_string(i + 1) + " has a rated flux of " +
                               format_number(l.flux_lm) +
                               " lm; relative photometry needs a positive rated lamp flux");
  }
}

// Largest minus smallest of the values f(i), i < n.
template <class F>
double spread(std::size_t n, F&& f) {
  double lo = f(0), hi = f(0);
  for (std::size_t i = 1; i < n; ++i) {
    lo = std::min(lo, f(i));
    hi = std::max(hi, f(i));
  }
  return hi - lo;
}

void check_poles(Report& r, const Distribution& d, double peak, double tolerance) {
  const std::size_t nh = d.horizontal_count(), nv = d.vertical_count();
  const double limit = tolerance * peak;
  const std::string allowed = " cd, more than the allowed " + format_number(limit) + " cd (" +
                              format_number(100 * tolerance) + " % of the peak " +
                              format_number(peak) + " cd)";
  if (d.type == PhotometricType::C) {
    if (nh > 1) {
      auto pole = [&](std::size_t v, const char* code, const char* name) {
        const double s = spread(nh, [&](std::size_t h) { return d.at(h, v); });
        if (s > limit)
          r.warning(code, std::string("the C-planes disagree at the ") + name + " (gamma " +
                              format_number(d.vertical_deg[v]) + " deg), one direction, by " +
                              format_number(s) + allowed);
      };
      if (near(d.vertical_deg.front(), 0.0)) pole(0, "nadir-mismatch", "nadir");
      if (near(d.vertical_deg.back(), 180.0)) pole(nv - 1, "zenith-mismatch", "zenith");
    }
    if (d.symmetry == Symmetry::None && nh > 1 && near(d.horizontal_deg.front(), 0.0) &&
        near(d.horizontal_deg.back(), 360.0)) {
      double s = 0.0;
      for (std::size_t v = 0; v < nv; ++v) s = std::max(s, std::abs(d.at(0, v) - d.at(nh - 1, v)));
      if (s > limit)
        r.warning("seam-mismatch",
                  "planes C 0 and C 360 (one plane) differ by up to " + format_number(s) + allowed);
    }
    return;
  }
  // Type A: the poles are V = ±90 (a column); Type B: H = ±90 (a row).
  if (d.type == PhotometricType::A) {
    for (std::size_t v : {std::size_t{0}, nv - 1}) {
      if (!near(std::abs(d.vertical_deg[v]), 90.0) || nh < 2) continue;
      const double s = spread(nh, [&](std::size_t h) { return d.at(h, v); });
      if (s > limit)
        r.warning("pole-mismatch", "the planes disagree at the pole V " +
                                       format_number(d.vertical_deg[v]) +
                                       " deg, one direction, by " + format_number(s) + allowed);
    }
  } else {
    for (std::size_t h : {std::size_t{0}, nh - 1}) {
      if (!near(std::abs(d.horizontal_deg[h]), 90.0) || nv < 2) continue;
      const double s = spread(nv, [&](std::size_t v) { return d.at(h, v); });
      if (s > limit)
        r.warning("pole-mismatch",
                  "the values at the pole H " + format_number(d.horizontal_deg[h]) +
                      " deg, one direction, differ by " + format_number(s) + allowed);
    }
  }
}

void check_data(Report& r, const Distribution& d, const CheckOptions& o) {
  const std::size_t nv = d.vertical_count();
  std::size_t negative = 0, lowest = 0, highest = 0;
  bool all_zero = true;
  for (std::size_t i = 0; i < d.candela.size(); ++i) {
    if (d.candela[i] < 0.0) ++negative;
    if (d.candela[i] < d.candela[lowest]) lowest = i;
    if (d.candela[i] > d.candela[highest]) highest = i;
    all_zero = all_zero && d.candela[i] == 0.0;
  }
  if (negative > 0)
    r.error("negative-intensity",
            std::to_string(negative) + " intensities are negative, the lowest " +
                format_number(d.candela[lowest]) + " cd at " + where(d, lowest / nv, lowest % nv) +
                "; intensities cannot be below 0 cd");
  if (all_zero) {
    r.error("all-zero", "every intensity is 0 cd: the distribution emits no light");
    return;
  }
  if (!d.absolute && d.lamps.empty())
    r.warning(
        "no-lamp-data",
        "relative photometry without lamp data: no rated lamp flux, so no light output ratio");

  const auto& v = d.vertical_deg;
  if (d.type == PhotometricType::C) {
    if (!(near(v.front(), 0.0) || near(v.front(), 90.0)) ||
        !(near(v.back(), 90.0) || near(v.back(), 180.0)))
      r.warning("vertical-range-nonstandard", "gamma runs from " + format_number(v.front()) +
                                                  " to " + format_number(v.back()) +
                                                  " deg; LM-63-2002 expects it to start at 0 or 90 "
                                                  "deg and end at 90 or 180 deg (directions "
                                                  "outside are taken as dark)");
  } else if (!(near(v.front(), -90.0) || near(v.front(), 0.0)) || !near(v.back(), 90.0)) {
    r.warning("vertical-range-nonstandard",
              "V runs from " + format_number(v.front()) + " to " + format_number(v.back()) +
                  " deg; LM-63-2002 expects it to start at -90 or 0 deg and end at 90 "
                  "deg (directions outside are taken as dark)");
  }
  if (nv == 1 || (d.type != PhotometricType::C && d.horizontal_count() == 1))
    r.warning("no-solid-angle",
              std::string("a single ") + (nv == 1 ? "vertical" : "horizontal") +
                  " angle spans no solid angle, so the flux is 0 lm; expected at least two");

  const double peak = d.candela[highest];
  check_poles(r, d, peak, o.pole_tolerance);

  const double flux = total_flux_lm(d);
  const double lamps = d.rated_lamp_flux_lm();
  if (!d.absolute && lamps > 0.0) {
    const double lor = flux / lamps;
    if (lor > o.max_lor)
      r.warning("lor-implausible",
                "the intensities integrate to " + format_number(flux) + " lm from rated lamps of " +
                    format_number(lamps) + " lm, a light output ratio of " +
                    format_number(100 * lor) +
                    " %; a luminaire cannot emit more than its lamps (expected at most " +
                    format_number(100 * o.max_lor) + " %): check the lamp flux and the multiplier");
    if (std::isfinite(d.declared_lor_percent)) {
      const double declared = d.declared_lor_percent / 100.0;
      const bool off =
          declared > 0.0 ? std::abs(lor / declared - 1.0) > o.declared_lor_tolerance : lor > 0.0;
      if (off)
        r.warning("lor-mismatch",
                  "the declared light output ratio is " + format_number(d.declared_lor_percent) +
                      " % but the intensities integrate to " + format_number(100 * lor) + " % (" +
                      format_number(flux) + " lm from " + format_number(lamps) +
                      " lm); expected them to agree within " +
                      format_number(100 * o.declared_lor_tolerance) + " %");
    }
  }
  if (std::isfinite(d.declared_dff_percent) && flux > 0.0) {
    const double dff = 100.0 * downward_flux_lm(d) / flux;
    if (std::abs(dff - d.declared_dff_percent) > o.declared_dff_tolerance_percent)
      r.warning("dff-mismatch",
                "the declared downward flux fraction is " + format_number(d.declared_dff_percent) +
                    " % but the intensities give " + format_number(dff) +
                    " %; expected them to agree within " +
                    format_number(o.declared_dff_tolerance_percent) + " percentage points");
  }
  if (peak > o.max_intensity_cd || (peak > 0.0 && peak < o.min_peak_intensity_cd))
    r.warning("absurd-intensity", "the peak intensity is " + format_number(peak) + " cd at " +
                                      where(d, highest / nv, highest % nv) + "; expected between " +
                                      format_number(o.min_peak_intensity_cd) + " and " +
                                      format_number(o.max_intensity_cd) +
                                      " cd: check the units and the multiplier");
  if (flux > o.max_flux_lm)
    r.warning("absurd-flux", "the intensities integrate to " + format_number(flux) +
                                 " lm; expected at most " + format_number(o.max_flux_lm) +
                                 " lm for a luminaire: check the units and the multiplier");
  const double power = input_power_w(d);
  if (std::isfinite(power) && flux / power > o.max_efficacy_lm_per_w)
    r.warning("efficacy-implausible",
              format_number(flux) + " lm from " + format_number(power) + " W is " +
                  format_number(flux / power) + " lm/W; expected at most " +
                  format_number(o.max_efficacy_lm_per_w) +
                  " lm/W for white light: check the input watts and the intensities");
}

}  // namespace

std::vector<Finding> check(const Distribution& d, const CheckOptions& options) {
  Report r;
  check_structure(r, d);
  if (!r.findings.empty()) return std::move(r.findings);
  if (Status s = validate(d); !s.ok()) {
    r.error("invalid-model", s.error().message);
    return std::move(r.findings);
  }
  check_data(r, d, options);
  return std::move(r.findings);
}

}  // namespace gonio::photometry
