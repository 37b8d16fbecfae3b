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
//
// Noise by construction: every evaluation traces the same photons (the same
// seed: photon i draws its numbers from (seed, i, dimension) alone), and with
// `smooth` each photon's flux is spread over the four nodes around its
// direction with tent (bilinear) weights in C and γ, so the merit is a
// continuous function of the photons' directions, and so of the variables
// wherever the photons' paths are (no plateaus and jumps as a photon crosses
// a bin's edge). Without it each photon counts in the nearest node alone.
#pragma once

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
  int line = 0;                  // the [merit] table's line (0: none in the file)
};

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

// The merit's terms and sum.
struct MeritValue {
  double merit = 0.0;
  double candela_rms_pct = 0.0;  // RMS of traced − target at the nodes, % of the target's peak
  double lor = 0.0;              // escaped flux / the emitters' flux
  double beam_deg = 0.0, target_beam_deg = 0.0;  // at C0 (NaN where undefined)
};

// The target sampled at the grid's nodes, and its figures.
struct MeritTarget {
  std::vector<double> candela;  // [c * gamma_count + g]
  double peak_cd = 0.0, flux_lm = 0.0;  // flux on the grid's quadrature
  double beam_deg = 0.0;
};
Result<MeritTarget> merit_target(const MeritGrid& grid, const photometry::Distribution& target);

// The merit of `candela` (bin_photons) with `lor` against the target.
MeritValue evaluate_merit(const MeritSpec& spec, const MeritGrid& grid, const MeritTarget& target,
                          const std::vector<double>& candela, double lor);

// The grid's nodes as a Type C distribution (for the beam angle, files).
photometry::Distribution merit_distribution(const MeritGrid& grid, const std::vector<double>& candela);

}  // namespace gonio::design
