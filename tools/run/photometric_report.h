// What `gonio info --json` prints of a photometry and `gonio compare --json`
// of two, built in one place: for the commands, and for the Python module
// (tools/python), whose figures are these objects (the same numbers, under
// the same keys). Units are in the key names (flux_lm, max_cd, *_deg, *_m,
// *_w); a value that is undefined (NaN) is null; an undefined planning
// figure is null with a *_why key beside it.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/photometric/photometric_file.h"
#include "photometry/compare.h"
#include "photometry/planning.h"
#include "photometry/summary.h"
#include "photometry/vec3.h"

namespace gonio::cli {

// info keeps its keys in the order it writes them.
using OrderedJson = nlohmann::ordered_json;

// The step of an evenly spaced angle list [deg]; nullopt for fewer than two
// angles or uneven steps (differing by more than 1e-6°).
std::optional<double> even_step_deg(const std::vector<double>& angles_deg);

// The box the rays of a TM-25 ray file start in [mm] (zero for no rays).
struct RayExtent {
  Vec3 lo{0.0, 0.0, 0.0}, hi{0.0, 0.0, 0.0};
};
RayExtent ray_extent(const io::Tm25RaySet& set);
// "none", "one wavelength", "a wavelength per ray", … (info's words).
const char* spectrum_text(io::Tm25Spectrum spectrum);

// gonio info --json's object for one photometry of a file (`name`: its
// path, or CONTAINER:ENTRY for a photometry inside a GLDF).
OrderedJson info_json(const std::string& name, const io::PhotometricFile& file, const photometry::Summary& s,
                      const photometry::PlanningFigures& planning);

// Its parts, under its keys. The summary: flux_lm, lor, dff,
// declared_lor_percent, declared_dff_percent, downward_flux_lm,
// upward_flux_lm, zones, zones_10deg, the peak and spread
// (tools/json_figures.h), beam, field, cie_flux_code, input_power_w,
// efficacy_lm_per_w.
void put_summary(OrderedJson& j, const photometry::Distribution& d, const photometry::Summary& s);
// The planning figures: ugr_table, cu_table, spacing_criterion, bug,
// luminance_table, methods.
void put_planning(OrderedJson& j, const photometry::PlanningFigures& p);
// One lamp set: count, type, flux_lm, color, color_rendering, power_w.
OrderedJson lamp_json(const photometry::LampSet& lamps);
// A TM-25 ray file's rays: count, flux, extent, spectrum, creation.
OrderedJson ray_set_json(const io::Tm25RaySet& set);
// A reader's finding: severity, code, message, line (null where unknown).
OrderedJson finding_json(const Finding& finding);

// gonio compare --json's object for B against the reference A (without the
// "plot" key the command adds).
nlohmann::json compare_json(const std::string& path_a, const io::PhotometricFile& a, const std::string& path_b,
                            const io::PhotometricFile& b, const photometry::Comparison& c,
                            const photometry::CompareOptions& options);

}  // namespace gonio::cli
