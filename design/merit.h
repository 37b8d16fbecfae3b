// The merit of a design against a target distribution (gonio optimize,
// docs/design.md "Optimisation"): a weighted sum of terms computed from the
// photons that escaped the luminaire, on a C-γ grid of its own.
//
//   [merit]                        # in the design file; every key optional
//   target = "target.ies"          # the target (gonio optimize --target overrides)
//   c_step = 360                   # the merit's grid [deg]: 360 one C column (rotational)
//   gamma_step = 5
//   normalize = "flux"             # "flux": the traced candela scaled to the target's
//                                  #   flux; "absolute": as traced
//   smooth = true                  # each photon spread over the neighbouring nodes
//   photons_per_bin = 40           # the first stage's photons per node (≥ 40)
//   candela = 1                    # weight of the candela RMS [% of the target's peak]
//   gamma_weights = [[0, 60, 1], [60, 180, 0.5]]   # [from, to, weight] of nodes by γ
//   lor = 0                        # weight of the light lost, 100·(1 − LOR) [%]
//   beam = 0                       # weight of |beam angle − the target's| [deg]
//   field = 0                      # weight of |field angle − the target's| [deg]
//   max_cd_above = { gamma = 65, to = 90, limit = 500, weight = 1 }  # cut-off: the largest
//                                  #   candela at gamma ≤ γ ≤ to (default 180), a limit [cd]
//                                  #   or (no limit) a term [% of the target's peak]
//   ugr = { limit = 19, weight = 1 }   # UGR 4H × 8H (70/50/20, the larger of crosswise and
//                                  #   endwise): a limit, or (no limit) |UGR − the target's|
//   ugr = { limit = 19, room = [8, 6], reflectances = [50, 30, 20], view = "endwise" }
//                                  #   another cell of CIE 190's table: room X, Y [H] (its
//                                  #   rows), ceiling/walls/floor [%] (its columns), the
//                                  #   viewing direction (crosswise, endwise; default the larger)
//   bug = { b = 1, u = 0, g = 1, table = "asymmetric", weight = 1 }  # BUG class limits
//   size = { radius = 40, height = 30, weight = 1 }  # the luminaire's size limits [mm]
//
// Limits (docs/design.md "Merit terms and limits"): each gives values
// c = (figure − limit) / limit (c ≤ 0: within; a limit of 0 lm: per lumen);
// COBYLA takes them as NLopt inequality constraints, the other methods as a
// penalty weight · 100 · max(0, c) added to the merit (1 % over a limit
// costs as much as 1 % of candela RMS at weight 1).
//
// Noise by construction: every evaluation traces the same photons (the same
// seed: photon i draws its numbers from (seed, i, dimension) alone), and with
// `smooth` each photon's flux is spread over the four nodes around its
// direction with tent (bilinear) weights in C and γ, so the merit is a
// continuous function of the photons' directions, and so of the variables
// wherever the photons' paths are (no plateaus and jumps as a photon crosses
// a bin's edge). Without it each photon counts in the nearest node alone.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "io/model/toml_tree.h"
#include "photometry/diagnostics.h"
#include "photometry/distribution.h"
#include "photometry/vec3.h"

