// The data model of a measured or simulated light distribution: the common
// ground of IES LM-63 and EULUMDAT files and of simulation results.
//
// Conventions (see docs/conventions.md):
// - Angles in this model are degrees, exactly as files carry them, so that a
//   round trip through a file is exact. Functions that take directions take
//   unit vectors or radians and say so.
// - Intensities are candela, multipliers and conversion factors applied.
//   For relative photometry they are the candela of the luminaire fitted with
//   the rated lamps (`lamps[*].flux_lm`); for absolute photometry
//   (`absolute == true`) they are the candela measured, and no lamp flux exists.
// - Type C: vertical angle γ, 0° = nadir, 180° = zenith; horizontal angle C,
//   the C-plane, counter-clockwise seen from above, C0 along LM-63's length
//   axis (an EULUMDAT linear luminaire's lamp axis lies along C90–C270: see
//   LuminousOpening). Local photometric frame: x = C0, y = C90, z = up (zenith),
//   so the direction (C, γ) is (sin γ cos C, sin γ sin C, −cos γ).
// - Types A and B: horizontal angle H (−90…90 or 0…90 with lateral symmetry)
//   and vertical angle V (−90…90); see photometry/angles.h for the frames.
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "photometry/diagnostics.h"

namespace gonio::photometry {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// LM-63 photometric type codes: C = 1, B = 2, A = 3. EULUMDAT is always Type C.
enum class PhotometricType { C = 1, B = 2, A = 3 };

// Which part of the horizontal range the stored planes cover.
enum class Symmetry {
  None,        // Type C: C 0…360 (LM-63 last angle 360, LDT Isym 0).
               // Types A/B: H −90…90.
  Rotational,  // Type C: one plane for all C (LM-63 single angle 0, LDT Isym 1).
  C0_C180,     // Type C: mirror about the C0–C180 plane, I(C) = I(360° − C);
               // planes C 0…180 (LM-63 last angle 180, LDT Isym 2).
  C90_C270,    // Type C: mirror about the C90–C270 plane, I(C) = I(180° − C);
               // planes C 90…270 (LM-63-1995 range 90–270, LDT Isym 3).
  Quadrant,    // Type C: mirror about both planes; planes C 0…90
               // (LM-63 last angle 90, LDT Isym 4).
  Lateral,     // Types A/B: I(−H, V) = I(H, V); H 0…90.
};

const char* to_string(PhotometricType type);
const char* to_string(Symmetry symmetry);

// Shape of the luminous opening (LM-63-2002/2019 table of signed dimensions;
// EULUMDAT: rectangular, or circular when its width is 0).
enum class OpeningShape {
  Point,                      // all dimensions zero
  Rectangular,                // flat, width × length, height 0
  RectangularWithSides,       // box, width × length × height
  Circular,                   // flat disc, diameter = width = length
  Ellipse,                    // flat, axes width × length
  VerticalCylinder,           // diameter × height
  VerticalEllipticalCylinder, // width × length × height
  Sphere,                     // diameter
  Ellipsoid,                  // width × length × height
  HorizontalCylinderAlongLength,     // axis along C0–C180
  HorizontalEllipticalCylinderAlongLength,
  HorizontalCylinderAlongWidth,      // axis along C90–C270
  HorizontalEllipticalCylinderAlongWidth,
  VerticalCircle,             // disc facing the horizon (LM-63-2019)
  VerticalEllipse,
};

const char* to_string(OpeningShape shape);

// Unit of length a file gave dimensions in.
enum class LengthUnit { Metre, Foot };

// Luminous opening. Dimensions are positive, in metres, whatever sign
// encoding the file used. `length_m` runs along C0–C180, `width_m` along
// C90–C270, `height_m` vertically: LM-63's definitions (its length is
// measured along the 0–180° photometric plane, its width along 90–270°).
// EULUMDAT's luminous length lies along C90–C270 (a linear luminaire's lamp
// axis; C0–C180 is its transverse plane), so the LDT reader and writer
// exchange length and width (io/photometric/ldt.h).
struct LuminousOpening {
  OpeningShape shape = OpeningShape::Point;
  double length_m = 0.0;  // [m]
  double width_m = 0.0;   // [m]
  double height_m = 0.0;  // [m]
  // EULUMDAT only: heights of the luminous area in the C0, C90, C180 and
  // C270 planes [m]; NaN where unknown.
  double side_height_m[4] = {kNaN, kNaN, kNaN, kNaN};
  // LM-63 units type (1 feet, 2 metres) the dimensions were read in; an IES
  // writer gives them back in this unit so that a round trip writes the
  // same numbers.
  LengthUnit file_unit = LengthUnit::Metre;
};

// LM-63-2019 file generation type (its Table 2): how the data was produced.
// The LM-63 code is 1.ABCDE with one flag per digit: A accredited lab,
// B interpolated angle set, C lumen scaled, D computer simulation,
// E undefined (io/photometric/ies.h converts codes).
enum class FileGenerationType {
  Undefined,                          // 1.00001: unknown, e.g. converted from an older file
  ComputerSimulation,                 // 1.00010
  UnaccreditedLab,                    // 1.00000
  UnaccreditedLabScaled,              // 1.00100: lumen scaled
  UnaccreditedLabInterpolated,        // 1.01000: interpolated angle set
  UnaccreditedLabInterpolatedScaled,  // 1.01100
  AccreditedLab,                      // 1.10000
  AccreditedLabScaled,                // 1.10100
  AccreditedLabInterpolated,          // 1.11000
  AccreditedLabInterpolatedScaled,    // 1.11100
};

const char* to_string(FileGenerationType type);

// Outer dimensions of the luminaire body (EULUMDAT fields 13–15, which the
// LDT reader and writer exchange as they do the opening's: see
// LuminousOpening). A width of zero means a round luminaire of diameter
// `length_m`. NaN where unknown.
struct LuminaireDimensions {
  double length_m = kNaN;  // [m] along C0–C180, or the diameter
  double width_m = kNaN;   // [m] along C90–C270; 0 for round luminaires
  double height_m = kNaN;  // [m]
};

// One set of identical lamps (EULUMDAT 26a–f; LM-63 has exactly one set).
struct LampSet {
  int count = 1;                  // number of lamps, > 0
  std::string type;               // lamp type or description
  double flux_lm = kNaN;          // rated flux of the whole set [lm]; NaN for absolute photometry
  std::string color;              // colour appearance / correlated colour temperature
  std::string color_rendering;    // colour rendering group or index
  double power_w = kNaN;          // wattage including ballast [W]; NaN if unknown
};

// LM-63 TILT: how output changes with the lamp's tilt.
struct Tilt {
  enum class Kind { None, Include, File };
  Kind kind = Kind::None;
  std::string file;               // TILT=<file>: the name as written in the file
  int lamp_geometry = 0;          // lamp-to-luminaire geometry 1, 2 or 3; 0 if none
  std::vector<double> angles_deg; // tilt angles [deg], increasing
  std::vector<double> factors;    // multiplying factor per angle
};

// One LM-63 keyword line, `[KEY] value`; [MORE] continuations are joined into
// the preceding keyword's value with '\n'. EULUMDAT header strings are mapped
// onto the same keys (see io/photometric/ldt.h), so both formats share one list.
struct Keyword {
  std::string key;    // without brackets, upper case, e.g. "MANUFAC", "_USER"
  std::string value;
};

// A spectral power distribution of an emitter (IES TM-33 SpectralData /
// EmitterSpectral), kept for round trips through formats that hold one;
// nothing is derived from it.
struct Spectrum {
  std::string emitter;                // the emitter it belongs to; empty if unnamed
  bool normalized = false;            // relative values (peak 1) rather than W/nm
  std::vector<double> wavelength_nm;  // strictly increasing [nm]
  std::vector<double> values;         // one per wavelength, multiplier applied
};

// A light distribution as files exchange it.
struct Distribution {
  PhotometricType type = PhotometricType::C;
  Symmetry symmetry = Symmetry::None;

