#include "io/outputs/colour_chart.h"

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

}  // namespace gonio::io