namespace gonio::design {

struct GammaWeight {
  double from_deg = 0.0, to_deg = 180.0, weight = 1.0;
};

struct MeritSpec {
  std::string target;            // the [merit] table's target, resolved against the design's folder
  double c_step_deg = 360.0;     // 360: one column
  double gamma_step_deg = 5.0;
  bool absolute = false;         // normalize = "absolute"
  bool smooth = true;
  double photons_per_bin = 40.0;
  double candela_weight = 1.0;
  std::vector<GammaWeight> gamma_weights;  // none: every node weight 1
  double lor_weight = 0.0;
  double beam_weight = 0.0;
  double field_weight = 0.0;
  int beam_line = 0, field_line = 0;  // their keys' lines (0: not in the file)
  // max_cd_above: the largest candela of the nodes at gamma_deg ≤ γ ≤ to_deg
  // (the merit's candela: scaled to the target's flux with normalize = "flux").
  struct MaxCdAbove {
    double gamma_deg = 90.0;
    double to_deg = 180.0;
    std::optional<double> limit_cd;  // a limit; none: a term (% of the target's peak)
    double weight = 1.0;
    int line = 0;
  };
  std::optional<MaxCdAbove> max_cd_above;
  // ugr: 4H × 8H, reflectances 0.7/0.5/0.2, the larger of crosswise and
  // endwise (photometry/ugr.h, CIE 190), of the merit's candela.
  struct Ugr {
    std::optional<double> limit;  // a limit; none: |UGR − the target's| is a term
    double weight = 1.0;
    int line = 0;
    // The table's cell (room, reflectances, view): default 4H × 8H, 70/50/20, the larger.
    double x_h = 4.0, y_h = 8.0;  // the room across and along the line of sight [H]
    std::size_t reflectance_set = 0;  // index into photometry::kUgrReflectances
    int view = 0;  // 0: the larger of crosswise and endwise; 1: crosswise; 2: endwise
  };
  std::optional<Ugr> ugr;
  // bug: the largest B, U and G classes allowed (−1: no limit), each zone's
  // lumens against its class limit (photometry/bug_rating.h).
  struct Bug {
    int b = -1, u = -1, g = -1;
    bool symmetric = false;  // the glare table of Types V and VS
    double weight = 1.0;
    int line = 0;
  };
  std::optional<Bug> bug;
  // size: the largest distance of the luminaire's surfaces from the
  // photometric axis and their height along it [mm].
  struct Size {
    std::optional<double> radius_mm, height_mm;
    double weight = 1.0;
    int line = 0;
  };
  std::optional<Size> size;
  int line = 0;                  // the [merit] table's line (0: none in the file)
};

// The merit's hard limits, one per figure limited, in a fixed order:
// "max_cd_above", "ugr", "bug BL", …, "size radius", "size height".
std::vector<std::string> merit_limit_names(const MeritSpec& spec);

// The [merit] table of a resolved design document (resolved_document): its
// defaults where absent. Errors name the file and line: unknown keys, wrong
// types, a grid step that does not divide 360 or 180, a weight below zero.
Result<MeritSpec> read_merit(const io::TomlNode& resolved, const std::string& path);

// The merit's grid: nodes C_i = i·ΔC (i < 360/ΔC), γ_j = j·Δγ (j ≤ 180/Δγ),
// and each node's solid angle: the integral over the sphere of its basis
// function (tent in C and γ when smooth, the node's cell otherwise), so that
// a node's candela is its flux over its solid angle.
struct MeritGrid {
  std::vector<double> c_deg, gamma_deg;
  std::vector<double> solid_angle_sr;  // [c * gamma_count + g]
  bool smooth = true;
  std::size_t size() const { return c_deg.size() * gamma_deg.size(); }
};
MeritGrid merit_grid(const MeritSpec& spec);

// A photon that left the luminaire: its direction in the photometric frame
// (local: x C0, y C90, z the zenith) and its flux [lm].
struct MeritPhoton {
  Vec3 direction;
  double flux_lm = 0.0;
};

// The candela at the grid's nodes ([c * gamma_count + g]) from the photons.
std::vector<double> bin_photons(const MeritGrid& grid, const std::vector<MeritPhoton>& photons);

// One hard limit at an evaluation.
struct MeritLimitValue {
  std::string name;
  double value = 0.0, limit = 0.0;
  double c = 0.0;  // (value − limit) / limit (per unit where the limit is 0): ≤ 0 within
};

// The merit's terms and sum.
struct MeritValue {
  double merit = 0.0;            // the weighted terms plus `penalty`
  double penalty = 0.0;          // Σ weight · 100 · max(0, c) over the limits
  double field_deg = 0.0, target_field_deg = 0.0;  // at C0 (NaN where undefined)
  double max_cd_above = 0.0;     // [cd]; NaN without the term
  double ugr = 0.0, target_ugr = 0.0;  // NaN without the term
  std::vector<MeritLimitValue> limits;  // merit_limit_names' order
  std::string error;             // a term that cannot be computed for this design (the evaluation fails)
  double candela_rms_pct = 0.0;  // RMS of traced − target at the nodes, % of the target's peak
  double lor = 0.0;              // escaped flux / the emitters' flux
  double beam_deg = 0.0, target_beam_deg = 0.0;  // at C0 (NaN where undefined)
};

// The target sampled at the grid's nodes, and its figures.
struct MeritTarget {
  std::vector<double> candela;  // [c * gamma_count + g]
  double peak_cd = 0.0, flux_lm = 0.0;  // flux on the grid's quadrature
  double beam_deg = 0.0;
  double field_deg = 0.0;
  photometry::LuminousOpening opening;  // the target file's
  double ugr = std::numeric_limits<double>::quiet_NaN();  // merit_ugr at the nodes; NaN: undefined
  std::string ugr_undefined;           // why
};
Result<MeritTarget> merit_target(const MeritGrid& grid, const photometry::Distribution& target);

// What a term needs of the traced design beyond its photons: where its light
// leaves (the luminous opening gonio simulate writes: tools/run
// simulated_opening) and its size [mm].
struct MeritGeometry {
  photometry::LuminousOpening opening;
  double radius_mm = std::numeric_limits<double>::quiet_NaN();
  double height_mm = std::numeric_limits<double>::quiet_NaN();
};

// UGR 4H × 8H, reflectances 0.7/0.5/0.2 (CIE 190), the larger of crosswise
// and endwise, of `d` (its opening the luminous area); NaN where the table
// is undefined (`why` says why) or no light reaches the eye in that room.
double merit_ugr(const photometry::Distribution& d, std::string* why = nullptr);
// The same for the cell the [merit] ugr table names (room, reflectances,
// view; its defaults: the above).
double merit_ugr(const photometry::Distribution& d, const MeritSpec::Ugr& cell, std::string* why = nullptr);
// "4H × 8H, 70/50/20, the larger of crosswise and endwise": the cell in words.
std::string ugr_cell_name(const MeritSpec::Ugr& cell);
// The target's UGR for the spec's cell (merit_target computes 4H × 8H,
// 70/50/20): where the [merit] ugr table names another, call this after
// merit_target.
void set_target_ugr(const MeritSpec& spec, const MeritGrid& grid, MeritTarget* target);

// Whether the spec's terms can be computed against this target; the error
// names the design file and the term's line: a UGR term without a limit
// against a target without a luminous area, a beam or field term against a
// target without that angle (its C0 plane never falls to 50 % / 10 %).
Status check_merit_terms(const MeritSpec& spec, const MeritTarget& target, const std::string& design_path,
                         const std::string& target_path);

// The merit of `candela` (bin_photons) with `lor` against the target.
MeritValue evaluate_merit(const MeritSpec& spec, const MeritGrid& grid, const MeritTarget& target,
                          const std::vector<double>& candela, double lor, const MeritGeometry& geometry = {});

// The grid's nodes as a Type C distribution (for the beam angle, files).
photometry::Distribution merit_distribution(const MeritGrid& grid, const std::vector<double>& candela);

}  // namespace gonio::design
