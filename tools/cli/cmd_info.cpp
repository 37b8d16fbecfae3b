// gonio info FILE [--json]: what a measured file holds and what follows from
// it, as an aligned table or one JSON object.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "photometry/format.h"
#include "photometry/planning.h"
#include "photometry/summary.h"
#include "tools/cli/cli.h"
#include "tools/cli/input_options.h"
#include "tools/cli/commands.h"
#include "tools/run/photometric_input.h"
#include "tools/run/photometric_report.h"

namespace gonio::cli {
namespace {

using json = app::OrderedJson;
using photometry::BeamSpread;
using photometry::Distribution;
using photometry::Summary;

constexpr const char* kDescription =
    "Prints what an IES LM-63 (.ies), EULUMDAT (.ldt), IES TM-33 (.xml) or GLDF\n"
    "(.gldf, each photometry inside) file (other names by their content) holds and\n"
    "what follows from it; of an IES TM-25 ray file (.tm25ray) its rays (count,\n"
    "flux, extent, spectrum) and its far field as a photometric file (the rays'\n"
    "directions binned by luminous flux, C every 5 deg, gamma every 2.5 deg, +z the\n"
    "nadir), and\n"
    "what follows from it: format and version, photometric type, symmetry, angle\n"
    "grid, lamp data,\n"
    "luminous opening, total luminous flux (solid-angle integral of the candela\n"
    "grid), light output ratio (LOR, relative photometry only), downward flux\n"
    "fraction (DFF), zonal flux, maximum intensity and its direction, beam (50 %) and\n"
    "field (10 %) angles in the C0-C180 and C90-C270 planes, CIE flux code, and\n"
    "efficacy where the input watts are known; and the light-planning figures: UGR\n"
    "table (CIE 190:2010 catalogue table: CIE 117 tabular method, CIE 190 rooms,\n"
    "reflectances and background luminance, S = 0.25H), coefficients of\n"
    "utilisation (IES zonal cavity method), IES spacing criterion, BUG rating\n"
    "(IES TM-15-11 Addendum A) and the luminance table, each with its method,\n"
    "convention and the outside reference it is checked against (\"Methods\";\n"
    "--json: \"methods\"; docs/methods.md). Reader warnings go\n"
    "to stderr as\n"
    "'gonio: FILE:LINE: warning: message [code]'.\n"
    "\n"
    "With --json, stdout is one JSON object; units are in the key names (flux_lm,\n"
    "max_cd, *_deg, *_m, *_w); lor and dff are fractions (0.85, not 85 %); null marks\n"
    "a value that is undefined (e.g. lor of absolute photometry, a beam angle where\n"
    "there is no beam); an undefined planning figure comes with a *_why key.\n"
    "\n"
    "Exit status: 0 success, 1 the file could not be read, 2 usage error.\n"
    "\n"
    "Examples:\n"
    "  gonio info samples/curves/downlight.ldt\n"
    "  gonio info lamp.ies --json";

// ------------------------------------------------------------ formatting

// The table's cells: format_fixed / format_number, "-" where not finite.
std::string fmt(double v, int decimals) {
  return std::isfinite(v) ? format_fixed(v, decimals) : "-";
}
std::string num(double v, int digits = 6) {
  return std::isfinite(v) ? format_number(v, digits) : "-";
}

std::string grid_text(const std::vector<double>& a) {
  std::string s = std::to_string(a.size()) + " (" + num(a.front());
  if (a.size() > 1) s += " to " + num(a.back());
  s += " deg";
  if (a.size() > 1) {
    const auto step = app::even_step_deg(a);
    s += step ? ", step " + num(*step) + " deg" : ", uneven steps";
  }
  return s + ")";
}

std::string lamp_text(const photometry::LampSet& l, bool absolute) {
  std::string s = std::to_string(l.count) + " x " + (l.type.empty() ? "lamp" : l.type);
  if (!absolute && std::isfinite(l.flux_lm)) s += ", " + num(l.flux_lm, 7) + " lm";
  if (std::isfinite(l.power_w) && l.power_w > 0.0) s += ", " + num(l.power_w) + " W";
  if (!l.color.empty()) s += ", colour " + l.color;
  if (!l.color_rendering.empty()) s += ", colour rendering " + l.color_rendering;
  return s;
}

std::string opening_text(const photometry::LuminousOpening& o) {
  using S = photometry::OpeningShape;
  std::string s = photometry::to_string(o.shape);
  const auto m = [](double v) { return num(v, 4); };
  switch (o.shape) {
    case S::Point:
      return s;
    case S::Circular:
    case S::Sphere:
      return s + ", diameter " + m(std::max(o.length_m, o.width_m)) + " m";
    case S::VerticalCylinder:
      return s + ", diameter " + m(std::max(o.length_m, o.width_m)) + " m, height " +
             m(o.height_m) + " m";
    default:
      break;
  }
  s += ", length " + m(o.length_m) + " m, width " + m(o.width_m) + " m";
  if (o.height_m > 0.0) s += ", height " + m(o.height_m) + " m";
  return s;
}

// The beam in the plane C = c_deg / c_deg + 180°; its axis as the half-plane
// and γ it lies in (beam.h measures it as a signed angle θ from the nadir).
std::string beam_text(const BeamSpread& b, double c_deg) {
  if (!std::isfinite(b.angle_deg)) return "none";
  std::string s = (b.lower_open || b.upper_open ? "at least " : "") + fmt(b.angle_deg, 1) + " deg";
  if (b.lower_open || b.upper_open) s += " (the data ends first)";
  if (std::abs(b.axis_deg) > 0.05) {
    const bool other_half = b.axis_deg < 0.0;
    s += ", axis at C " + fmt(other_half ? c_deg + 180.0 : c_deg, 0) + " gamma " +
         fmt(std::abs(b.axis_deg), 1) + " deg";
  }
  return s;
}

std::string percent(double fraction, int decimals = 1) {
  return std::isfinite(fraction) ? fmt(100.0 * fraction, decimals) + " %" : "-";
}

// One zone a line: "0-30 deg      512.3 lm   47.6 %".
std::string zones_text(const std::vector<photometry::Zone>& zones, double total_lm) {
  std::string out;
  for (const photometry::Zone& z : zones) {
    const std::string range = fmt(z.from_deg, 0) + "-" + fmt(z.to_deg, 0) + " deg";
    char buf[128];
    std::snprintf(buf, sizeof buf, "%-11s %10s lm %8s", range.c_str(), fmt(z.flux_lm, 1).c_str(),
                  total_lm > 0.0 ? percent(z.flux_lm / total_lm).c_str() : "-");
    out += (out.empty() ? "" : "\n") + std::string(buf);
  }
  return out;
}

// A two-column table, labels padded to one width; a value may span lines.
class Table {
 public:
  void row(std::string label, std::string value) {
    rows_.push_back({std::move(label), std::move(value)});
  }
  void print() const {
    std::size_t width = 0;
    for (const auto& r : rows_) width = std::max(width, r.first.size());
    for (const auto& r : rows_) {
      std::size_t start = 0;
      bool first = true;
      do {
        const std::size_t end = r.second.find('\n', start);
        const std::string part =
            r.second.substr(start, end == std::string::npos ? end : end - start);
        std::printf("%-*s  %s\n", static_cast<int>(width), first ? r.first.c_str() : "",
                    part.c_str());
        first = false;
        start = end == std::string::npos ? end : end + 1;
      } while (start != std::string::npos);
    }
  }

