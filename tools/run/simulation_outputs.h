// The files `gonio simulate` leaves for light-planning programs and
// renderers, made from the converged far field, each read back and checked.
//
//   STEM.ies          IES LM-63-2019 (file generation type 1.00010, computer
//                     simulation) or LM-63-2002
//   STEM.ldt          EULUMDAT: cd/klm of the emitters' flux, so LORL is
//                     escaped / emitted; DFF and the direct ratios computed
//                     (photometry/direct_ratios.h, Gonio's room model)
//   farfield.exr      the far field as an OpenEXR cube map (Y [cd], flux
//                     [lm], photons per texel), world directions
//   farfield-latlong.exr the same as an equirectangular map (io/outputs/exr.h), world
//                     directions, for renderers
//   STEM.svg          the intensity diagram (C0–C180 and C90–C270, polar and
//                     cartesian), io/outputs/intensity_diagram.h
//   STEM.html         the datasheet (io/outputs/datasheet.h) of the candela table,
//                     with the run's energy ledger; only when asked for by
//                     name ("report"), not part of "all"
//   STEM.gldf         on request only (not part of "all"): a GLDF container
//                     (io/photometric/gldf.h) with product.xml, the LDT and IES above
//                     (the same bytes) and the model's geometry as L3D
//
// The candela table. The far field is resampled to the Type C grid
// (sim/detectors/resample.h: every value is the flux of its bin over the bin's solid
// angle) in the scene's photometric frame, then averaged over the
// directions the symmetry makes equivalent (sim/detectors/symmetry.h), chosen by the
// statistical test of sim::detect_symmetry() unless the user names one.
// Lamp data: one set, count = number of emitters, rated flux = the emitters'
// flux [lm] (relative photometry), so a planning program's LOR is
// escaped / emitted. Nothing is invented: no test lab, no manufacturer (both
// say so), the luminaire's outer dimensions are the bounding box of its
// meshes in the photometric frame, and the luminous opening is what
// simulated_opening() finds where the light leaves the model (a point when
// the request carries none).
//
// Read-back. Each file is read by Gonio's own reader and integrated:
// IES and LDT by photometry::total_flux_lm() (for LDT, cd/klm × lamp flux),
// the cube by the sum of its flux channel, the latlong map by
// io::latlong_flux_lm(). The difference to the escaped flux is the
// quadrature error of the file's grid (the bins carry the flux exactly).
// Findings: the reader's plus photometry::check() for IES and LDT (what
// `gonio check` reports), readable channels with finite, non-negative
// values for EXR, a readable SVG document for the diagram. A file is clean
// when no finding is a warning or an error.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/photometric/ies.h"
#include "photometry/diagnostics.h"
#include "photometry/distribution.h"
#include "sim/detectors/colour_over_angle.h"
#include "sim/detectors/far_field.h"
#include "sim/ledger.h"
#include "sim/detectors/resample.h"
#include "sim/scene.h"
#include "sim/simulation.h"
#include "sim/detectors/symmetry.h"
#include "sim/tracer/tracer.h"

