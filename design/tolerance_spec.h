// A tolerance specification (issue 42): what of a loaded model varies from
// one luminaire to the next, and how. Read from a TOML file (`gonio tolerance
// --tolerances FILE`, docs/tolerance.md) through io/model/toml_tree.h:
//
//   [emitter.LED]                              # an emitter by its name in the model
//   x = { normal = 0.05, truncate = 2 }        # [mm] along the luminaire's C0 axis; σ, ±2σ
//   tilt_x = { uniform = 1.0 }                 # [deg] about the C0 axis, ±1°
//   flux = { values = [-5, 0, 5] }             # [%] of the emitter's flux
//   flux_bin = { factors = [0.93, 1, 1.07], probabilities = [0.25, 0.5, 0.25] }
//   colour_bin = { spectra = ["bin_a.txt", { blackbody_k = 3000 }], probabilities = [0.4, 0.6] }
//   colour_bin = { cct = [2700, 3000] }        # blackbodies, equally likely
//   [material."semi-specular aluminium"]       # a material by its name
//   reflectance = { uniform = 2 }              # [%] of the reflection lobes' weights
//   roughness = { uniform = 20 }               # [%] of the glossy lobe's RMS slopes
//
// Emitters: x, y, z [mm] (the luminaire's photometric frame: x along C0,
// y along C90, z up), tilt_x, tilt_y [deg] (about the C0 and C90 axes),
// flux [%]; on an area or ray-set emitter x … tilt_y move its mesh or its
// rays (origins and directions) about its reference point: a ray set's
// origin as placed (Emitter::position), an area's bounding-box centre. Parts ([part.NAME]: every mesh of that name or under that node,
// "NAME/…"; an instanced mesh's name moves each of its copies about its own
// centre, by one value or, with `independent = true`, each by its own; a
// node's name or path moves its instances as one body):
// x, y, z [mm] and tilt_x, tilt_y [deg] about the luminaire's C0 and C90
// axes through the centre of their bounding box. Materials: reflectance, transmittance, roughness [%], relative
// changes; scattering [%]: a volume's scattering coefficient μs, relative
// (the absorption coefficient stays as it is). Each value has one law: normal (σ, truncated at ±truncate·σ,
// default 3), uniform (±half width), or a list of values. Mistakes are
// errors naming the file's line; check_tolerances() names what the model
// lacks.
#pragma once

#include <array>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "design/design_file.h"
#include "io/model/toml_tree.h"
#include "photometry/diagnostics.h"
#include "photometry/spectrum.h"
#include "sim/scene.h"

