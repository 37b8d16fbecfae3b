// The typed reads of a design file's part tables ([[reflectors]],
// [[lenses]], [[troughs]] through read_profile_part): every mistake an error
// naming the design file and the line of the key (or of the table where the
// key is missing). Lengths are read in the file's unit and scaled by the
// callers with `unit_` (metres per unit).
#pragma once

#include <cmath>
#include <initializer_list>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "design/revolved.h"
#include "io/model/toml_tree.h"
#include "photometry/diagnostics.h"
#include "photometry/error_at.h"

namespace gonio::design {

class TableReader {
 public:
  TableReader(std::string path, double unit_m) : path_(std::move(path)), unit_(unit_m) {}

  Status keys(const io::TomlNode& t, std::initializer_list<const char*> known, const std::string& what) const {
    return io::check_keys(t, known, what, path_);
  }
  Result<std::string> string(const io::TomlNode& t, const char* key, const std::string& what) const {
    const io::TomlNode* n = t.get(key);
    if (!n) return make_error(path_, t.line, what + ": '" + key + "' is missing");
    if (!n->is_string()) return make_error(path_, n->line, what + ": '" + key + "' must be a string");
    return n->string;
  }
  Result<std::optional<double>> number(const io::TomlNode& t, const char* key, const std::string& what) const {
    const io::TomlNode* n = t.get(key);
    if (!n) return std::optional<double>();
    const std::optional<double> v = n->number();
    if (!v || !std::isfinite(*v)) return make_error(path_, n->line, what + ": '" + key + "' must be a finite number");
    return v;
  }
  Result<std::vector<double>> numbers(const io::TomlNode& t, const char* key, const std::string& what,
                                      bool required) const {
    const io::TomlNode* n = t.get(key);
    if (!n) {
      if (required) return make_error(path_, t.line, what + ": '" + key + "' is missing");
      return std::vector<double>();
    }
    std::vector<double> out;
    bool ok = n->is_array();
    for (std::size_t i = 0; ok && i < n->array.size(); ++i) {
      const std::optional<double> v = n->array[i].number();
      ok = v && std::isfinite(*v);
      if (ok) out.push_back(*v);
    }
    if (!ok) return make_error(path_, n->line, what + ": '" + key + "' must be an array of finite numbers");
    return out;
  }
  // A B-spline's control points [[ρ, z], …] into `b`, in metres.
  Status points(const io::TomlNode& t, const std::string& what, BSplineProfile& b) const {
    constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
    const io::TomlNode* points = t.get("points");
    if (!points) return make_error(path_, t.line, what + ": 'points' is missing");
    bool ok = points->is_array();
    for (std::size_t i = 0; ok && i < points->array.size(); ++i) {
      const io::TomlNode& pt = points->array[i];
      ok = pt.is_array() && pt.array.size() == 2;
      const double pr = ok ? pt.array[0].number().value_or(kNaN) : kNaN;
      const double pz = ok ? pt.array[1].number().value_or(kNaN) : kNaN;
      ok = std::isfinite(pr) && std::isfinite(pz);
      if (ok) {
        b.rho.push_back(pr * unit_);
        b.z.push_back(pz * unit_);
      }
    }
    if (!ok) return make_error(path_, points->line, what + ": 'points' must be an array of [ρ, z] pairs of finite numbers");
    if (b.rho.size() > 10000) return make_error(path_, points->line, what + ": more than 10000 points");
    return Ok{};
  }
  // A polar table's `theta_deg` (to radians) and `r` (to metres).
  Result<PolarProfile> polar(const io::TomlNode& t, const std::string& what) const {
    PolarProfile p;
    Result<std::vector<double>> theta = numbers(t, "theta_deg", what, true);
    if (!theta.ok()) return theta.error();
    Result<std::vector<double>> radii = numbers(t, "r", what, true);
    if (!radii.ok()) return radii.error();
    for (double v : *theta) p.theta.push_back(v * std::numbers::pi / 180.0);
    for (double v : *radii) p.r.push_back(v * unit_);
    return p;
  }
  // A B-spline's `degree`, 1 … 5 (`fallback` where the key is absent).
  Result<int> degree(const io::TomlNode& t, const std::string& what, int fallback) const {
    Result<std::optional<double>> d = number(t, "degree", what);
    if (!d.ok()) return d.error();
    const double wanted = d->value_or(fallback);
    if (!(wanted >= 1.0 && wanted <= 5.0) || wanted != std::trunc(wanted))
      return make_error(path_, t.get("degree")->line, what + ": 'degree' must be a whole number, 1 … 5");
    return static_cast<int>(wanted);
  }

 protected:
  std::string path_;
  double unit_;
};

}  // namespace gonio::design