namespace gonio::app {

enum class OutputFormat { Ies, Ldt, Exr, LatLong, Plot, Report, Gldf, Tm33 };

// "ies", "ldt", "exr", "latlong", "plot", "report", "gldf", "tm33".
const char* to_string(OutputFormat format);

// A comma-separated list of the names above, or "all" (every format but
// "report" and "gldf", in the order above). Repeats are ignored; an empty list or an unknown name is an
// error that lists the valid names.
Result<std::vector<OutputFormat>> parse_formats(const std::string& list);

// What the files record about the run that made them ([FILEGENINFO] and
// [_GONIO_…] keywords, EXR attributes).
struct RunInfo {
  std::string program_version;
  std::string model;                 // the model file as given
  std::uint64_t photons = 0;         // traced
  std::uint64_t seed = 0;
  int max_bounces = 0;
  std::string issue_date;            // [ISSUEDATE] and the LDT date field, YYYY-MM-DD
};

// The luminous opening of a simulated luminaire, as the light leaves it: the
// photons [0, photons) of the run `seed` are traced again (the same photons
// the run began with) and every escape that leaves downward (below the
// horizontal of the photometric frame: the light an observer below sees) is
// taken at the point it leaves from — the last surface it met, or the
// emitter for light that meets none. The opening is the rectangle those
// points cover projected on the horizontal plane, its sides along C0–C180
// (length) and C90–C270 (width); flat (height 0), since a projection of the
// points inside a reflector or behind a lens falls within its rim. It is a
// disc instead when that rectangle is square (sides within 2 %) and its
// corners hold no exit (at most 1 in 1000 outside the inscribed circle, 1 %
// enlarged): a round reflector or lens. Elliptical and other shapes keep
// their bounding rectangle (area up to 4/π too large). A Point opening where
// nothing escapes downward.
struct SimulatedOpening {
  photometry::LuminousOpening opening;  // Rectangular, Circular, or Point
  Vec3 centre_m;                        // of the rectangle, photometric frame [m]
  std::uint64_t exits = 0;              // downward escapes it was found from
};
SimulatedOpening simulated_opening(const sim::Tracer& tracer, const sim::SceneDesc& scene, std::uint64_t seed,
                                   std::uint64_t photons = std::uint64_t{1} << 16);
// The same opening from the trace's own escapes of photons 0 … photons − 1
// where it kept them (SimulationSettings::capture_escaped_photons, which
// plan_simulation sets to kOpeningPhotons unless TM-25 rays name their own
// count) and followed them as
// record_rays does (no next-event connections, guided emission or
// luminance images; one process): the same points in the same order, so the
// same opening, without tracing them again (issue 40). Otherwise traces
// them again (above).
inline constexpr std::uint64_t kOpeningPhotons = std::uint64_t{1} << 16;
bool opening_from_trace(const sim::Simulation& simulation, std::uint64_t photons = kOpeningPhotons);
SimulatedOpening simulated_opening(const sim::Simulation& simulation, std::uint64_t photons = kOpeningPhotons);
// The same opening from points downward escapes leave from, given in the
// photometric frame [m] (simulated_opening's second half; gonio optimize's
// UGR takes them from an evaluation's own escaped photons).
SimulatedOpening opening_of_exits(const std::vector<Vec3>& exits_local);

struct OutputRequest {
  std::string directory;             // exists
  std::string stem;                  // file names: STEM.ies, …
  std::vector<OutputFormat> formats;
  sim::CGammaGrid grid;              // validate(grid).ok()
  std::optional<photometry::Symmetry> symmetry;  // nullopt: decide from the data
  io::IesVersion ies_version = io::IesVersion::LM63_2019;  // 2019 or 2002
  RunInfo run;
  std::string cache_dir;  // where resamplers are kept (tools/run/resampler_cache.h); empty: none
  // The output grid's resampler already built for this run (the error
  // estimate's: `grid`, the scene's frame, the far field's face size); not
  // owned. Null, or another face size: one from cache_dir, or made.
  const sim::Resampler* resampler = nullptr;
  // The opening the IES and LDT carry and the GLDF's light-emitting object
  // takes; none: a point opening, and the L3D object where the emitters are.
  std::optional<SimulatedOpening> opening;
  // A spectral run's X and Z beside the far field (farfield.exr's X and Z
  // channels); null: a grey run. Not owned.
  const sim::ColourFarField* colour = nullptr;
  // {near_field: [...], far_field_distance_m} of report.json (--near-field)
  // for the datasheet; null: none.
  nlohmann::json near_field;
  // {colour: {...}, colour_over_angle: {...}} of report.json (colour_json)
  // for the datasheet; null: a grey run.
  nlohmann::json colour_report;
};

// A spectral run's colour as report.json, the datasheet and the live page
// give it: {"colour": {cie_x, cie_y, u_prime, v_prime, cct_k, duv, method},
// "colour_over_angle": {threshold_fraction, mean_u_prime, mean_v_prime,
// delta_uv_max, bins_counted, planes: [{c_deg, gamma_deg, u_prime, v_prime,
// cct_k, duv}]}} (undefined values null).
nlohmann::json colour_json(const sim::ColourOverAngle& c);
// The live page's colour (state.json "colour"): colour_json's "colour"
// without its method, plus delta_uv_max.
nlohmann::json live_colour_json(const sim::ColourOverAngle& c);


// One file written and read back.
struct WrittenFile {
  OutputFormat format = OutputFormat::Ies;
  std::string path;
  // Integrated from the file as read back [lm]; NaN for the diagram.
  double flux_lm = photometry::kNaN;
  // (flux_lm − escaped) / escaped [1]; NaN for the diagram or no escaped flux.
  double flux_difference = photometry::kNaN;
  std::vector<Finding> writer_notes;  // what the writer said (defaults filled, conversions)
  std::vector<Finding> findings;      // the read-back checks
  bool clean() const { return worst(findings) < Severity::Warning; }
};

// A requested file that could not be written (nothing of it is left: the
// writes are atomic).
struct FailedFile {
  OutputFormat format = OutputFormat::Ies;
  std::string path;
  Error error;
};

struct OutputResult {
  photometry::Distribution distribution;  // the candela table the IES and LDT files hold
  photometry::Symmetry symmetry = photometry::Symmetry::None;
  std::string symmetry_reason;      // one line: what was chosen and why
  sim::SymmetryDecision decision;   // the tests (auto only)
  std::vector<WrittenFile> files;   // written, in request order
  std::vector<FailedFile> failed;   // not written, in request order
};

// The Type C distribution of a far field: resampled in `scene.frame`,
// symmetry averaged, with lamp data, keywords and derived EULUMDAT values as
// described at the top. `symmetry` must be supported by the grid.
photometry::Distribution simulated_distribution(const sim::BinnedField& binned, photometry::Symmetry symmetry,
                                                const sim::SceneDesc& scene, const sim::Ledger& ledger,
                                                const OutputRequest& request);

// What `gonio simulate` asks of a finished simulation's table, whatever
// files it then writes: `grid` and `symmetry` (none: detect), the
// resamplers' cache folder, the opening the light leaves by
// (simulated_opening, from the run's own seed), and the run's facts (this
// version, `model` as given, the photons traced, seed, bounce limit, today's
// date). The caller adds the folder, stem and formats.
OutputRequest table_request(const sim::Simulation& simulation, const std::string& model, const sim::CGammaGrid& grid,
                            const std::optional<photometry::Symmetry>& symmetry, const std::string& cache_dir);

// The candela table of a far field, the one the IES and LDT files hold:
// binned onto request.grid, with request.symmetry or the one
// sim::detect_symmetry() finds, and simulated_distribution()'s lamp data
// and keywords. Error: an explicit symmetry the grid does not support.
struct SimulatedTable {
  photometry::Distribution distribution;
  photometry::Symmetry symmetry = photometry::Symmetry::None;
  std::string symmetry_reason;     // one line: what was chosen and why
  sim::SymmetryDecision decision;  // the tests (auto only)
};
Result<SimulatedTable> simulated_table(const sim::FarField& far_field, const sim::SceneDesc& scene,
                                       const sim::Ledger& ledger, const OutputRequest& request);

// Resamples, writes every requested file atomically, reads each back and
// checks it. A file that cannot be written (a missing plot program, a full
// disk, a path that is a folder) is listed in `failed` and the others are
// still written; nothing is left half written. Error (before anything is
// written): an explicit symmetry the grid does not support.
Result<OutputResult> write_outputs(const sim::FarField& far_field, const sim::SceneDesc& scene,
                                   const sim::Ledger& ledger, const OutputRequest& request);

// report.json's "outputs" (grid, symmetry and its tests, files with flux,
// difference and findings, and "failed" [{path, format, error}]).
nlohmann::json to_json(const OutputResult& result, const sim::CGammaGrid& grid, double escaped_lm);

// The energy checks `gonio simulate` makes once every file is written: the
// books close (emitted = escaped + absorbed + cut off, in photons exactly and
// in lumens to 1e-9 of the emitted flux), the LOR escaped / emitted is at
// least `min_lor`, every file's flux read back lies within `flux_tolerance`
// (a fraction) of the escaped flux, and every file is clean.
struct EnergyCheck {
  double lor = 0.0;                   // escaped / emitted; 0 without emitted flux
  std::vector<std::string> failures;  // one sentence per failed check
  nlohmann::json json;                // report.json's "energy"
  bool passed() const { return failures.empty(); }
};

EnergyCheck check_energy(const sim::Ledger& ledger, const std::vector<WrittenFile>& files, double min_lor,
                         double flux_tolerance);

// How the run ends: each failure printed to stderr as
// "gonio: MODEL: energy check failed: …" and exit code 1; 0 when all passed.
int energy_exit_code(const std::string& model, const EnergyCheck& check);

}  // namespace gonio::app