  // Strictly increasing angle lists [deg]. Type C: vertical = γ in [0, 180],
  // horizontal = C in the range `symmetry` implies. Types A/B: V in [−90, 90],
  // H in [−90, 90] (or [0, 90] with Symmetry::Lateral).
  std::vector<double> vertical_deg;
  std::vector<double> horizontal_deg;

  // Intensities [cd], one row per horizontal angle:
  // candela[h * vertical_deg.size() + v].
  std::vector<double> candela;

  bool absolute = false;          // absolute photometry: no rated lamp flux
  std::vector<LampSet> lamps;     // at least one set when read from a file
  // EULUMDAT standard sets 2…n: alternative equipment of the same luminaire
  // for which the relative distribution also holds. They are not part of
  // `lamps`: the candela and rated_lamp_flux_lm() refer to `lamps` alone.
  std::vector<LampSet> alternative_lamps;

  double ballast_factor = 1.0;    // LM-63 ballast factor (kept, not applied)
  double input_watts = kNaN;      // luminaire input power [W]; NaN if unknown

  LuminousOpening opening;
  LuminaireDimensions luminaire;
  Tilt tilt;
  std::vector<Keyword> keywords;

  // EULUMDAT fields without an LM-63 counterpart; NaN / empty where unknown.
  double declared_dff_percent = kNaN;   // downward flux fraction as declared [%]
  double declared_lor_percent = kNaN;   // light output ratio as declared [%]
  double measurement_tilt_deg = kNaN;   // tilt of the luminaire during measurement [deg]
  std::vector<double> direct_ratios;    // utilisation direct ratios for k = 0.6…5 (10 values)
  // EULUMDAT type indicator Ityp as read: 0 point source without symmetry,
  // 1 rotationally symmetric, 2 linear luminaire, 3 point source with other
  // symmetry. Empty where unknown: the LDT writer then derives one.
  std::optional<int> ldt_type_indicator;

