// The output grid of a simulation from its options: uniform steps
// (--c-step, --gamma-step), explicit angle lists (--c-angles,
// --gamma-angles) or a measured file's own angles (--grid-like).
//
// Angle lists (docs/commands/simulate.md, "Grids"): comma-separated items,
// each an angle or a range FROM:STEP:TO (every STEP from FROM up to and
// including TO, which must be a whole number of steps away), ascending; an
// item may start where the previous one ended ("0:0.1:5,5:1:90,90:5:180").
// γ lists run from 0 to 180. C lists lie in [0, 360) (a final 360 repeats 0
// and is dropped); with --symmetry C0-C180, C90-C270 or quadrant they may
// give the symmetry's range alone (0…180, 90…270, 0…90), which is mirrored
// to the full circle.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "photometry/diagnostics.h"
#include "photometry/distribution.h"
#include "sim/detectors/resample.h"

namespace gonio::app {

// Parses an angle list as above (no range check beyond finiteness and
// ascending order; validate() checks the rest). Errors begin with `option`
// ("--gamma-angles: …") and quote the item at fault.
Result<std::vector<double>> parse_angle_list(std::string_view text, const std::string& option);

// The C-planes of a list over the full circle: a final 360 dropped, and the
// planes mirrored by `symmetry` (C0-C180: C → 360 − C; C90-C270: C → 180 − C
// and its wrap; quadrant: both), sorted, without repeats.
std::vector<double> full_circle_c_angles(std::vector<double> c_deg, photometry::Symmetry symmetry);

// The grid of a measured Type C photometric file (IES, LDT, TM-33, GLDF):
// its C-planes over the full circle (by its symmetry; a rotationally
// symmetric file gives none, so the caller's C step stays), its γ angles,
// extended to 0…180 where the file covers less (a downlight's 0…90: the
// file's last γ gap, evened out to end at 180; a file starting above 0 gets
// its first gap down to 0). `extended` (may be null) says what was added.
// Errors name the file: unreadable, or not Type C.
Result<sim::CGammaGrid> grid_like_file(const std::string& path, const sim::CGammaGrid& defaults,
                                       std::string* extended = nullptr);

struct GridOptions {
  double c_step = 5.0, gamma_step = 2.5;
  std::optional<std::string> c_angles, gamma_angles, grid_like;
  std::optional<photometry::Symmetry> symmetry;  // --symmetry where not auto
};

// The grid the options describe, validated; errors name the option
// (--c-angles, --gamma-angles, --grid-like and its file). Lists and
// --grid-like exclude each other. `note` (may be null): what --grid-like
// added to the file's angles, empty where nothing.
Result<sim::CGammaGrid> resolve_grid(const GridOptions& options, std::string* note = nullptr);

// Checks a grid against the formats a run writes: EULUMDAT holds at most
// io::kMaxLdtCPlanes C-planes and io::kMaxLdtGammaAngles γ angles. The error
// names the option the grid came from (`source`, e.g. "--c-angles").
Status check_grid_for_ldt(const sim::CGammaGrid& grid, const std::string& c_source, const std::string& gamma_source);

}  // namespace gonio::app
