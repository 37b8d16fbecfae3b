#include "io/outputs/colour_chart.h"

#include <limits>

#include "photometry/colour.h"
#include "photometry/format.h"

namespace gonio::io {

Result<Figure> colour_over_angle_chart(const std::vector<ColourCurve>& curves, const std::string& title,
                                       double delta_uv_max) {
  if (curves.empty()) return make_error("a colour-over-angle chart needs at least one C-plane");
  LineChart cct{"CCT over gamma", "gamma [deg]", "CCT [K]", false, false, 0.0, 180.0, {}, {}, true, {}};
  LineChart duv{"Delta u'v' from the mean (max " + format_number(delta_uv_max, 3) + " over >= 10 % of the peak)",
                "gamma [deg]", "Delta u'v'", false, false, 0.0, 180.0, 0.0, {}, true, {}};
  const LineStyle styles[] = {LineStyle::Solid, LineStyle::Dashed, LineStyle::Dotted, LineStyle::Solid};
  for (std::size_t i = 0; i < curves.size(); ++i) {
    const ColourCurve& c = curves[i];
    if (c.cct_k.size() != c.gamma_deg.size() || c.delta_uv.size() != c.gamma_deg.size())
      return make_error("colour curve C" + format_number(c.c_deg) + ": gamma, CCT and delta u'v' lists differ in length");
    const std::string label = "C" + format_number(c.c_deg);
    cct.series.push_back({label, c.gamma_deg, c.cct_k, styles[i % 4], i >= 3});
    duv.series.push_back({label, c.gamma_deg, c.delta_uv, styles[i % 4], i >= 3});
  }
  Figure f;
  f.title = title;
  f.charts = {cct, duv};
  return f;
}

std::vector<ColourCurve> colour_curves(const nlohmann::json& coa) {
  const auto value = [](const nlohmann::json& j) {
    return j.is_number() ? j.get<double>() : std::numeric_limits<double>::quiet_NaN();
  };
  std::vector<ColourCurve> curves;
  if (!coa.is_object() || !coa.contains("planes") || !coa["planes"].is_array()) return curves;
  const photometry::UvPrime mean{value(coa.value("mean_u_prime", nlohmann::json())),
                                 value(coa.value("mean_v_prime", nlohmann::json()))};
  for (const nlohmann::json& p : coa["planes"]) {
    ColourCurve cc;
    cc.c_deg = value(p.value("c_deg", nlohmann::json()));
    const nlohmann::json g = p.value("gamma_deg", nlohmann::json::array()), u = p.value("u_prime", g),
                         v = p.value("v_prime", g), t = p.value("cct_k", g);
    if (u.size() != g.size() || v.size() != g.size() || t.size() != g.size()) continue;
    for (std::size_t i = 0; i < g.size(); ++i) {
      cc.gamma_deg.push_back(value(g[i]));
      cc.cct_k.push_back(value(t[i]));
      cc.delta_uv.push_back(photometry::delta_uv_prime({value(u[i]), value(v[i])}, mean));
    }
    curves.push_back(std::move(cc));
  }
  return curves;
}

}  // namespace gonio::io
