#include "io/outputs/datasheet.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>
#include <string_view>
#include <vector>

#include "io/support/file_io.h"
#include "io/outputs/colour_chart.h"
#include "io/outputs/intensity_diagram.h"
#include "photometry/colour.h"
#include "photometry/spectrum.h"
#include "io/outputs/plot.h"
#include "io/support/process.h"
#include "photometry/format.h"
#include "photometry/intensity_sampler.h"
#include "photometry/planning.h"
#include "photometry/resample.h"
#include "photometry/summary.h"

namespace gonio::io {
namespace {

namespace fs = std::filesystem;
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

Error error(std::string message) {
  Error e;
  e.message = std::move(message);
  return e;
}

std::string esc(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      default: o += c;
    }
  }
  return o;
}

// A table cell: format_fixed, with a dash for an undefined value.
std::string fmt(double v, int decimals) { return std::isfinite(v) ? format_fixed(v, decimals) : "–"; }

std::string pct(double fraction, int decimals = 1) {
  return std::isfinite(fraction) ? fmt(100 * fraction, decimals) + " %" : "–";
}

// gnuplot's SVG document without its XML prolog, to sit inline in HTML.
std::string inline_svg(const std::string& svg) {
  const std::size_t at = svg.find("<svg");
  return at == std::string::npos ? svg : svg.substr(at);
}

