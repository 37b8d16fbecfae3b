// Goniometer tables as CSV (io/materials/bsdf_file.h).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "io/materials/bsdf_file.h"
#include "io/support/text.h"
#include "photometry/error_at.h"
#include "photometry/format.h"

namespace gonio::io {
namespace {

constexpr std::size_t kMaxRows = 4000000;
constexpr std::size_t kMaxAngles = 1000;

std::vector<std::string_view> fields_of(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    std::size_t j = i;
    while (j < line.size() && line[j] != ',' && line[j] != ';' && line[j] != '\t' && line[j] != ' ') ++j;
    out.push_back(line.substr(i, j - i));
    i = j;
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    if (i < line.size() && (line[i] == ',' || line[i] == ';')) ++i;
  }
  return out;
}

std::string lower(std::string_view s) {
  std::string r(s);
  for (char& c : r) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return r;
}

struct Sample {
  double theta_in, theta_out, phi, value;
  int line;
};

// Sorted unique values (exact repeats only: a goniometer's grid).
std::vector<double> unique_sorted(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

// Ring and φ bounds halfway between measured angles.
sim::PatchBasis basis_for(const std::vector<double>& thetas, const std::vector<double>& phis) {
  sim::PatchBasis b;
  b.ring_theta_deg.push_back(0.0);
  for (std::size_t i = 1; i < thetas.size(); ++i) b.ring_theta_deg.push_back(0.5 * (thetas[i - 1] + thetas[i]));
  b.ring_theta_deg.push_back(90.0);
  std::vector<double> bounds;
  const std::size_t n = phis.size();
  for (std::size_t k = 0; k < n; ++k) {
    const double prev = k == 0 ? phis[n - 1] - 360.0 : phis[k - 1];
    bounds.push_back(0.5 * (prev + phis[k]));
  }
  bounds.push_back(bounds.front() + 360.0);
  b.ring_phi_deg.assign(thetas.size(), bounds);
  return b;
}

}  // namespace

Result<sim::TabulatedBsdf> read_bsdf_csv(std::string_view bytes, const std::string& name,
                                         std::vector<Finding>& findings) {
  if (looks_binary(bytes)) return make_error(name, "not a text file");
  const std::vector<TextLine> lines = split_lines(bytes);
  int col[5] = {-1, -1, -1, -1, -1};  // theta_in, theta_out, phi_out, bsdf, side
  bool header = false;
  std::vector<Sample> samples[2];  // front, back
  for (const TextLine& l : lines) {
    std::string_view text = l.text;
    if (const auto hash = text.find('#'); hash != std::string_view::npos) text = text.substr(0, hash);
    if (text.find_first_not_of(" \t\r,;") == std::string_view::npos) continue;
    const std::vector<std::string_view> f = fields_of(text);
    const auto fail = [&](std::string m) { return make_error(name, l.number, std::move(m)); };
    if (!header) {
      for (std::size_t i = 0; i < f.size(); ++i) {
        std::string k = lower(f[i]);
        for (const char* suffix : {"_deg", "_per_sr"})
          if (k.size() > std::string(suffix).size() && k.compare(k.size() - std::string(suffix).size(), std::string::npos, suffix) == 0)
            k.resize(k.size() - std::string(suffix).size());
        int c = -1;
        if (k == "theta_in") c = 0;
        if (k == "theta_out") c = 1;
        if (k == "phi_out" || k == "phi") c = 2;
        if (k == "bsdf" || k == "brdf" || k == "btdf") c = 3;
        if (k == "side") c = 4;
        if (c < 0) return fail("unknown column " + shown(f[i]) + " (theta_in, theta_out, phi_out, bsdf, side)");
        if (col[c] >= 0) return fail("column " + shown(f[i]) + " appears twice");
        col[c] = static_cast<int>(i);
      }
      for (int c = 0; c < 4; ++c)
        if (col[c] < 0)
          return fail("the header must name the columns theta_in, theta_out, phi_out and bsdf");
      header = true;
      continue;
    }
    const std::size_t want = static_cast<std::size_t>(*std::max_element(col, col + 5)) + 1;
    if (f.size() != want && !(col[4] < 0 && f.size() == 4))
      return fail("expected " + std::to_string(want) + " fields, found " + std::to_string(f.size()));
    double v[4];
    for (int c = 0; c < 4; ++c) {
      const std::optional<double> x = parse_number(f[static_cast<std::size_t>(col[c])]);
      if (!x) return fail(shown(f[static_cast<std::size_t>(col[c])]) + " is not a number");
      v[c] = *x;
    }
    if (!(v[0] >= 0.0 && v[0] < 90.0)) return fail("theta_in " + format_number(v[0]) + " must lie in 0..90 (below 90)");
    if (!(v[1] >= 0.0 && v[1] <= 180.0) || v[1] == 90.0)
      return fail("theta_out " + format_number(v[1]) + " must lie in 0..180 and not be 90");
    if (!(v[2] >= 0.0 && v[2] < 360.0)) return fail("phi_out " + format_number(v[2]) + " must lie in 0..360 (below 360)");
    if (!(v[3] >= 0.0 && v[3] < 1e30)) return fail("bsdf " + format_number(v[3]) + " must be >= 0 and finite");
    int side = 0;
    if (col[4] >= 0) {
      const std::string s = lower(f[static_cast<std::size_t>(col[4])]);
      if (s == "back") side = 1;
      else if (s != "front") return fail("side " + shown(f[static_cast<std::size_t>(col[4])]) + " is not front or back");
    }
    if (samples[0].size() + samples[1].size() >= kMaxRows)
      return fail("more than " + std::to_string(kMaxRows) + " measurements");
    samples[side].push_back({v[0], v[1], v[2], v[3], l.number});
  }
  if (!header) return make_error(name, "no header line naming the columns");
  sim::TabulatedBsdf t;
  t.name = name;
  // One basis for both sides and hemispheres: the union of the measured
  // outgoing angles (transmission mirrored: 180 − θ), filled per hemisphere
  // from its nearest measured angle.
  std::vector<double> thetas, phis;
  bool half_plane = true;
  for (const auto& side : samples)
    for (const Sample& s : side) {
      thetas.push_back(s.theta_out < 90.0 ? s.theta_out : 180.0 - s.theta_out);
      phis.push_back(s.phi);
      if (s.phi > 180.0) half_plane = false;
    }
  if (thetas.empty()) return make_error(name, "no measurements");
  thetas = unique_sorted(thetas);
  phis = unique_sorted(phis);
  if (half_plane) {
    const std::vector<double> measured = phis;
    for (double p : measured)
      if (p > 0.0 && p < 180.0) phis.push_back(360.0 - p);
    phis = unique_sorted(phis);
  }
  if (thetas.size() > kMaxAngles || phis.size() > kMaxAngles || thetas.size() * phis.size() > 20000)
    return make_error(name, "the outgoing grid has " + std::to_string(thetas.size()) + " × " +
                                std::to_string(phis.size()) + " angles, more than Gonio reads");
  t.basis = basis_for(thetas, phis);
  for (int side = 0; side < 2; ++side) {
    if (samples[side].empty()) continue;
    sim::TabulatedBsdf::Side& out = side == 0 ? t.front : t.back;
    // Per hemisphere: the grid (θin → θout × φ → value), which must be full.
    for (int hemi = 0; hemi < 2; ++hemi) {
      std::map<std::tuple<double, double, double>, const Sample*> grid;
      std::vector<double> tin, tout, ph;
      for (const Sample& s : samples[side]) {
        if ((s.theta_out > 90.0) != (hemi == 1)) continue;
        const double to = hemi ? 180.0 - s.theta_out : s.theta_out;
        if (!grid.emplace(std::tuple{s.theta_in, to, s.phi}, &s).second)
          return make_error(name, s.line, "the same angles (theta_in " + format_number(s.theta_in) +
                                              ", theta_out " + format_number(s.theta_out) + ", phi_out " +
                                              format_number(s.phi) + ") appear twice");
        tin.push_back(s.theta_in);
        tout.push_back(to);
        ph.push_back(s.phi);
      }
      if (grid.empty()) continue;
      tin = unique_sorted(tin);
      tout = unique_sorted(tout);
      ph = unique_sorted(ph);
      if (grid.size() != tin.size() * tout.size() * ph.size()) {
        for (double a : tin)
          for (double b : tout)
            for (double c : ph)
              if (!grid.count({a, b, c}))
                return make_error(name, std::string(side ? "back " : "front ") + (hemi ? "transmission" : "reflection") +
                                            " is not a full grid: no value at theta_in " + format_number(a) +
                                            ", theta_out " + format_number(hemi ? 180.0 - b : b) + ", phi_out " +
                                            format_number(c));
      }
      if (out.rows.empty()) {
        for (double a : tin) {
          sim::TabulatedBsdf::Row r;
          r.theta_deg = a;
          out.rows.push_back(std::move(r));
        }
      } else {
        std::vector<double> have;
        for (const auto& r : out.rows) have.push_back(r.theta_deg);
        if (have != tin)
          return make_error(name, std::string(side ? "back" : "front") +
                                      ": reflection and transmission must be measured at the same theta_in");
      }
      const auto nearest = [](const std::vector<double>& v, double x, bool circular) {
        double best = 1e300;
        double pick = v.front();
        for (double a : v) {
          double d = std::abs(a - x);
          if (circular) d = std::min(d, 360.0 - d);
          if (d < best) {
            best = d;
            pick = a;
          }
        }
        return pick;
      };
      for (sim::TabulatedBsdf::Row& r : out.rows) {
        std::vector<float>& v = hemi ? r.transmit : r.reflect;
        v.resize(t.basis.size());
        std::size_t p = 0;
        for (double to : thetas) {
          const double mt = nearest(tout, to, false);
          for (double phi : phis) {
            double look = phi;
            if (half_plane && look > 180.0) look = 360.0 - look;
            const double mp = nearest(ph, look, true);
            v[p++] = static_cast<float>(grid.at({r.theta_deg, mt, mp})->value);
          }
        }
      }
    }
  }
  if (Status f = finish_bsdf(t, name, findings); !f.ok()) return f.error();
  return t;
}

}  // namespace gonio::io
