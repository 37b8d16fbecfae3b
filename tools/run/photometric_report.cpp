#include "tools/run/photometric_report.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "tools/run/json_figures.h"

namespace gonio::app {
namespace {

using json = OrderedJson;
using photometry::BeamSpread;
using photometry::Distribution;
using photometry::Summary;

const auto number = json_number<json>;

}  // namespace

std::optional<double> even_step_deg(const std::vector<double>& a) {
  if (a.size() < 2) return std::nullopt;
  const double step = (a.back() - a.front()) / static_cast<double>(a.size() - 1);
  for (std::size_t i = 1; i < a.size(); ++i)
    if (std::abs(a[i] - a[i - 1] - step) > 1e-6) return std::nullopt;
  return step;
}

RayExtent ray_extent(const io::Tm25RaySet& set) {
  RayExtent e;
  for (std::size_t i = 0; i < set.ray_count(); ++i) {
    const Vec3 p = set.position_mm(i);
    if (i == 0) e.lo = e.hi = p;
    e.lo = {std::min(e.lo.x, p.x), std::min(e.lo.y, p.y), std::min(e.lo.z, p.z)};
    e.hi = {std::max(e.hi.x, p.x), std::max(e.hi.y, p.y), std::max(e.hi.z, p.z)};
  }
  return e;
}

const char* spectrum_text(io::Tm25Spectrum s) {
  switch (s) {
    case io::Tm25Spectrum::None: return "none";
    case io::Tm25Spectrum::SingleWavelength: return "one wavelength";
    case io::Tm25Spectrum::PerRayWavelength: return "a wavelength per ray";
    case io::Tm25Spectrum::OneTable: return "one spectral table for all rays";
    case io::Tm25Spectrum::TablePerRay: return "a spectral table per ray";
  }
  return "?";
}

json ray_set_json(const io::Tm25RaySet& set) {
  const io::Tm25Header& h = set.header;
  const RayExtent e = ray_extent(set);
  return {{"rays", set.ray_count()},
          {"measured", h.creation_method == 1},
          {"flux_per_ray", set.columns.tri_y >= 0 ? "luminous" : "radiant"},
          {"rays_flux_lm", json_number<json>(set.total_luminous_flux_lm())},
          {"rays_radiant_flux_w", json_number<json>(set.total_radiant_flux_w())},
          {"header_flux_lm", json_number<json>(h.luminous_flux_lm)},
          {"header_radiant_flux_w", json_number<json>(h.radiant_flux_w)},
          {"extent_mm", {{"min", {e.lo.x, e.lo.y, e.lo.z}}, {"max", {e.hi.x, e.hi.y, e.hi.z}}}},
          {"spectrum", spectrum_text(h.spectrum)},
          {"created", h.created}};
}

namespace {

json grid_json(const std::vector<double>& a) {
  const auto step = even_step_deg(a);
  return {{"count", a.size()},
          {"first_deg", a.front()},
          {"last_deg", a.back()},
          {"step_deg", step ? json(*step) : json(nullptr)},
          {"angles_deg", a}};
}

}  // namespace

json lamp_json(const photometry::LampSet& l) {
  return {{"count", l.count},
          {"type", l.type},
          {"flux_lm", number(l.flux_lm)},
          {"color", l.color},
          {"color_rendering", l.color_rendering},
          {"power_w", number(l.power_w)}};
}

namespace {

json beam_json(const BeamSpread& b) {
  return {{"angle_deg", number(b.angle_deg)},
          {"axis_deg", number(b.axis_deg)},
          {"lower_edge_deg", number(b.lower_edge_deg)},
          {"upper_edge_deg", number(b.upper_edge_deg)},
          {"lower_open", b.lower_open},
          {"upper_open", b.upper_open},
          {"max_cd", number(b.max_cd)},
          {"threshold_cd", number(b.threshold_cd)}};
}

json zones_json(const std::vector<photometry::Zone>& zones) {
  json out = json::array();
  for (const auto& z : zones)
    out.push_back({{"from_deg", z.from_deg}, {"to_deg", z.to_deg}, {"flux_lm", number(z.flux_lm)}});
  return out;
}

json values5(const std::array<double, 5>& v) {
  json a = json::array();
  for (double x : v) a.push_back(number(x));
  return a;
}

json spacing_json(const photometry::SpacingValue& v) {
  return v.ratio ? json(*v.ratio) : json(nullptr);
}

// The planning figures under the keys the issue fixed (ugr_table, cu_table,
// spacing_criterion, bug, luminance_table); an undefined one is null with a
// *_why key beside it.
}  // namespace

void put_planning(json& j, const photometry::PlanningFigures& p) {
  if (p.ugr.defined) {
    json u;
    u["background"] = photometry::to_string(p.ugr.background);
    u["spacing_h"] = p.ugr.spacing_h;
    u["reflectances"] = json::array();
    for (const auto& r : photometry::kUgrReflectances) u["reflectances"].push_back({r[0], r[1], r[2]});
    u["flux_lm"] = number(p.ugr.flux_lm);
    u["rooms"] = json::array();
    for (const auto& r : p.ugr.rooms)
      u["rooms"].push_back({{"x_h", r.x_h},
                            {"y_h", r.y_h},
                            {"crosswise", values5(r.crosswise)},
                            {"endwise", values5(r.endwise)}});
    j["ugr_table"] = u;
  } else {
    j["ugr_table"] = nullptr;
    j["ugr_table_why"] = p.ugr.why_undefined;
  }
  if (p.cu.defined) {
    json c;
    c["floor_reflectance"] = p.cu.floor_reflectance;
    c["pairs"] = json::array();
    for (const auto& pr : photometry::kCuReflectancePairs) c["pairs"].push_back({pr[0], pr[1]});
    c["rcr"] = p.cu.rcr;
    c["values"] = json::array();
    for (const auto& row : p.cu.values) {
      json r = json::array();
      for (double v : row) r.push_back(number(v));
      c["values"].push_back(r);
    }
    c["reference_flux_lm"] = number(p.cu.reference_flux_lm);
    c["relative_to"] = p.cu.relative_to_lamps ? "rated_lamp_flux" : "luminaire_flux";
    j["cu_table"] = c;
  } else {
    j["cu_table"] = nullptr;
    j["cu_table_why"] = p.cu.why_undefined;
  }
  json sc = {{"c0_c180", spacing_json(p.spacing.c0_c180)},
             {"c90_c270", spacing_json(p.spacing.c90_c270)},
             {"diagonal", spacing_json(p.spacing.diagonal)}};
  for (const auto& [key, v] : {std::pair{"c0_c180_why", &p.spacing.c0_c180},
                               {"c90_c270_why", &p.spacing.c90_c270},
                               {"diagonal_why", &p.spacing.diagonal}})
    if (!v->ratio) sc[key] = v->why_undefined;
  j["spacing_criterion"] = sc;
  const auto& z = p.bug.zones_lm;
  j["bug"] = {{"b", p.bug.b},
              {"u", p.bug.u},
              {"g", p.bug.g},
              {"text", photometry::to_string(p.bug)},
              {"glare_table", photometry::to_string(p.bug.glare_table)},
              {"zones_lm",
               {{"bl", z.bl}, {"bm", z.bm}, {"bh", z.bh}, {"bvh", z.bvh},
                {"fl", z.fl}, {"fm", z.fm}, {"fh", z.fh}, {"fvh", z.fvh},
                {"ul", z.ul}, {"uh", z.uh}}}};
  if (p.luminance.defined) {
    json l;
    l["gamma_deg"] = p.luminance.gamma_deg;
    l["c_deg"] = p.luminance.c_deg;
    l["cd_m2"] = json::array();
    l["ldt_cd_m2"] = json::array();
    for (std::size_t c = 0; c < p.luminance.c_deg.size(); ++c) {
      json a = json::array(), b = json::array();
      for (std::size_t g = 0; g < p.luminance.gamma_deg.size(); ++g) {
        a.push_back(number(p.luminance.cd_m2[c][g]));
        b.push_back(number(p.luminance.ldt_cd_m2[c][g]));
      }
      l["cd_m2"].push_back(a);
      l["ldt_cd_m2"].push_back(b);
    }
    l["max_cd_m2"] = number(p.luminance.max_cd_m2);
    j["luminance_table"] = l;
  } else {
    j["luminance_table"] = nullptr;
    j["luminance_table_why"] = p.luminance.why_undefined;
  }
  json methods = json::object();
  for (const photometry::MethodLabel& m : photometry::method_labels(p))
    methods[m.key] = {{"figure", m.figure},
                      {"method", m.method},
                      {"convention", m.convention},
                      {"checked_against", m.checked_against}};
  j["methods"] = methods;
}

void put_summary(json& j, const Distribution& d, const Summary& s) {
  j["flux_lm"] = number(s.flux_lm);
  j["lor"] = number(s.lor);
  j["dff"] = number(s.dff);
  j["declared_lor_percent"] = number(d.declared_lor_percent);
  j["declared_dff_percent"] = number(d.declared_dff_percent);
  j["downward_flux_lm"] = number(s.downward_flux_lm);
  j["upward_flux_lm"] = number(s.upward_flux_lm);
  j["zones"] = zones_json(s.zones);
  j["zones_10deg"] = zones_json(s.zones_10deg);
  put_peak_and_spread(j, &s);
  j["beam"] = {{"c0_c180", beam_json(s.beam_c0_c180)}, {"c90_c270", beam_json(s.beam_c90_c270)}};
  j["field"] = {{"c0_c180", beam_json(s.field_c0_c180)}, {"c90_c270", beam_json(s.field_c90_c270)}};
  const auto& code = s.cie_flux_code;
  j["cie_flux_code"] = {{"n1", number(code.n1)}, {"n2", number(code.n2)},
                        {"n3", number(code.n3)}, {"n4", number(code.n4)},
                        {"n5", number(code.n5)}, {"text", photometry::to_string(code)}};
  j["input_power_w"] = number(s.input_power_w);
  j["efficacy_lm_per_w"] = number(s.efficacy_lm_per_w);
}

json finding_json(const Finding& f) {
  return {{"severity", to_string(f.severity)},
          {"code", f.code},
          {"message", f.message},
          {"line", f.where.line > 0 ? json(f.where.line) : json(nullptr)}};
}

json info_json(const std::string& path, const io::PhotometricFile& file, const Summary& s,
               const photometry::PlanningFigures& planning) {
  const Distribution& d = file.distribution;
  json j;
  j["file"] = path;
  j["format"] = io::to_string(file.format);
  j["version"] = file.ies_version    ? json(io::to_string(*file.ies_version))
                 : file.tm33_version ? json(io::to_string(*file.tm33_version))
                                     : json(nullptr);
  if (file.ray_set) j["ray_set"] = ray_set_json(*file.ray_set);
  j["photometric_type"] = photometry::to_string(d.type);
  j["symmetry"] = photometry::to_string(d.symmetry);
  j["ldt_type_indicator"] = d.ldt_type_indicator ? json(*d.ldt_type_indicator) : json(nullptr);
  j["vertical_angles"] = grid_json(d.vertical_deg);
  j["horizontal_angles"] = grid_json(d.horizontal_deg);
  j["absolute_photometry"] = d.absolute;
  j["lamps"] = json::array();
  for (const auto& l : d.lamps) j["lamps"].push_back(lamp_json(l));
  j["alternative_lamps"] = json::array();
  for (const auto& l : d.alternative_lamps) j["alternative_lamps"].push_back(lamp_json(l));
  j["rated_lamp_flux_lm"] = number(s.rated_lamp_flux_lm);
  j["ballast_factor"] = number(d.ballast_factor);
  j["luminous_opening"] = {{"shape", photometry::to_string(d.opening.shape)},
                           {"length_m", d.opening.length_m},
                           {"width_m", d.opening.width_m},
                           {"height_m", d.opening.height_m}};
  j["luminaire_dimensions"] = {{"length_m", number(d.luminaire.length_m)},
                               {"width_m", number(d.luminaire.width_m)},
                               {"height_m", number(d.luminaire.height_m)}};
  put_summary(j, d, s);
  put_planning(j, planning);
  j["keywords"] = json::array();
  for (const auto& k : d.keywords) j["keywords"].push_back({{"key", k.key}, {"value", k.value}});
  j["findings"] = json::array();
  for (const auto& f : file.findings) j["findings"].push_back(finding_json(f));
  return j;
}


nlohmann::json compare_json(const std::string& path_a, const io::PhotometricFile& a, const std::string& path_b,
                            const io::PhotometricFile& b, const photometry::Comparison& c,
                            const photometry::CompareOptions& options) {
  const double beam_a0 = photometry::beam_angle(a.distribution, 0.0).angle_deg;
  const double beam_a90 = photometry::beam_angle(a.distribution, 90.0).angle_deg;
  const double beam_b0 = photometry::beam_angle(b.distribution, 0.0).angle_deg;
  const double beam_b90 = photometry::beam_angle(b.distribution, 90.0).angle_deg;
  nlohmann::json j;
  j["a"] = {{"path", path_a}, {"format", io::format_label(a)}, {"flux_lm", c.flux_a_lm}};
  j["b"] = {{"path", path_b}, {"format", io::format_label(b)}, {"flux_lm", c.flux_b_lm}};
  j["grid"] = {{"c_step_deg", options.c_step_deg}, {"gamma_step_deg", options.gamma_step_deg}};
  j["normalized"] = options.normalize_flux;
  // Files on different angles are each interpolated onto the common grid.
  j["grids_differ"] = !photometry::same_angles(a.distribution, b.distribution);
  j["scale_b"] = c.scale;
  j["reference_cd"] = c.reference_cd;
  j["rms_relative"] = c.rms_relative;
  j["max_relative"] = c.max_relative;
  j["max_at"] = {{"c_deg", c.max_at_c_deg}, {"gamma_deg", c.max_at_gamma_deg}};
  j["flux_ratio"] = json_number(c.flux_ratio);
  j["flux_difference_lm"] = c.flux_b_lm - c.flux_a_lm;
  j["beam_angle_deg"] = {{"a", {{"c0_c180", json_number(beam_a0)}, {"c90_c270", json_number(beam_a90)}}},
                         {"b", {{"c0_c180", json_number(beam_b0)}, {"c90_c270", json_number(beam_b90)}}}};
  j["beam_difference_deg"] = {{"c0_c180", json_number(c.beam_difference_c0_c180_deg)},
                              {"c90_c270", json_number(c.beam_difference_c90_c270_deg)}};
  j["field_difference_deg"] = {{"c0_c180", json_number(c.field_difference_c0_c180_deg)},
                               {"c90_c270", json_number(c.field_difference_c90_c270_deg)}};
  return j;
}

}  // namespace gonio::app