const char* kStyle = R"(
body{font-family:"DejaVu Sans",Arial,sans-serif;font-size:10pt;color:#222;margin:18px}
h1{font-size:16pt;margin:0 0 4px}h2{font-size:12pt;margin:18px 0 6px;border-bottom:1px solid #999}
table{border-collapse:collapse;margin:4px 0}td,th{border:1px solid #bbb;padding:2px 6px;text-align:right}
th{background:#eee}td.l,th.l{text-align:left}.note{font-size:8.5pt;color:#555;max-width:60em}
section.lum{page-break-after:always}.svg svg{max-width:100%;height:auto}
.grid{display:flex;flex-wrap:wrap;gap:16px;align-items:flex-start}
)";

std::string row(const std::string& label, const std::string& value) {
  return "<tr><th class=l>" + esc(label) + "</th><td class=l>" + esc(value) + "</td></tr>\n";
}

std::string keyword(const photometry::Distribution& d, const char* key) {
  const photometry::Keyword* k = d.find_keyword(key);
  return k ? k->value : std::string();
}

// Colour of an illuminance relative to the maximum, on a log scale over
// two decades: dark blue → green → yellow → white.
std::string heat(double rel) {
  if (!(rel > 0.0)) return "#0b1a40";
  const double t = std::clamp(1.0 + std::log10(rel) / 2.0, 0.0, 1.0);
  const double stops[5][3] = {{11, 26, 64}, {30, 90, 170}, {60, 170, 90}, {240, 220, 60}, {255, 255, 240}};
  const double x = t * 4.0;
  const int i = std::min(3, static_cast<int>(x));
  const double f = x - i;
  char buf[16];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x",
                static_cast<int>(stops[i][0] + f * (stops[i + 1][0] - stops[i][0])),
                static_cast<int>(stops[i][1] + f * (stops[i + 1][1] - stops[i][1])),
                static_cast<int>(stops[i][2] + f * (stops[i + 1][2] - stops[i][2])));
  return buf;
}

// Isolux plot: horizontal illuminance on the floor h below the luminaire
// over ±2h, E = I cos³γ / h², C0 to the right, C90 up.
std::string isolux_svg(const photometry::IntensitySampler& s, double h, double* e_max_lx) {
  constexpr int n = 61;
  const double half = 2.0 * h, cell = 2 * half / n;
  std::vector<double> e(n * n);
  double emax = 0.0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = -half + (i + 0.5) * cell, y = half - (j + 0.5) * cell;
      const double r = std::hypot(x, y);
      const double g = std::atan2(r, h);
      double c = std::atan2(y, x) / kDeg;
      if (c < 0) c += 360;
      const double v = s.cd(c, g / kDeg) * std::pow(std::cos(g), 3) / (h * h);
      e[j * n + i] = v;
      emax = std::max(emax, v);
    }
  *e_max_lx = emax;
  const int px = 5;
  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << n * px + 150 << "\" height=\"" << n * px + 30
    << "\" font-family=\"DejaVu Sans\" font-size=\"10\">\n";
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      o << "<rect x=\"" << i * px << "\" y=\"" << j * px << "\" width=\"" << px << "\" height=\"" << px
        << "\" fill=\"" << heat(emax > 0 ? e[j * n + i] / emax : 0.0) << "\"/>";
  // The isolux lines: marching squares over the texel centres, one path per
  // level of the legend (below the maximum), interpolated along cell edges.
  for (double rel : {0.5, 0.2, 0.1, 0.05, 0.02, 0.01}) {
    const double level = rel * emax;
    if (!(level > 0.0)) break;
    std::ostringstream d;
    auto at = [&](int i, int j) { return e[j * n + i]; };
    auto point = [&](double i, double j) {
      d << format_fixed((i + 0.5) * px, 2) << ' ' << format_fixed((j + 0.5) * px, 2);
    };
    for (int j = 0; j + 1 < n; ++j)
      for (int i = 0; i + 1 < n; ++i) {
        // Corners anticlockwise from the top left; the edges between them.
        const double v[4] = {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
        const int ci[4] = {i, i + 1, i + 1, i}, cj[4] = {j, j, j + 1, j + 1};
        double ex[4], ey[4];
        int crossings = 0;
        for (int k = 0; k < 4; ++k) {
          const int l = (k + 1) % 4;
          if ((v[k] >= level) == (v[l] >= level)) continue;
          const double t = (level - v[k]) / (v[l] - v[k]);
          ex[crossings] = ci[k] + t * (ci[l] - ci[k]);
          ey[crossings] = cj[k] + t * (cj[l] - cj[k]);
          ++crossings;
        }
        for (int k = 0; k + 1 < crossings; k += 2) {  // 2 crossings, or 4 at a saddle
          d << 'M';
          point(ex[k], ey[k]);
          d << 'L';
          point(ex[k + 1], ey[k + 1]);
        }
      }
    if (d.tellp() > 0)
      o << "\n<path class=\"isolux\" data-lx=\"" << format_number(level, 6) << "\" d=\"" << d.str()
        << "\" fill=\"none\" stroke=\"#fff\" stroke-width=\"0.8\"/>";
  }
  o << "\n<line x1=\"" << n * px / 2.0 << "\" y1=\"0\" x2=\"" << n * px / 2.0 << "\" y2=\"" << n * px
    << "\" stroke=\"#888\" stroke-width=\"0.5\"/><line x1=\"0\" y1=\"" << n * px / 2.0 << "\" x2=\"" << n * px
    << "\" y2=\"" << n * px / 2.0 << "\" stroke=\"#888\" stroke-width=\"0.5\"/>\n";
  o << "<text x=\"" << n * px - 4 << "\" y=\"" << n * px / 2.0 - 4 << "\" text-anchor=\"end\" fill=\"#fff\">C0</text>";
  o << "<text x=\"" << n * px / 2.0 + 4 << "\" y=\"12\" fill=\"#fff\">C90</text>";
  o << "<text x=\"0\" y=\"" << n * px + 14 << "\">" << fmt(-half, 1) << " m</text><text x=\"" << n * px
    << "\" y=\"" << n * px + 14 << "\" text-anchor=\"end\">" << fmt(half, 1) << " m</text>\n";
  // Legend: the levels 100, 50, 20, 10, 5, 2, 1 % of the maximum.
  int k = 0;
  for (double rel : {1.0, 0.5, 0.2, 0.1, 0.05, 0.02, 0.01}) {
    const int y = 10 + 18 * k++;
    o << "<rect x=\"" << n * px + 10 << "\" y=\"" << y << "\" width=\"14\" height=\"14\" fill=\"" << heat(rel)
      << "\" stroke=\"#666\" stroke-width=\"0.5\"/><text x=\"" << n * px + 30 << "\" y=\"" << y + 11 << "\">"
      << fmt(rel * emax, emax * rel < 10 ? 2 : 0) << " lx</text>\n";
  }
  o << "</svg>";
  return o.str();
}

std::string zones_table(const photometry::Summary& s) {
  std::string h = "<table><tr><th>zone</th><th>lm</th><th>% of luminaire</th></tr>\n";
  for (const auto& z : s.zones)
    h += "<tr><td>" + fmt(z.from_deg, 0) + "–" + fmt(z.to_deg, 0) + "°</td><td>" + fmt(z.flux_lm, 1) +
         "</td><td>" + (s.flux_lm > 0 ? pct(z.flux_lm / s.flux_lm) : "–") + "</td></tr>\n";
  h += "</table><table><tr><th>10° zone</th><th>lm</th><th>%</th></tr>\n";
  for (const auto& z : s.zones_10deg)
    h += "<tr><td>" + fmt(z.from_deg, 0) + "–" + fmt(z.to_deg, 0) + "°</td><td>" + fmt(z.flux_lm, 1) +
         "</td><td>" + (s.flux_lm > 0 ? pct(z.flux_lm / s.flux_lm) : "–") + "</td></tr>\n";
  return h + "</table>\n";
}

// At most 13 of the stored planes, and every stored vertical angle.
std::string candela_table(const photometry::Distribution& d) {
  const std::size_t nh = d.horizontal_count();
  const std::size_t step = std::max<std::size_t>(1, (nh + 12) / 13);
  std::vector<std::size_t> cols;
  for (std::size_t h = 0; h < nh; h += step) cols.push_back(h);
  if (cols.back() != nh - 1) cols.push_back(nh - 1);
  const bool c = d.type == photometry::PhotometricType::C;
  std::string t = std::string("<table><tr><th>") + (c ? "γ \\ C" : "V \\ H") + "</th>";
  for (std::size_t h : cols) t += "<th>" + fmt(d.horizontal_deg[h], 1) + "°</th>";
  t += "</tr>\n";
  for (std::size_t v = 0; v < d.vertical_count(); ++v) {
    t += "<tr><th>" + fmt(d.vertical_deg[v], 1) + "°</th>";
    for (std::size_t h : cols) t += "<td>" + fmt(d.at(h, v), 1) + "</td>";
    t += "</tr>\n";
  }
  return t + "</table>\n";
}

std::string ugr_html(const photometry::UgrTable& u) {
  if (!u.defined) return "<p>UGR: not defined — " + esc(u.why_undefined) + ".</p>\n";
  std::string t =
      "<table><tr><th colspan=2>room</th><th colspan=5>viewed crosswise</th><th colspan=5>viewed "
      "endwise</th></tr><tr><th>X</th><th>Y</th>";
  for (int k = 0; k < 2; ++k)
    for (const auto& r : photometry::kUgrReflectances)
      t += "<th>" + fmt(100 * r[0], 0) + "/" + fmt(100 * r[1], 0) + "/" + fmt(100 * r[2], 0) + "</th>";
  t += "</tr>\n";
  for (const auto& r : u.rooms) {
    t += "<tr><td>" + fmt(r.x_h, 0) + "H</td><td>" + fmt(r.y_h, 0) + "H</td>";
    for (double v : r.crosswise) t += "<td>" + fmt(v, 1) + "</td>";
    for (double v : r.endwise) t += "<td>" + fmt(v, 1) + "</td>";
    t += "</tr>\n";
  }
  t += "</table><p class=note>Reflectances ceiling/walls/working plane; spacing S = " + fmt(u.spacing_h, 2) +
       "H; for " + fmt(u.flux_lm, 0) + " lm; for another flux F add 8 log10(F / " + fmt(u.flux_lm, 0) +
       ").</p>\n";
  return t;
}

std::string cu_html(const photometry::CuTable& c) {
  if (!c.defined) return "<p>CU: not defined — " + esc(c.why_undefined) + ".</p>\n";
  std::string t = "<table><tr><th>ρcc</th>";
  for (const auto& p : photometry::kCuReflectancePairs) t += "<th>" + fmt(100 * p[0], 0) + "</th>";
  t += "</tr><tr><th>ρw</th>";
  for (const auto& p : photometry::kCuReflectancePairs) t += "<th>" + fmt(100 * p[1], 0) + "</th>";
  t += "</tr>\n";
  for (std::size_t r = 0; r < c.rcr.size(); ++r) {
    t += "<tr><th>RCR " + fmt(c.rcr[r], 0) + "</th>";
    for (double v : c.values[r]) t += "<td>" + fmt(100 * v, 0) + "</td>";
    t += "</tr>\n";
  }
  t += std::string("</table><p class=note>IES zonal cavity method; effective floor cavity reflectance ") +
       fmt(100 * c.floor_reflectance, 0) + " %; values in % of the " +
       (c.relative_to_lamps ? "rated lamp flux" : "luminaire flux") + " (" + fmt(c.reference_flux_lm, 0) +
       " lm).</p>\n";
  return t;
}

std::string sc_text(const photometry::SpacingValue& v) {
  return v.ratio ? fmt(*v.ratio, 2) : "– (" + v.why_undefined + ")";
}

// A spectral simulation's colour (report.json's "colour" and
// "colour_over_angle"): the luminaire's CIE x, y, u′v′, CCT and Duv, Δu′v′
// max, and the colour-over-angle chart; empty without them.
Result<std::string> colour_html(const nlohmann::json& r) {
  if (!r.contains("colour") || !r["colour"].is_object()) return std::string();
  const nlohmann::json& c = r["colour"];
  const auto num = [](const nlohmann::json& j, const char* key) {
    return j.contains(key) && j[key].is_number() ? j[key].get<double>() : photometry::kNaN;
  };
  std::string h = "<h2>Colour</h2>\n<table class=colour>\n";
  h += row("CIE 1931 x, y", fmt(num(c, "cie_x"), 4) + ", " + fmt(num(c, "cie_y"), 4));
  h += row("CIE 1976 u′, v′", fmt(num(c, "u_prime"), 4) + ", " + fmt(num(c, "v_prime"), 4));
  h += row("CCT", fmt(num(c, "cct_k"), 0) + " K");
  h += row("Duv", fmt(num(c, "duv"), 4));
  const nlohmann::json coa = r.value("colour_over_angle", nlohmann::json());
  if (coa.is_object()) {
    h += row("Δu′v′ max", fmt(num(coa, "delta_uv_max"), 4) + " (from the flux-weighted mean u′v′ " +
                               fmt(num(coa, "mean_u_prime"), 4) + ", " + fmt(num(coa, "mean_v_prime"), 4) +
                               ", over directions of at least " + pct(num(coa, "threshold_fraction"), 0) +
                               " of the peak intensity)");
  }
  h += "</table>\n";
  if (coa.is_object() && coa.contains("planes") && coa["planes"].is_array()) {
    const std::vector<ColourCurve> curves = colour_curves(coa);
    if (!curves.empty()) {
      Result<Figure> fig = colour_over_angle_chart(curves, "Colour over angle", num(coa, "delta_uv_max"));
      if (!fig.ok()) return fig.error();
      Result<std::string> svg = render_figure(fig.value(), ImageFormat::Svg);
      if (!svg.ok()) return svg.error();
      h += "<div class=\"svg colour-chart\">" + inline_svg(svg.value()) + "</div>\n";
    }
  }
  h += "<p class=note>" + esc(c.value("method", std::string("CIE 1931 2°"))) +
       "; per direction from the far field's X, Y and Z binned like the intensity.</p>\n";
  return h;
}

// A file's spectrum (TM-33 SpectralData): the colour it gives, CIE 15's
// 5 nm summation and Ohno's CCT (photometry/colour.h).
std::string spectrum_colour_html(const photometry::Spectrum& spectrum) {
  const photometry::SampledSpectrum s = photometry::sampled(spectrum);
  if (!photometry::validate_spectrum(s).ok()) return std::string();
  const photometry::Tristimulus t = photometry::tristimulus(s);
  const photometry::Chromaticity xy = photometry::chromaticity(t);
  const photometry::UvPrime uv = photometry::uv_prime(t);
  const photometry::CctDuv c = photometry::cct_duv(uv);
  std::string h = "<h2>Colour</h2>\n<table class=colour>\n";
  h += row("CIE 1931 x, y", fmt(xy.x, 4) + ", " + fmt(xy.y, 4));
  h += row("CIE 1976 u′, v′", fmt(uv.u_prime, 4) + ", " + fmt(uv.v_prime, 4));
  h += row("CCT", fmt(c.cct_k, 0) + " K");
  h += row("Duv", fmt(c.duv, 4));
  h += "</table>\n<p class=note>From the file's spectrum" +
       (spectrum.emitter.empty() ? std::string() : " (" + esc(spectrum.emitter) + ")") + ", " +
       std::to_string(spectrum.wavelength_nm.size()) +
       " wavelengths: CIE 1931 2°, 5 nm; CCT and Duv by Ohno 2014.</p>\n";
  return h;
}

std::string ledger_html(const nlohmann::json& r) {
  const auto num = [&](const char* key) {
    return r.contains(key) && r[key].is_number() ? r[key].get<double>() : photometry::kNaN;
  };
  const double emitted = num("emitted_lm");
  std::string t = "<table>";
  for (const auto& [key, label] : {std::pair{"emitted_lm", "emitted"},
                                   {"escaped_lm", "escaped (the photometry)"},
                                   {"absorbed_lm", "absorbed in the luminaire"},
                                   {"cutoff_lm", "cut off by the bounce limit"}}) {
    const double v = num(key);
    t += "<tr><th class=l>" + std::string(label) + "</th><td>" + fmt(v, 2) + " lm</td><td>" +
         (emitted > 0 ? pct(v / emitted, 2) : "–") + "</td></tr>\n";
  }
  t += "</table>";
  // Spectral runs: the same books in watts (report.json's "radiant").
  if (r.contains("radiant") && r["radiant"].is_object()) {
    const nlohmann::json& w = r["radiant"];
    const auto watts = [&](const char* key) {
      return w.contains(key) && w[key].is_number() ? w[key].get<double>() : photometry::kNaN;
    };
    const double emitted_w = watts("emitted_w");
    t += "<table class=radiant>";
    for (const auto& [key, label] : {std::pair{"emitted_w", "emitted (radiant)"},
                                     {"escaped_w", "escaped (radiant)"},
                                     {"absorbed_w", "absorbed (radiant)"},
                                     {"cutoff_w", "cut off (radiant)"}}) {
      const double v = watts(key);
      t += "<tr><th class=l>" + std::string(label) + "</th><td>" + fmt(v, 4) + " W</td><td>" +
           (emitted_w > 0 ? pct(v / emitted_w, 2) : "–") + "</td></tr>\n";
    }
    t += "</table><p class=note>Radiant power over 360–830 nm from each photon's wavelength and its emitter's "
         "spectrum (docs/methods.md, \"Radiant books\").</p>";
  }
  if (r.contains("photons_emitted"))
    t += "<p class=note>" + esc(r["photons_emitted"].dump()) + " photons" +
         (r.contains("seed") ? ", seed " + esc(r["seed"].dump()) : std::string()) + ".</p>";
  if (r.contains("near_field") && r["near_field"].is_array()) {
    t += "<h2>Near field</h2>\n<table><tr><th>distance</th><th>on axis (centre pixel, 4D/41 wide)</th><th>far field predicts</th>"
         "<th>largest deviation (pixels, E &ge; 10 % of max)</th><th>cells (4D/21): largest |&delta;|, bound</th>"
         "<th>verdict</th></tr>\n";
    for (const auto& p : r["near_field"]) {
      const auto val = [&](const char* key) {
        return p.contains(key) && p[key].is_number() ? p[key].get<double>() : photometry::kNaN;
      };
      t += "<tr><td>" + fmt(val("distance_m"), 3) + " m</td><td>" + fmt(val("on_axis_lx"), 3) + " lx</td><td>" +
           fmt(val("far_field_on_axis_lx"), 3) + " lx</td><td>" + fmt(val("max_deviation_pct"), 2) + " %</td><td>" +
           fmt(val("cell_deviation_pct"), 2) + " %, " + fmt(val("upper_bound_pct"), 2) + " %</td><td class=l>" +
           esc(p.value("verdict", std::string("–"))) + "</td></tr>\n";
    }
    t += "</table>\n";
    const bool known = r.contains("far_field_distance_m") && r["far_field_distance_m"].is_number();
    std::string why = "not reached at the distances simulated";
    if (!known && r.contains("far_field_distance") && r["far_field_distance"].is_object()) {
      const nlohmann::json& f = r["far_field_distance"];
      if (f.value("farthest", std::string()) == "undecided")
        why = "undecided: too few photons to tell at the farthest plane (about " +
              fmt(f.value("photons_to_tell", photometry::kNaN) / 1e6, 0) + " million would)";
      else if (f.value("farthest", std::string()) == "fails")
        why = "beyond the farthest plane (it deviates by more than 1 %)";
    }
    t += "<p>Far-field distance: " + (known ? fmt(r["far_field_distance_m"].get<double>(), 3) + " m" : why) +
         " (from the photometric centre, the luminous centre of the light heading down; a plane passes when every "
         "cell where E &ge; 10 % of its maximum is within 1 % of the far field's prediction at 95 % confidence, "
         "photon noise counted).</p>\n";
  }
  return t + "\n";
}

// A luminance image's thumbnail (report.json's, row-major cd/m²) as an
// inline SVG heat map over two decades below the 99th percentile of its lit
// cells (a bare lamp's cell clips to white rather than darken the rest).
std::string thumbnail_svg(const nlohmann::json& thumb) {
  if (!thumb.is_object() || !thumb.contains("size") || !thumb.contains("cd_m2")) return {};
  const int n = thumb["size"].get<int>();
  const nlohmann::json& v = thumb["cd_m2"];
  if (n <= 0 || !v.is_array() || v.size() != static_cast<std::size_t>(n) * static_cast<std::size_t>(n)) return {};
  std::vector<double> lit;
  for (const auto& x : v)
    if (x.is_number() && x.get<double>() > 0.0) lit.push_back(x.get<double>());
  double vmax = 0.0;
  if (!lit.empty()) {
    const std::size_t k = static_cast<std::size_t>(0.99 * static_cast<double>(lit.size() - 1));
    std::nth_element(lit.begin(), lit.begin() + static_cast<std::ptrdiff_t>(k), lit.end());
    vmax = lit[k];
  }
  constexpr int px = 4;
  std::string svg = "<svg xmlns='http://www.w3.org/2000/svg' width='" + std::to_string(n * px) + "' height='" +
                    std::to_string(n * px) + "' viewBox='0 0 " + std::to_string(n) + " " + std::to_string(n) +
                    "' shape-rendering='crispEdges'><rect width='100%' height='100%' fill='" + heat(0.0) + "'/>";
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const auto& c = v[static_cast<std::size_t>(y) * static_cast<std::size_t>(n) + static_cast<std::size_t>(x)];
      if (!c.is_number() || !(c.get<double>() > 0.0) || !(vmax > 0.0)) continue;
      svg += "<rect x='" + std::to_string(x) + "' y='" + std::to_string(y) + "' width='1' height='1' fill='" +
             heat(std::min(1.0, c.get<double>() / vmax)) + "'/>";
    }
  return svg + "</svg>";
}

// Luminance images and CIE 232:2019's glare figures of a simulation
// (report.json's "luminance_images" and "cie232"), with the UGR table's
// 4H × 8H room (70/50/20) corrected by the largest ΔUGR.
std::string luminance_html(const nlohmann::json& r, const photometry::UgrTable& ugr) {
  if (!r.contains("luminance_images") || !r["luminance_images"].is_array() || r["luminance_images"].empty()) return {};
  std::string t = "<h2>Luminance images and glare of a non-uniform source (CIE 232:2019)</h2>\n<div class=grid>";
  const auto num = [](const nlohmann::json& o, const char* key) {
    return o.is_object() && o.contains(key) && o[key].is_number() ? o[key].get<double>() : photometry::kNaN;
  };
  for (const auto& img : r["luminance_images"]) {
    t += "<div>" + thumbnail_svg(img.value("thumbnail", nlohmann::json())) + "<p class=note>C " +
         fmt(num(img, "c_deg"), 0) + "°, γ " + fmt(num(img, "gamma_deg"), 0) + "°: max " + fmt(num(img, "max_cd_m2"), 0) +
         " cd/m², I " + fmt(num(img, "intensity_cd"), 1) + " cd<br>" + esc(img.value("file", std::string())) + "</p></div>";
  }
  t += "</div>\n<table><tr><th>view</th><th>I</th><th>A<sub>p</sub></th><th>L<sub>s</sub> = I/A<sub>p</sub></th>"
       "<th>A<sub>p,eff</sub></th><th>L<sub>eff</sub></th><th>k²</th><th>ΔUGR</th></tr>\n";
  for (const auto& img : r["luminance_images"]) {
    const nlohmann::json g = img.value("cie232", nlohmann::json());
    t += "<tr><td class=l>C " + fmt(num(img, "c_deg"), 0) + "°, γ " + fmt(num(img, "gamma_deg"), 0) + "°</td>";
    if (!g.is_object() || !g.value("defined", false)) {
      t += "<td class=l colspan=7>not defined — " + esc(g.is_object() ? g.value("why_undefined", std::string()) : "") +
           "</td></tr>\n";
      continue;
    }
    t += "<td>" + fmt(num(g, "intensity_cd"), 1) + " cd</td><td>" + fmt(num(g, "projected_area_m2") * 1e4, 1) +
         " cm²</td><td>" + fmt(num(g, "mean_luminance_cd_m2"), 0) + " cd/m²</td><td>" +
         fmt(num(g, "glare_area_m2") * 1e4, 1) + " cm²</td><td>" + fmt(num(g, "glare_luminance_cd_m2"), 0) +
         " cd/m²</td><td>" + fmt(num(g, "k2"), 2) + "</td><td>" + fmt(num(g, "delta_ugr"), 1) + "</td></tr>\n";
  }
  t += "</table>\n";
  const nlohmann::json c = r.value("cie232", nlohmann::json());
  const double delta = num(c, "delta_ugr");
  if (std::isfinite(delta)) {
    t += "<p>Largest ΔUGR = 8 log<sub>10</sub> k² over the views: " + fmt(delta, 1) + ".";
    if (ugr.defined)
      for (const photometry::UgrRoom& room : ugr.rooms)
        if (room.x_h == 4.0 && room.y_h == 8.0)
          t += " UGR of the 4H × 8H room (70/50/20) crosswise " + fmt(room.crosswise[0], 1) + " → " +
               fmt(room.crosswise[0] + delta, 1) + ", endwise " + fmt(room.endwise[0], 1) + " → " +
               fmt(room.endwise[0] + delta, 1) + " (every value of the table moves by ΔUGR).";
    t += "</p>\n";
  }
  t += "<p class=note>Each image: the luminaire seen from a direction at infinity (orthographic), luminance averaged "
       "over a cone of " + fmt(num(r["luminance_images"][0], "cone_deg"), 1) +
       "° half-angle and connected from every diffuse and glossy surface. CIE 232:2019: the image filtered by a "
       "Gaussian of 12 mm full width at half maximum (the eye's resolution), the glare source where it reaches "
       "500 cd/m² (area A<sub>p,eff</sub>, mean L<sub>eff</sub>), k² = L<sub>eff</sub>² A<sub>p,eff</sub> "
       "A<sub>p</sub> / I², the UGR corrected by 8 log<sub>10</sub> k² (A<sub>p</sub> the luminous area of the "
       "UGR table). Views 25° and 40° above the luminaire's plane (γ 65° and 50°) in C0 and C90.</p>\n";
  return t;
}

Result<std::string> entry_html(const DatasheetEntry& e, const DatasheetOptions& o) {
  const photometry::Distribution& d = e.distribution;
  if (Status s = photometry::validate(d); !s.ok()) {
    Error err = s.error();
    err.where.file = e.source;
    return err;
  }
  const photometry::Summary s = photometry::summarize(d);
  const photometry::PlanningFigures p = photometry::planning_figures(d, o.floor_reflectance, o.ugr);
  const std::vector<photometry::MethodLabel> labels = photometry::method_labels(p);
  const auto method = [&](const char* key) {
    for (const photometry::MethodLabel& m : labels)
      if (m.key == key)
        return "<p class=note>Method: " + esc(m.method) + ". Convention: " + esc(m.convention) +
               ". Checked against: " + esc(m.checked_against) + ".</p>\n";
    return std::string();
  };
  const photometry::IntensitySampler sampler(d);
  std::string name = keyword(d, "LUMINAIRE");
  if (name.empty()) name = fs::path(e.source).filename().string();

  std::string h = "<section class=lum>\n<h1>" + esc(name) + "</h1>\n<table>\n";
  h += row("Source file", e.source);
  if (!e.format.empty()) h += row("Format", e.format);
  for (const auto& [key, label] : {std::pair{"MANUFAC", "Manufacturer"},
                                   {"LUMCAT", "Catalogue no."},
                                   {"LAMP", "Lamp"},
                                   {"TEST", "Test report"},
                                   {"TESTLAB", "Test lab"},
                                   {"ISSUEDATE", "Issue date"}})
    if (const std::string v = keyword(d, key); !v.empty()) h += row(label, v);
  if (e.simulation_report) h += row("Origin", "Gonio simulation of " + e.simulation_report->value("model", std::string("a model")));
  h += row("Photometry", d.absolute ? "absolute" : "relative (rated lamp flux " + fmt(s.rated_lamp_flux_lm, 0) + " lm)");
  h += row("Luminaire flux", fmt(s.flux_lm, 1) + " lm");
  if (s.lor_defined) h += row("LOR", pct(s.lor, 1));
  h += row("DFF / ULOR", pct(s.dff, 1) + " / " + (s.flux_lm > 0 ? pct(s.upward_flux_lm / s.flux_lm, 1) : "–"));
  h += row("Input power", std::isfinite(s.input_power_w) ? fmt(s.input_power_w, 1) + " W" : "unknown");
  h += row("Efficacy", std::isfinite(s.efficacy_lm_per_w) ? fmt(s.efficacy_lm_per_w, 1) + " lm/W" : "– (input power unknown)");
  h += row("Maximum intensity", fmt(s.max_intensity_cd, 1) + " cd at C " + fmt(s.max_c_deg, 1) + "°, γ " + fmt(s.max_gamma_deg, 1) + "°");
  h += row("Beam angle C0-C180 / C90-C270", fmt(s.beam_c0_c180.angle_deg, 1) + "° / " + fmt(s.beam_c90_c270.angle_deg, 1) + "°");
  h += row("Field angle C0-C180 / C90-C270", fmt(s.field_c0_c180.angle_deg, 1) + "° / " + fmt(s.field_c90_c270.angle_deg, 1) + "°");
  h += row("CIE flux code", photometry::to_string(s.cie_flux_code));
  h += row("BUG rating (TM-15-11)", photometry::to_string(p.bug));
  h += row("Spacing criterion C0-C180 / C90-C270 / diagonal",
           sc_text(p.spacing.c0_c180) + " / " + sc_text(p.spacing.c90_c270) + " / " + sc_text(p.spacing.diagonal));
  h += "</table>\n";

  h += "<h2>Intensity distribution</h2>\n";
  {
    // Types A and B are drawn from their Type C resampling (as gonio plot does).
    Result<photometry::Distribution> c = d.type == photometry::PhotometricType::C
                                             ? Result<photometry::Distribution>(d)
                                             : photometry::to_type_c(d);
    if (!c.ok()) return c.error();
    Result<Figure> fig = intensity_diagram(c.value(), DiagramOptions{});
    if (!fig.ok()) return fig.error();
    fig.value().width_px = 900;
    fig.value().height_px = 420;
    Result<std::string> svg = render_figure(fig.value(), ImageFormat::Svg);
    if (!svg.ok()) return svg.error();
    h += "<div class=svg>" + inline_svg(svg.value()) + "</div>\n";
  }

  const double mh = o.mounting_height_m;
  h += "<h2>Cone diagram and isolux on the floor</h2>\n<div class=grid><div><table><tr><th>height</th><th>E nadir</th><th>⌀ beam C0-C180</th><th>⌀ beam C90-C270</th></tr>\n";
  const double i0 = sampler.cd(0, 0);
  for (int k = 1; k <= 6; ++k) {
    const double z = mh * k / 3.0;
    const auto dia = [&](const photometry::BeamSpread& b) {
      return std::isfinite(b.angle_deg) && b.angle_deg < 179 ? fmt(2 * z * std::tan(b.angle_deg / 2 * kDeg), 2) + " m" : std::string("–");
    };
    h += "<tr><td>" + fmt(z, 2) + " m</td><td>" + fmt(i0 / (z * z), 1) + " lx</td><td>" + dia(s.beam_c0_c180) +
         "</td><td>" + dia(s.beam_c90_c270) + "</td></tr>\n";
  }
  double emax = 0.0;
  const std::string iso = isolux_svg(sampler, mh, &emax);
  h += "</table><p class=note>Beam diameters from the 50 % beam angles; illuminance at the nadir I(0)/h².</p></div>\n<div>" + iso +
       "<p class=note>Horizontal illuminance on the floor " + fmt(mh, 2) + " m below the luminaire, ±" + fmt(2 * mh, 1) +
       " m; maximum " + fmt(emax, 1) + " lx.</p></div></div>\n";

  h += "<h2>Zonal lumen summary</h2>\n<div class=grid>" + zones_table(s) + "</div>\n";
  h += "<h2>UGR table</h2>\n" + ugr_html(p.ugr) + method("ugr_table");
  h += "<h2>Coefficients of utilisation</h2>\n" + cu_html(p.cu) + method("cu_table");
  h += "<h2>Spacing criterion (IES)</h2>\n<table>" + row("C0-C180", sc_text(p.spacing.c0_c180)) +
       row("C90-C270", sc_text(p.spacing.c90_c270)) + row("diagonal (square array side)", sc_text(p.spacing.diagonal)) + "</table>\n" +
       method("spacing_criterion");
  const auto& z = p.bug.zones_lm;
  h += "<h2>BUG rating " + photometry::to_string(p.bug) + "</h2>\n<table><tr><th></th><th>L 0–30°</th><th>M 30–60°</th><th>H 60–80°</th><th>VH 80–90°</th></tr>\n";
  h += "<tr><th>front (C0–C180)</th><td>" + fmt(z.fl, 0) + "</td><td>" + fmt(z.fm, 0) + "</td><td>" + fmt(z.fh, 0) + "</td><td>" + fmt(z.fvh, 0) + "</td></tr>\n";
  h += "<tr><th>back (C180–C360)</th><td>" + fmt(z.bl, 0) + "</td><td>" + fmt(z.bm, 0) + "</td><td>" + fmt(z.bh, 0) + "</td><td>" + fmt(z.bvh, 0) + "</td></tr>\n";
  h += "<tr><th>uplight</th><td colspan=2>UL 90–100°: " + fmt(z.ul, 0) + "</td><td colspan=2>UH 100–180°: " + fmt(z.uh, 0) + "</td></tr></table>\n<p class=note>Luminaire lumens per zone (IES TM-15-11 with Addendum A); glare table of " + photometry::to_string(p.bug.glare_table) + ".</p>\n" + method("bug");
  h += "<h2>Luminance table</h2>\n";
  if (p.luminance.defined) {
    h += "<table><tr><th>γ</th><th>C0 cd/m²</th><th>C90 cd/m²</th><th>C0, bottom only</th><th>C90, bottom only</th></tr>\n";
    for (std::size_t g = 0; g < p.luminance.gamma_deg.size(); ++g)
      h += "<tr><td>" + fmt(p.luminance.gamma_deg[g], 0) + "°</td><td>" + fmt(p.luminance.cd_m2[0][g], 0) + "</td><td>" +
           fmt(p.luminance.cd_m2[1][g], 0) + "</td><td>" + fmt(p.luminance.ldt_cd_m2[0][g], 0) + "</td><td>" +
           fmt(p.luminance.ldt_cd_m2[1][g], 0) + "</td></tr>\n";
    h += "</table>\n";
  } else {
    h += "<p>Not defined — " + esc(p.luminance.why_undefined) + ".</p>\n";
  }
  h += method("luminance_table");
  if ((!e.simulation_report || !e.simulation_report->contains("colour")) && !d.spectra.empty())
    h += spectrum_colour_html(d.spectra.front());
  if (e.simulation_report) {
    Result<std::string> colour = colour_html(*e.simulation_report);
    if (!colour.ok()) return colour.error();
    h += colour.value();
    h += luminance_html(*e.simulation_report, p.ugr);
    h += "<h2>Energy ledger of the simulation</h2>\n" + ledger_html(*e.simulation_report);
  }
  h += "<h2>Candela table</h2>\n" + candela_table(d);
  return h + "</section>\n";
}

std::string lower_ext(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

}  // namespace

Result<std::string> tolerance_yield_html(const nlohmann::json& report, const std::string& source) {
  using nlohmann::json;
  const auto lacks = [&](const std::string& what) {
    return make_error(source, "not a gonio tolerance report.json (" + what + ")");
  };
  if (!report.is_object()) return lacks("not a JSON object");
  const json* mc = report.contains("monte_carlo") ? &report["monte_carlo"] : nullptr;
  if (!mc || !mc->is_object() || !mc->contains("trials") || !(*mc)["trials"].is_array() || !mc->contains("yield") ||
      !(*mc)["yield"].is_object())
    return lacks("no monte_carlo.trials and monte_carlo.yield");
  if (!report.contains("nominal") || !report["nominal"].is_object()) return lacks("no nominal figures");
  const json& trials = (*mc)["trials"];
  const json& yield = (*mc)["yield"];
  const json settings = report.value("settings", json::object());
  const auto number = [](const json& v) {
    return v.is_number() ? v.get<double>() : std::numeric_limits<double>::quiet_NaN();
  };
  std::string h = "<section class=tolerance>\n<h2>Tolerance yield</h2>\n<p>" +
                  esc(report.value("model", std::string("the model"))) + ": " + std::to_string(trials.size()) +
                  " Monte Carlo trials (Latin hypercube, every tolerance drawn at once), " +
                  format_number(number(settings.value("photons", json()))) + " photons per trace on common random numbers"
                  " (seed " + format_number(number(settings.value("seed", json()))) + "); from " + esc(source) +
                  " (gonio tolerance, docs/tolerance.md).</p>\n";
  if (yield.empty()) return h + "<p>No limits were given (--spec): no yield.</p>\n</section>\n";
  h += "<table><tr><th>limit</th><th>nominal</th><th>trials min</th><th>trials max</th><th>within</th>"
       "<th>yield</th></tr>\n";
  for (const auto& [text, value] : yield.items()) {
    if (text == "all") continue;
    const std::string figure = text.substr(0, text.find_first_of("=<>"));
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    std::size_t within = 0;
    for (const json& t : trials) {
      const double v = t.contains("figures") ? number(t["figures"].value(figure, json())) : number(json());
      if (std::isfinite(v)) {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
      if (t.contains("limits") && t["limits"].value(text, false)) ++within;
    }
    h += "<tr><th class=l>" + esc(text) + "</th><td>" + esc(format_number(number(report["nominal"].value(figure, json())), 5)) +
         "</td><td>" + (std::isfinite(lo) ? esc(format_number(lo, 5)) : "–") + "</td><td>" +
         (std::isfinite(hi) ? esc(format_number(hi, 5)) : "–") + "</td><td>" + std::to_string(within) + " of " +
         std::to_string(trials.size()) + "</td><td>" + fmt(100.0 * number(value), 1) + " %</td></tr>\n";
  }
  if (yield.contains("all")) {
    std::size_t within = 0;
    for (const json& t : trials) within += t.value("in_spec", false) ? 1 : 0;
    h += "<tr><th class=l>all limits</th><td></td><td></td><td></td><td>" + std::to_string(within) + " of " +
         std::to_string(trials.size()) + "</td><td>" + fmt(100.0 * number(yield["all"]), 1) + " %</td></tr>\n";
  }
  return h + "</table>\n</section>\n";
}

Result<std::string> datasheet_html(const std::vector<DatasheetEntry>& entries, const DatasheetOptions& options) {
  if (entries.empty()) return error("a datasheet needs at least one luminaire");
  std::string html = "<!DOCTYPE html>\n<html lang=en><head><meta charset=\"utf-8\"><title>";
  std::string title;
  for (const auto& e : entries) title += (title.empty() ? "" : ", ") + fs::path(e.source).filename().string();
  html += esc(title) + " — Gonio datasheet</title><style>" + std::string(kStyle) + "</style></head><body>\n";
  for (const auto& e : entries) {
    Result<std::string> part = entry_html(e, options);
    if (!part.ok()) return part.error();
    html += part.value();
  }
  if (options.tolerance_report) {
    Result<std::string> yield = tolerance_yield_html(*options.tolerance_report, options.tolerance_source);
    if (!yield.ok()) return yield.error();
    html += yield.value();
  }
  html += "<p class=note>Written by Gonio. Methods: docs/methods.md, \"Light-planning figures\".</p>\n</body></html>\n";
  return html;
}

void make_pdf_deterministic(std::string& pdf) {
  // The dates: "/CreationDate (D:20261207132317+00'00')".
  std::string dated;
  if (const char* epoch = std::getenv("SOURCE_DATE_EPOCH"); epoch && *epoch) {
    char* end = nullptr;
    const long long seconds = std::strtoll(epoch, &end, 10);
    if (end && *end == '\0' && seconds >= 0) dated = format_utc(seconds, "D:%Y%m%d%H%M%S+00'00'");
  }
  for (const std::string_view key : {"/CreationDate (", "/ModDate ("}) {
    for (std::size_t at = pdf.find(key); at != std::string::npos; at = pdf.find(key, at + 1)) {
      const std::size_t value = at + key.size(), close = pdf.find(')', value);
      if (close == std::string::npos || close - value > 64) continue;
      if (!dated.empty() && close - value == dated.size()) {
        pdf.replace(value, dated.size(), dated);
      } else {
        std::fill(pdf.begin() + static_cast<std::ptrdiff_t>(at), pdf.begin() + static_cast<std::ptrdiff_t>(close) + 1, ' ');
      }
    }
  }
  // The structure ids: Chromium names the tagged structure's elements by its
  // session's DOM node ids, whose order shifts from run to run (an element's
  // id may fall above its neighbour's in one run and below it in the next),
  // while the objects they name are laid out the same way every time. So the
  // ids are renumbered by the objects they name in the ID tree (/IDTree's
  // /Names: "(id) N 0 R" pairs sorted by id): 0 up in the order of the
  // objects, each in its old width. The tree's pairs are then put back in the
  // order of the new ids (the same pairs, so the same length and offsets)
  // and its /Limits name the first and the last.
  constexpr std::string_view kNode = "(node";
  const auto parse_id = [&pdf, kNode](std::size_t at, std::size_t* digits, unsigned long long* value) {
    // at: the '(' of "(node"; true for "(node" + 1 to 19 digits + ")".
    if (pdf.compare(at, kNode.size(), kNode) != 0) return false;
    std::size_t end = at + kNode.size();
    unsigned long long v = 0;
    while (end < pdf.size() && end - at - kNode.size() < 19 && std::isdigit(static_cast<unsigned char>(pdf[end])))
      v = v * 10 + static_cast<unsigned long long>(pdf[end++] - '0');
    *digits = end - at - kNode.size();
    *value = v;
    return *digits > 0 && end < pdf.size() && pdf[end] == ')';
  };
  const std::size_t names = pdf.find("/Names [(node");
  if (names == std::string::npos || pdf.find("/Names [(node", names + 1) != std::string::npos) return;
  struct Pair {
    unsigned long long id;
    std::size_t digits;
    unsigned long long object;
    std::string text;  // "(nodeX) N 0 R"
  };
  std::vector<Pair> pairs;
  const std::size_t first = names + std::string_view("/Names [").size();
  std::size_t at = first;
  for (;;) {
    Pair q{};
    if (!parse_id(at, &q.digits, &q.id)) return;
    std::size_t end = at + kNode.size() + q.digits + 1;
    if (end >= pdf.size() || pdf[end] != ' ') return;
    std::size_t num = end + 1;
    while (num < pdf.size() && std::isdigit(static_cast<unsigned char>(pdf[num])))
      q.object = q.object * 10 + static_cast<unsigned long long>(pdf[num++] - '0');
    if (num == end + 1 || pdf.compare(num, 4, " 0 R") != 0) return;
    end = num + 4;
    q.text = pdf.substr(at, end - at);
    pairs.push_back(std::move(q));
    if (end < pdf.size() && pdf[end] == ']') break;
    if (end >= pdf.size() || pdf[end] != ' ') return;
    at = end + 1;
  }
  const std::size_t last = at + pairs.back().text.size();  // the ']'
  std::vector<Pair> by_object = pairs;
  std::stable_sort(by_object.begin(), by_object.end(),
                   [](const Pair& x, const Pair& y) { return x.object < y.object; });
  std::map<unsigned long long, std::string> renamed;  // old id → new digits
  for (std::size_t k = 0; k < by_object.size(); ++k) {
    std::string n = std::to_string(k);
    if (n.size() > by_object[k].digits || !renamed.emplace(by_object[k].id, std::string()).second) return;
    n.insert(0, by_object[k].digits - n.size(), '0');
    renamed[by_object[k].id] = n;
  }
  // Every "(nodeX)" of the file that the tree names.
  for (std::size_t p = pdf.find(kNode); p != std::string::npos; p = pdf.find(kNode, p + 1)) {
    std::size_t digits = 0;
    unsigned long long value = 0;
    if (!parse_id(p, &digits, &value)) continue;
    const auto r = renamed.find(value);
    if (r != renamed.end() && r->second.size() == digits) pdf.replace(p + kNode.size(), digits, r->second);
  }
  // The tree's pairs in the order of their new ids: the order of the objects.
  std::string sorted;
  for (const Pair& q : by_object) {
    if (!sorted.empty()) sorted += ' ';
    sorted += "(node" + renamed[q.id] + q.text.substr(kNode.size() + q.digits);
  }
  if (sorted.size() == last - first) pdf.replace(first, sorted.size(), sorted);
  // "/Limits [(first) (last)]" of the same node of the tree.
  const std::size_t limits = pdf.rfind("/Limits [(node", names);
  if (limits != std::string::npos && names - limits < 128) {
    const std::size_t lo = limits + std::string_view("/Limits [").size();
    std::size_t lo_digits = 0, hi_digits = 0;
    unsigned long long lo_value = 0, hi_value = 0;
    if (parse_id(lo, &lo_digits, &lo_value)) {
      const std::size_t hi = lo + kNode.size() + lo_digits + 2;
      if (parse_id(hi, &hi_digits, &hi_value)) {
        const std::string& a = renamed[by_object.front().id];
        const std::string& b = renamed[by_object.back().id];
        if (a.size() == lo_digits) pdf.replace(lo + kNode.size(), lo_digits, a);
        if (b.size() == hi_digits) pdf.replace(hi + kNode.size(), hi_digits, b);
      }
    }
  }
}

Result<std::string> html_to_pdf(const std::string& html) {
  ScratchDir dir("gonio-pdf");
  if (dir.path().empty()) return error("cannot create a scratch directory for the PDF");
  const std::string in = (dir.path() / "sheet.html").string();
  const std::string out = (dir.path() / "sheet.pdf").string();
  {
    std::ofstream f(in, std::ios::binary);
    f << html;
    if (!f) return error("cannot write " + in);
  }
  const char* env = std::getenv("GONIO_CHROMIUM");
  const std::string program = env && *env ? env : "chromium";
  Result<ProcessOutput> run = run_program(
      {program, "--headless", "--no-sandbox", "--disable-gpu", "--no-pdf-header-footer",
       "--user-data-dir=" + (dir.path() / "profile").string(), "--print-to-pdf=" + out, "file://" + in},
      std::chrono::seconds(120), 1u << 20,
      "PDF datasheets need a headless Chromium, Debian package chromium (scripts/setup.sh installs it), "
      "or $GONIO_CHROMIUM naming the program");
  if (!run.ok()) return run.error();
  Result<std::string> pdf = read_file(out, 256u << 20);
  if (run.value().exit_code != 0 || !pdf.ok() || pdf.value().rfind("%PDF", 0) != 0)
    return error(program + " did not print the PDF" +
                 (run.value().err.empty() ? std::string() : ": " + last_lines(run.value().err, 400)));
  make_pdf_deterministic(pdf.value());
  return pdf;
}

Status write_datasheet(const std::string& path, const std::vector<DatasheetEntry>& entries,
                       const DatasheetOptions& options) {
  const std::string ext = lower_ext(path);
  if (ext != ".html" && ext != ".htm" && ext != ".pdf") {
    Error e;
    e.where.file = path;
    e.message = "cannot tell the datasheet format: the name must end in .html or .pdf";
    return e;
  }
  Result<std::string> html = datasheet_html(entries, options);
  if (!html.ok()) return html.error();
  if (ext == ".pdf") {
    Result<std::string> pdf = html_to_pdf(html.value());
    if (!pdf.ok()) {
      Error e = pdf.error();
      if (e.where.file.empty()) e.where.file = path;
      return e;
    }
    return write_file_atomic(path, pdf.value());
  }
  return write_file_atomic(path, html.value());
}

}  // namespace gonio::io