 private:
  std::vector<std::pair<std::string, std::string>> rows_;
};

std::string why_or(const std::string& why) { return "- (" + why + ")"; }

std::string sc_text(const photometry::SpacingValue& v) {
  return v.ratio ? fmt(*v.ratio, 2) : why_or(v.why_undefined);
}

// The planning figures as table rows (UGR 70/50/20 for the reference rooms;
// the full tables are in --json and the datasheet).
void planning_rows(Table& t, const photometry::PlanningFigures& p) {
  if (p.ugr.defined) {
    std::string u = "reflectances 70/50/20, S = " + fmt(p.ugr.spacing_h, 2) + "H, crosswise / endwise, background " +
                    photometry::to_string(p.ugr.background);
    for (const auto& r : p.ugr.rooms) {
      if (!((r.x_h == 4 && r.y_h == 8) || (r.x_h == 8 && r.y_h == 4) || (r.x_h == 2 && r.y_h == 2) ||
            (r.x_h == 12 && r.y_h == 8)))
        continue;
      u += "\n" + fmt(r.x_h, 0) + "H x " + fmt(r.y_h, 0) + "H" + std::string(r.x_h < 10 ? "  " : " ") +
           (r.y_h < 10 ? " " : "") + fmt(r.crosswise[0], 1) + " / " + fmt(r.endwise[0], 1);
    }
    u += "\nfor " + fmt(p.ugr.flux_lm, 0) + " lm; another flux F adds 8 log10(F / " +
         fmt(p.ugr.flux_lm, 0) + ")";
    t.row("UGR", u);
  } else {
    t.row("UGR", why_or(p.ugr.why_undefined));
  }
  if (p.cu.defined) {
    // RCR 1, 5, 10 for 80/50, 70/50, 50/30 and 0/0.
    std::string c = std::string("floor cavity ") + fmt(100 * p.cu.floor_reflectance, 0) +
                    " %, % of " + (p.cu.relative_to_lamps ? "lamp" : "luminaire") + " flux";
    c += "\nRCR   80/50  70/50  50/30    0/0";
    for (int r : {0, 1, 2, 5, 10}) {
      char buf[96];
      const auto& v = p.cu.values[r];
      std::snprintf(buf, sizeof buf, "%-4d %6s %6s %6s %6s", r, fmt(100 * v[1], 0).c_str(),
                    fmt(100 * v[5], 0).c_str(), fmt(100 * v[9], 0).c_str(), fmt(100 * v[17], 0).c_str());
      c += "\n" + std::string(buf);
    }
    t.row("CU (zonal cavity)", c);
  } else {
    t.row("CU (zonal cavity)", why_or(p.cu.why_undefined));
  }
  const auto& sc = p.spacing;
  if (!sc.c0_c180.ratio && !sc.c90_c270.ratio && !sc.diagonal.ratio &&
      sc.c0_c180.why_undefined == sc.c90_c270.why_undefined && sc.c0_c180.why_undefined == sc.diagonal.why_undefined)
    t.row("Spacing criterion", why_or(sc.c0_c180.why_undefined));
  else
    t.row("Spacing criterion", "C0-C180 " + sc_text(sc.c0_c180) + ", C90-C270 " + sc_text(sc.c90_c270) +
                                   ", diagonal " + sc_text(sc.diagonal));
  const auto& z = p.bug.zones_lm;
  t.row("BUG rating", photometry::to_string(p.bug) + "\nBL " + fmt(z.bl, 0) + "  BM " + fmt(z.bm, 0) +
                          "  BH " + fmt(z.bh, 0) + "  BVH " + fmt(z.bvh, 0) + " lm\nFL " +
                          fmt(z.fl, 0) + "  FM " + fmt(z.fm, 0) + "  FH " + fmt(z.fh, 0) +
                          "  FVH " + fmt(z.fvh, 0) + " lm\nUL " + fmt(z.ul, 0) + "  UH " +
                          fmt(z.uh, 0) + " lm\nglare table: " + photometry::to_string(p.bug.glare_table));
  if (p.luminance.defined) {
    std::string l = "gamma    C0 cd/m2    C90 cd/m2";
    for (std::size_t g = 0; g < p.luminance.gamma_deg.size(); ++g) {
      char buf[96];
      std::snprintf(buf, sizeof buf, "%-5s %12s %12s", fmt(p.luminance.gamma_deg[g], 0).c_str(),
                    fmt(p.luminance.cd_m2[0][g], 0).c_str(), fmt(p.luminance.cd_m2[1][g], 0).c_str());
      l += "\n" + std::string(buf);
    }
    t.row("Luminance", l);
  } else {
    t.row("Luminance", why_or(p.luminance.why_undefined));
  }
  std::string methods;
  for (const photometry::MethodLabel& m : photometry::method_labels(p))
    methods += (methods.empty() ? "" : "\n") + m.figure + ": " + m.method + "\n  convention: " + m.convention +
               "\n  checked against: " + m.checked_against;
  t.row("Methods", methods);
}

// ------------------------------------------------------------ ray files

void ray_set_rows(Table& t, const io::Tm25RaySet& set) {
  const io::Tm25Header& h = set.header;
  t.row("Rays", std::to_string(set.ray_count()) + (h.creation_method == 1 ? " (measured)" : " (simulated)"));
  t.row("Ray flux", std::string(set.columns.tri_y >= 0 ? "luminous (Tri_Y)" : "radiant") + " per ray; rays' sum " +
                        num(set.total_luminous_flux_lm()) + " lm" +
                        (set.columns.radiant_flux >= 0 ? ", " + num(set.total_radiant_flux_w()) + " W" : "") +
                        "; header " + num(h.luminous_flux_lm) + " lm, " + num(h.radiant_flux_w) + " W");
  const app::RayExtent e = app::ray_extent(set);
  t.row("Ray extent", "x " + num(e.lo.x, 4) + " to " + num(e.hi.x, 4) + ", y " + num(e.lo.y, 4) + " to " +
                          num(e.hi.y, 4) + ", z " + num(e.lo.z, 4) + " to " + num(e.hi.z, 4) + " mm");
  std::string spectrum = app::spectrum_text(h.spectrum);
  if (h.spectrum == io::Tm25Spectrum::SingleWavelength) spectrum += " (" + num(h.wavelength_nm) + " nm)";
  if (std::isfinite(h.min_wavelength_nm) && std::isfinite(h.max_wavelength_nm))
    spectrum += ", " + num(h.min_wavelength_nm) + " to " + num(h.max_wavelength_nm) + " nm";
  t.row("Spectrum", spectrum);
}

void print_table(const std::string& path, const io::PhotometricFile& file, const Summary& s,
                 const photometry::PlanningFigures& planning) {
  const Distribution& d = file.distribution;
  Table t;
  t.row("File", path);
  t.row("Format", io::format_label(file));
  for (const auto& [key, label] : {std::pair{"MANUFAC", "Manufacturer"},
                                   {"LUMINAIRE", "Luminaire"},
                                   {"LUMCAT", "Catalogue no."},
                                   {"TEST", "Test report"},
                                   {"TESTLAB", "Test lab"},
                                   {"ISSUEDATE", "Issue date"}}) {
    if (const photometry::Keyword* k = d.find_keyword(key); k && !k->value.empty())
      t.row(label, k->value);
  }
  if (file.ray_set) ray_set_rows(t, *file.ray_set);
  t.row("Photometric type", photometry::to_string(d.type));
  std::string symmetry = photometry::to_string(d.symmetry);
  if (d.ldt_type_indicator)
    symmetry += " (EULUMDAT Ityp " + std::to_string(*d.ldt_type_indicator) + ")";
  t.row("Symmetry", symmetry);
  const bool c = d.type == photometry::PhotometricType::C;
  t.row(c ? "Gamma angles" : "Vertical angles", grid_text(d.vertical_deg));
  t.row(c ? "C-planes" : "Horizontal angles", grid_text(d.horizontal_deg));
  t.row("Photometry", d.absolute ? "absolute (candela as measured, no rated lamp flux)"
                                 : "relative (candela for the rated lamp flux)");
  std::string lamps;
  for (const auto& l : d.lamps) lamps += (lamps.empty() ? "" : "\n") + lamp_text(l, d.absolute);
  if (!lamps.empty()) t.row(d.lamps.size() > 1 ? "Lamp sets" : "Lamps", lamps);
  std::string alternatives;
  for (const auto& l : d.alternative_lamps)
    alternatives += (alternatives.empty() ? "" : "\n") + lamp_text(l, false);
  if (!alternatives.empty()) t.row("Alternative lamps", alternatives);
  if (s.lor_defined) t.row("Rated lamp flux", fmt(s.rated_lamp_flux_lm, 1) + " lm");
  if (d.ballast_factor != 1.0) t.row("Ballast factor", num(d.ballast_factor));
  t.row("Luminous opening", opening_text(d.opening));
  if (d.tilt.kind != photometry::Tilt::Kind::None)
    t.row("Tilt", std::to_string(d.tilt.angles_deg.size()) + " tilt angles, lamp geometry " +
                      std::to_string(d.tilt.lamp_geometry));

  t.row("Total flux", fmt(s.flux_lm, 1) + " lm");
  t.row("LOR", s.lor_defined ? percent(s.lor, 2) : "- (absolute photometry)");
  t.row("DFF", percent(s.dff, 2));
  if (std::isfinite(d.declared_lor_percent) || std::isfinite(d.declared_dff_percent))
    t.row("Declared LOR / DFF",
          fmt(d.declared_lor_percent, 2) + " % / " + fmt(d.declared_dff_percent, 2) + " %");
  t.row("Downward / upward",
        fmt(s.downward_flux_lm, 1) + " lm / " + fmt(s.upward_flux_lm, 1) + " lm");
  t.row("Zonal flux", zones_text(s.zones, s.flux_lm));
  t.row("Zonal flux, 10 deg", zones_text(s.zones_10deg, s.flux_lm));
  std::string peak = fmt(s.max_intensity_cd, 1) + " cd at C " + fmt(s.max_c_deg, 1) +
                     " deg, gamma " + fmt(s.max_gamma_deg, 1) + " deg";
  if (!c)
    peak += " (H " + fmt(s.max_horizontal_deg, 1) + ", V " + fmt(s.max_vertical_deg, 1) + " deg)";
  t.row("Maximum intensity", peak);
  t.row("Beam angle C0-C180", beam_text(s.beam_c0_c180, 0.0));
  t.row("Beam angle C90-C270", beam_text(s.beam_c90_c270, 90.0));
  t.row("Field angle C0-C180", beam_text(s.field_c0_c180, 0.0));
  t.row("Field angle C90-C270", beam_text(s.field_c90_c270, 90.0));
  t.row("CIE flux code", photometry::to_string(s.cie_flux_code));
  t.row("Input power", std::isfinite(s.input_power_w) ? num(s.input_power_w) + " W" : "unknown");
  if (std::isfinite(s.efficacy_lm_per_w)) t.row("Efficacy", fmt(s.efficacy_lm_per_w, 1) + " lm/W");
  planning_rows(t, planning);
  t.print();
}

}  // namespace

int run_info(const Args& args) {
  std::string path;
  bool as_json = false;
  double floor_reflectance = 0.2;
  std::string ugr_background = photometry::to_string(photometry::UgrBackground::Cie190);
  app::InputOptions input;
  ArgParser parser("info",
                   "FILE [--json] [--cu-floor RHO] [--ugr-background cie190|flux-transfer] "
                   "[--ldt-isym3 standard|qlumedit]",
                   kDescription);
  parser.positional("FILE", &path,
                    "An IES LM-63 (.ies), EULUMDAT (.ldt), TM-33 (.xml) or GLDF (.gldf: every photometry "
                    "inside) file; other names by their content.");
  parser.flag("json", &as_json, "Print one JSON object instead of the table.");
  parser.option("cu-floor", &floor_reflectance, 0.0, 0.95, "RHO",
                "Effective floor cavity reflectance of the CU table, 0..1 (default 0.2).");
  add_ugr_background_option(parser, &ugr_background);
  add_input_options(parser, &input);
  if (const auto outcome = parser.parse(args); outcome != ArgParser::Outcome::Run)
    return ArgParser::exit_code(outcome);

  auto files = app::read_inputs(path, input);
  if (!files.ok()) return kExitFailure;
  // A GLDF container: every photometry, each named CONTAINER:ENTRY.
  const bool container = !files->front().container.empty();
  json all = json::array();
  for (std::size_t i = 0; i < files->size(); ++i) {
    const io::PhotometricFile& file = (*files)[i];
    const std::string name = container ? path + ":" + file.container_entry : path;
    const Summary s = photometry::summarize(file.distribution);
    const photometry::PlanningFigures planning = photometry::planning_figures(file.distribution, floor_reflectance, app::ugr_options(ugr_background));
    if (as_json) {
      json j = app::info_json(name, file, s, planning);
      if (container) j["gldf_photometry_id"] = file.container_id;
      all.push_back(std::move(j));
    } else {
      if (i > 0) std::printf("\n");
      print_table(name, file, s, planning);
    }
  }
  if (as_json) {
    const json out = container ? json{{"file", path}, {"format", "GLDF"}, {"photometries", std::move(all)}}
                               : std::move(all.front());
    // Invalid UTF-8 in a label is replaced rather than thrown on.
    std::printf("%s\n", out.dump(2, ' ', false, json::error_handler_t::replace).c_str());
  }
  return std::fflush(stdout) == 0 ? kExitOk : kExitFailure;
}

}  // namespace gonio::cli