namespace gonio::design {

// How one value is distributed about its nominal (0: no change).
struct ToleranceLaw {
  // Bins: an emitter's flux or colour bins (flux_bin, colour_bin): the
  // value is the bin's number 1 … K (0: the model's own emitter, the
  // nominal), bin k drawn with probability probabilities[k − 1].
  enum class Kind { Normal, Uniform, Values, Bins };
  Kind kind = Kind::Uniform;
  double sigma = 0.0;       // Normal
  double truncate = 3.0;    // Normal: limits at ±truncate·σ
  double half_width = 0.0;  // Uniform: ±half_width
  std::vector<double> values;  // Values
  std::vector<double> probabilities;  // Bins: one per bin, summing to 1 (values: 1 … K)
  // The limits the sensitivity analysis sets it to: ±truncate·σ, ±half
  // width, the smallest and largest value.
  double low() const;
  double high() const;
  // The value at probability u in [0, 1) (the inverse of its distribution
  // function; a truncated normal's by bisection on erfc; Values: equally
  // likely).
  double quantile(double u) const;
  // Bins: the first and last bin. quantile: the bin k with
  // P(1) + … + P(k − 1) ≤ u < P(1) + … + P(k) (the discrete inverse
  // distribution function), so a Latin hypercube's N strata put N·P(k) ± 2
  // draws into bin k.
  // Its text: "N(0, σ) ±kσ", "U(±a)", "{v1, v2, …}", "bins {p1, p2, …}".
  std::string text() const;
};

struct Tolerance {
  enum class Target { Emitter, Part, Material, Variable };
  Target target = Target::Emitter;
  std::string name;      // the emitter's, part's (meshes') or material's name in the model
  std::string quantity;  // x, y, z, tilt_x, tilt_y, flux | x, y, z, tilt_x, tilt_y | reflectance, transmittance, roughness, scattering
  ToleranceLaw law;
  int line = 0;  // the value's line in the file
  // [part.NAME] independent = true: each copy of the instanced mesh NAME
  // draws its own value (expand_independent_copies makes one tolerance per
  // copy); false: one value moves every copy (a systematic error).
  bool independent = false;
  // "LED.x"; a variable's name alone ("reflectors[0].radius").
  std::string label() const { return quantity.empty() ? name : name + "." + quantity; }
  const char* unit() const;                                     // "mm", "deg", "%"
  // flux_bin: each bin's factor on the emitter's flux; colour_bin: each
  // bin's spectrum (it replaces the emitter's); names for reports.
  std::vector<double> bin_factors;
  std::vector<photometry::SampledSpectrum> bin_spectra;
  std::vector<std::string> bin_names;
};

struct ToleranceSpec {
  std::string path;  // for messages
  std::vector<Tolerance> tolerances;
};

// Parses a tolerance file's text; errors name `path` and the line.
Result<ToleranceSpec> parse_tolerances(std::string_view text, const std::string& path);
// The same from a parsed TOML table: the file's root, or a design file's
// `[tolerances]` table (`design`: true), where a key other than emitter,
// part, material and variable names a variable of the design with its law
// (`"reflectors[0].radius" = { normal = 0.05 }`). `[variable]` holds such
// keys in either. A variable's value is an absolute change in the design's
// own units of that number.
Result<ToleranceSpec> parse_tolerance_tree(const io::TomlNode& root, const std::string& path, bool design = false);
Result<ToleranceSpec> read_tolerances(const std::string& path);

// A relative spectrum from a text file of two columns, wavelength [nm] and
// value, separated by spaces, tabs, a comma or a semicolon (CRLF, blank
// lines, `#` comments and one header line of text allowed), as measured
// spectra come (/work/shared/corpus/spectra). Errors name the file and line;
// the spectrum is checked by photometry::validate_spectrum.
Result<photometry::SampledSpectrum> read_spectrum_table(const std::string& path);

// Whether `scene` has what each tolerance names: the emitter or material by
// that name; scattering on a material that scatters in volume; reflectance on a
// material that reflects, transmittance on one that transmits, roughness on
// one with a glossy lobe; and whether the limits keep a material's lobes
// within 1. Errors name the file's line and the model's names.
Status check_tolerances(const ToleranceSpec& spec, const sim::SceneDesc& scene);

// Form errors: `[part.NAME] form = { modes = K, rms_um = S }` gives K
// tolerances NAME.form1 … NAME.formK [µm], each the RMS amplitude of one
// mode of the part's sag along the luminaire's up axis: mode k displaces a
// vertex at distance ρ from the axis through the part's bounding-box centre
// by a·√(2k + 1)·P_k(t), t = 2(ρ − ρ_min)/(ρ_max − ρ_min) − 1 (P_k the
// Legendre polynomial, orthonormal over t: RMS a over uniform ρ), and turns
// its shading normal with the slope, n ∝ n − n_z·δ′(ρ)·ρ̂. Each mode's law
// is N(0, S/√K) truncated at ±3σ (expected mean square of the sum S²).
inline constexpr int kMaxFormModes = 8;
// P_k(t) and P′_k(t).
std::array<double, 2> legendre(int k, double t);
// Adds mode `mode` with RMS amplitude `amplitude_um` to the sag of every
// (not instanced) mesh of `part` about the axis through `centre`.
void apply_form_mode(sim::SceneDesc& scene, const std::string& part, int mode, double amplitude_um,
                     const Vec3& centre);

// The largest factor by which tolerance `t`'s limits may be scaled on
// `scene` (which passed check_tolerances): a relative tolerance stays above
// −100 % (0.999 of the way), a reflectance or transmittance keeps the
// material's lobes within 1; +inf for the others.
double largest_scale(const Tolerance& t, const sim::SceneDesc& scene);

// Whether every variable tolerance names a variable of `design` (the error
// names the tolerance's line and lists the design's variables); none may be
// given for a model that is not a design (`design` null).
Status check_variables(const ToleranceSpec& spec, const Design* design);
// `base` with each variable tolerance's variable set to its value in `base`
// plus its value in `values` (spec order; bounds are an optimiser's, not a
// part's, and are not applied).
Design design_with(const Design& base, const ToleranceSpec& spec, std::span<const double> values);
// Whether any variable tolerance has a value other than 0.
bool changes_variables(const ToleranceSpec& spec, std::span<const double> values);

// Replaces each `independent` part tolerance by one per copy of its
// instanced mesh on `scene`, in instance order, each named by the copy's
// placed name "NODE/MESH" (its node's name or CAD path, then the mesh's:
// the name sim::flattened gives it), which names that copy alone. An error
// naming the line where the part is not an instanced mesh.
Status expand_independent_copies(ToleranceSpec& spec, const sim::SceneDesc& scene);

// Applies one value per tolerance (spec order) to the scene; a value of 0
// leaves its part of the scene as it was, bit for bit. The scene must have
// passed check_tolerances().
void apply_tolerances(const ToleranceSpec& spec, std::span<const double> values, sim::SceneDesc& scene);

}  // namespace gonio::design
