// The UGR table of a luminaire as CIE 190:2010 computes the catalogue table
// (the simplified tabular method of CIE 117:1995 §4 with CIE 190's standard
// conditions and background luminance), which DIALux, Relux and the CIE's own
// worked example follow.
//
// Room and installation (every choice moves the figures, so each is stated):
// - H = 2 m between the observer's eye and the plane of the luminaires (UGR
//   does not depend on H). Room X × Y in multiples of H, X across the line of
//   sight, Y along it: the 19 standard sizes (ugr_room_sizes()).
// - A square array of spacing S = 0.25 H: across the line of sight the
//   luminaires stand at T = ±S/2, ±3S/2, … (X/S in all), along it at
//   R = S/2, 3S/2, … (Y/S rows). The observer sits at the middle of the wall
//   of length X and looks horizontally along +R.
// - Which luminaires count (CIE 117 §4.5): those with |T|/R ≤ 3 and
//   γ = atan(√(R² + T²) / H) ≤ 85°; the others are left out of the sum.
// - Orientation, as CIE 117 eq. 4.5–4.6 define it by C-planes: *crosswise*,
//   the luminaire straight ahead is seen in its C0 plane, C = atan(T/R) (the
//   C90–C270 axis — a linear luminaire's length in EULUMDAT — across the line
//   of sight); *endwise*, it is seen in its C90 plane, C = 90° − atan(T/R).
//   Luminaires left and right of the line of sight are seen at the mirrored
//   C-planes (C and 360° − C crosswise, C and 180° − C endwise), which for the
//   usual symmetric distributions is the same intensity twice.
// - UGR = 8 log10(0.25 / L_b · Σ L² ω / p²) with L² ω = I² / (A_p r²):
//   I(C, γ) the intensity at the luminaire's real flux (the file's candela:
//   rated lamps for relative photometry), A_p the projected luminous area
//   toward the eye (photometry/luminance.h, side heights included),
//   r² = R² + T² + H², and p Guth's position index from CIE 117's Table 4.1
//   (bilinear; a luminaire next to one of its blanks — above the field of
//   view, H/R > 1.7…1.9 — is left out of the sum, as the table says).
// - Background luminance L_b, by `UgrBackground`:
//   - Cie190 (default): CIE 190 §4.2 eq. 7–12. L_b = E_WID / π, E_WID =
//     B · F_UWID, B = Φ · N / A_w (Φ the rated lamp flux — the luminaire's flux
//     for absolute photometry —, N the luminaires in the room, A_w = 2H(X + Y)
//     the wall area between eye and luminaire plane). F_UWID from the zonal
//     fluxes of the 18 10° zones (intensity at the zone midpoints, averaged
//     over the C-planes), scaled to the declared LOR (the computed one where
//     the file declares none), split into direct flux on the floor cavity
//     (weights F_GL of CIE 190 Table 4, by room index k = XY / (H(X + Y))),
//     on the walls and on the ceiling, times the transfer factors of CIE 190
//     Table 5 per room and reflectance set. The same for both orientations.
//   - FluxTransfer: Gonio's own model of the room, kept as an option: the
//     direct flux on the floor plane at eye height (the exact overlap
//     integral of the array, photometry/direct_ratios.h), on the walls and on
//     the ceiling, then the inter-reflections of the box with exact view
//     factors; E = (wall flux − direct wall flux) / wall area. It follows the
//     luminaire's distribution beyond CIE 190's four zone weights; on eleven
//     published luminaires it is within −0.27…+0.02 of CIE 190 (docs/methods.md).
// - Flux: L² ω ∝ F and L_b ∝ F, so another luminaire flux F′ adds
//   8 log10(F′ / F) to every value (CIE 190's correction).
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "photometry/distribution.h"

namespace gonio::photometry {

// The five reflectance sets (ceiling, walls, floor / working plane) [1].
inline constexpr std::array<std::array<double, 3>, 5> kUgrReflectances = {{
    {0.7, 0.5, 0.2}, {0.7, 0.3, 0.2}, {0.5, 0.5, 0.2}, {0.5, 0.3, 0.2}, {0.3, 0.3, 0.2}}};

enum class UgrBackground {
  Cie190,        // CIE 190:2010 eq. 7–12 with its Tables 4 and 5 (default)
  FluxTransfer,  // Gonio's inter-reflection model of the room
};

// "cie190", "flux-transfer" (the command-line spelling).
const char* to_string(UgrBackground b);
std::optional<UgrBackground> parse_ugr_background(std::string_view text);

struct UgrOptions {
  UgrBackground background = UgrBackground::Cie190;
  double spacing_h = 0.25;  // luminaire spacing [H]
};

struct UgrRoom {
  double x_h = 0.0;  // room dimension across the line of sight [H]
  double y_h = 0.0;  // along the line of sight [H]
  std::array<double, 5> crosswise{};  // UGR per reflectance set; NaN where undefined
  std::array<double, 5> endwise{};
};

struct UgrTable {
  bool defined = false;
  std::string why_undefined;  // e.g. "point opening: no luminous area"
  UgrBackground background = UgrBackground::Cie190;
  double spacing_h = 0.25;    // [H]
  double flux_lm = kNaN;      // luminaire flux the table holds for [lm]
  std::vector<UgrRoom> rooms; // the 19 rooms in CIE 190's order
};

// The 19 room sizes (X, Y) [H] in CIE 190's order: X 2H with Y 2, 3, 4, 6,
// 8, 12 H; X 4H with the same; X 8H with Y 4, 6, 8, 12 H; X 12H with Y 4, 6, 8 H.
std::vector<std::array<double, 2>> ugr_room_sizes();

// Guth's position index from CIE 117:1995 Table 4.1 (T/R 0…3, H/R 0…1.9,
// bilinear between its cells) of a source at T across and R along the line
// of sight, H above the eye (any unit). NaN outside the table or next to one
// of its blanks (the source is out of the field of view).
double guth_position_index(double t, double r, double h);

// The zonal split of CIE 190 §4.2 (eq. 9–12) that its background luminance
// starts from, in fractions of the reference flux Φ (the rated lamp flux;
// the luminaire's flux for absolute photometry): R_DLO, R_ULO and the
// cumulative downward fluxes Φ1…4 in the cones of CIE 52's flux code
// (41.41°, 60°, 75.52°, 90°), from the 18 10° zones (intensity at the zone
// midpoints, averaged over the C-planes), the zones 40–50° and 70–80° split
// at 0.130 and 0.547. Scaled to the declared LOR (the computed one where the
// file declares none). `defined` is false for a dark luminaire. Requires
// validate(d).ok().
struct Cie190Zones {
  bool defined = false;
  double reference_lm = kNaN;  // Φ [lm]
  double r_dlo = 0.0, r_ulo = 0.0;  // [1]
  std::array<double, 4> phi{};      // Φ1…4 [1]
};
Cie190Zones cie190_zones(const Distribution& d);

// UGR of room `room` (index into ugr_room_sizes()) and reflectance set
// `reflectance_set` (index into kUgrReflectances), crosswise or endwise.
// NaN when no light reaches the observer. Requires validate(d).ok() and a
// luminous area.
double ugr(const Distribution& d, std::size_t room, std::size_t reflectance_set, bool endwise,
           const UgrOptions& options = {});

// The whole table; undefined (with the reason) without a luminous area or
// when no light reaches the eye in any room. Requires validate(d).ok().
UgrTable ugr_table(const Distribution& d, const UgrOptions& options = {});

}  // namespace gonio::photometry
