// The luminaire datasheet (`gonio report`): one self-contained HTML page per
// set of luminaires — identification, polar and cartesian intensity diagrams,
// a cone diagram and the isolux plot on the floor at a mounting height, the
// zonal lumen summary, the candela table, UGR, CU, spacing criterion, BUG,
// luminance table, efficacy and, for Gonio's own simulations, the energy
// ledger — and the same page printed to PDF.
//
// Self-contained: styles inline, diagrams as inline SVG (gnuplot's, see
// io/outputs/plot.h, and the isolux plot drawn here), no script, no external
// resource. PDF: the HTML printed by a headless Chromium (Debian package
// `chromium`, installed by scripts/setup.sh; `$GONIO_CHROMIUM` names another
// binary), run as a separate process like gnuplot.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "photometry/distribution.h"
#include "photometry/ugr.h"

namespace gonio::io {

struct DatasheetEntry {
  std::string source;                       // the file name shown on the sheet
  std::string format;                       // e.g. "IES LM-63-2002", "EULUMDAT"
  photometry::Distribution distribution;    // Type C for the diagrams; A/B get tables only
  // report.json of a simulation (io/outputs/report.h) for the energy ledger; empty
  // for measured files.
  std::optional<nlohmann::json> simulation_report;
};

struct DatasheetOptions {
  double mounting_height_m = 3.0;   // isolux and cone diagram [m]
  double floor_reflectance = 0.2;   // CU table's floor cavity [1]
  photometry::UgrOptions ugr;       // UGR table's background and spacing
  // `gonio tolerance`'s report.json (docs/tolerance.md): the sheet gains the
  // Monte Carlo yield table (tolerance_yield_html); empty: none.
  std::optional<nlohmann::json> tolerance_report;
  std::string tolerance_source;     // its file name, shown on the sheet
};

// The yield table of a `gonio tolerance` report.json: per --spec limit the
// nominal, the trials' range of that figure, how many trials are within it
// of how many and the yield, then all limits together; the model, trials,
// photons and seed above it. Errors name `source` where the report lacks
// what the table needs (monte_carlo.trials, monte_carlo.yield, nominal).
Result<std::string> tolerance_yield_html(const nlohmann::json& report, const std::string& source);

// The whole page. Errors: a distribution that fails photometry::validate
// (named by its source), gnuplot failing.
Result<std::string> datasheet_html(const std::vector<DatasheetEntry>& entries,
                                   const DatasheetOptions& options = {});

// HTML printed to PDF bytes (A4) by the headless browser, made
// deterministic (make_pdf_deterministic). Errors name the program and what
// it said.
Result<std::string> html_to_pdf(const std::string& html);

// Makes a PDF printed by Chromium the same bytes for the same page, its
// length and every cross-reference offset kept: the info dictionary's
// /CreationDate and /ModDate (the time of printing) become the date of
// $SOURCE_DATE_EPOCH where it is set, else are blanked out with spaces (a
// PDF without dates); the tagged structure's ids "(nodeNNNNNNNN)" — DOM node
// numbers of the browser session, which shift from run to run — are
// renumbered 0, 1, 2, … in their order with the same number of digits, so
// the ID tree stays sorted and every reference to an id follows it.
void make_pdf_deterministic(std::string& pdf);

// Writes the datasheet atomically to `path`: HTML for .html/.htm, PDF for
// .pdf (any case); any other extension is an error naming the file.
Status write_datasheet(const std::string& path, const std::vector<DatasheetEntry>& entries,
                       const DatasheetOptions& options = {});

}  // namespace gonio::io
