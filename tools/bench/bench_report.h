// What `gonio bench` writes: the series as CSV, a summary as JSON, the
// charts (SVG and PNG through io/outputs/plot.h), and the results page (Markdown)
// that collects several models.
//
// series.csv: one row per series and iteration, columns
//   series, iteration, photons, photons_traced, trace_s, filter_s, time_s,
//   cube_rmse, cube_psnr_db, cube_snr_db, cube_raw_mse,
//   table_rms_pct, table_raw_rms_pct, table_max_pct, flux_pct
// (definitions in sim/convergence.h and tools/bench/bench_series.h); an empty
// cell where a value is not a number (an error below the reference's noise).
//
// Charts (each as .svg and .png):
//   candela-time  RMS candela error [% of peak] against time, one panel per
//                 filter family (bilinear, bilateral, guided emission)
//   cubemap-time  cube-map RMSE after mean scaling against time, the same
//   photons       both errors against photons traced, log-log, with a line
//                 of slope −½ through half the raw series's first point
//   psnr-snr      PSNR and SNR of the cube map against time (thesis 8.7, 8.8)
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "photometry/diagnostics.h"
#include "tools/bench/bench_reference.h"
#include "tools/bench/bench_series.h"

namespace gonio::cli {

// One model's bench, as the outputs need it.
struct BenchOutcome {
  std::string model;       // the model file as given
  std::string name;        // its stem, e.g. "bell"
  std::string directory;   // where its files went
  BenchSettings settings;
  std::string grid;        // e.g. "5° × 2.5°"
  Reference reference;     // far field left empty in summaries
  std::vector<SeriesResult> series;
  double smallest_raw_error_pct = 0.0;  // smallest raw candela RMS error charted [%]
};

std::string series_csv(const std::vector<SeriesResult>& series);
nlohmann::json bench_json(const BenchOutcome& outcome);

// Writes the four charts into outcome.directory; `png` adds the PNG copies.
Status write_charts(const BenchOutcome& outcome, bool png);

// The results page: a headline table (time to the target candela error per
// model, raw against filtered and guided), then per model its reference, a
// table of every series and the SVG charts, linked relative to the page.
// `machine` describes where and when it ran.
std::string results_page(const std::vector<BenchOutcome>& outcomes, const std::string& page_path,
                         const std::string& machine, const std::string& command);

// Formats a value for tables: NaN as "—".
std::string format_value(double v, int precision);

}  // namespace gonio::cli