  // LM-63 fields without an EULUMDAT counterpart, kept for round trips.
  // LM-63-1986…1995 "ballast-lamp photometric factor" (second value of the
  // line after the photometric line; LM-63-2002 calls it "future use" and
  // LM-63-2019 puts the file generation type there). Kept, not applied.
  double ballast_lamp_factor = 1.0;
  FileGenerationType file_generation = FileGenerationType::Undefined;  // LM-63-2019

  // TM-33 spectral distributions (neither LM-63 nor EULUMDAT holds one).
  std::vector<Spectrum> spectra;

  std::size_t vertical_count() const { return vertical_deg.size(); }
  std::size_t horizontal_count() const { return horizontal_deg.size(); }

  // Intensity at grid point (h, v) [cd].
  double at(std::size_t h, std::size_t v) const { return candela[h * vertical_deg.size() + v]; }
  double& at(std::size_t h, std::size_t v) { return candela[h * vertical_deg.size() + v]; }

  // Sum of the rated flux of every lamp set [lm]; NaN for absolute photometry.
  double rated_lamp_flux_lm() const;

  // First keyword with this key (case-sensitive, without brackets), if any.
  const Keyword* find_keyword(std::string_view key) const;
  // Sets the first keyword with this key, or appends it.
  void set_keyword(std::string_view key, std::string value);
};

// Structural invariants every model must satisfy before anything is derived
// from it: non-empty strictly increasing finite angle lists within their
// ranges, horizontal range consistent with `symmetry` and `type`, candela
// count = horizontal × vertical, all intensities finite and ≥ 0, lamp sets
// valid. Returns the first violation (without a file location; readers add it).
Status validate(const Distribution& d);

// The same distribution over the whole horizontal range, Symmetry::None.
// Type C: planes cover C in [0, 360] with C = 360 a copy of C = 0, every
// stored plane mirrored by the symmetry's reflections (a rotational
// distribution becomes the two planes 0 and 360). A full-range input whose
// last plane is below 360 gains a closing plane at 360 copied from 0.
// Types A/B with Symmetry::Lateral: H mirrored to −H.
// Requires validate(d).ok().
Distribution expand_symmetry(const Distribution& d);

// One plane of expand_symmetry(d): its horizontal angle and the stored rows
// its intensities come from, (1 − t)·row + t·row_b. Planes copied from a
// stored row (the usual case) have row_b = row and t = 0; only the plane at
// C = 0 that closes a full-range Type C input without one is a blend of the
// two planes beside the seam (and so is its copy at C = 360).
struct ExpandedPlane {
  double angle_deg;   // C or H of the expanded plane [deg]
  std::size_t row;    // stored row (index into horizontal_deg)
  std::size_t row_b;  // second stored row of a blend; = row otherwise
  double t;           // blend weight of row_b, in [0, 1)
};

// The planes of expand_symmetry(d), in increasing angle, without building the
// expanded intensities (what integration and resampling need). O(n log n) in
// the number of stored planes. Requires validate(d).ok() (only the sizes are
// checked here: the full check is a pass over the data).
std::vector<ExpandedPlane> expanded_planes(const Distribution& d);

// Intensity [cd] at a direction given by grid angles [deg], by bilinear
// interpolation on a distribution returned by expand_symmetry():
// Type C: (c_deg, gamma_deg), C taken modulo 360 so the seam is continuous;
//   exactly at γ = 0° or 180° the mean over the planes [0, 360) is returned,
//   so the poles have one value whatever C is asked for. Outside the stored γ
//   range the intensity is 0 (LM-63: unmeasured directions emit nothing).
// Types A/B: (h_deg, v_deg); 0 outside the stored ranges.
double interpolate(const Distribution& expanded, double horizontal_deg, double vertical_deg);

// interpolate() at every point of the tensor grid horizontal_deg × vertical_deg,
// as out[i * vertical_deg.size() + j] for (horizontal_deg[i], vertical_deg[j]):
// the same values, with one search per grid line instead of two per point.
std::vector<double> interpolate_grid(const Distribution& expanded, const std::vector<double>& horizontal_deg,
                                     const std::vector<double>& vertical_deg);

}  // namespace gonio::photometry
