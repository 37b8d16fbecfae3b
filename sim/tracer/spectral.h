// Spectral photon transport: the wavelength each photon carries, how it is
// drawn, and what it changes on the way.
//
// Scheme (stated, as the issue asks): one wavelength per photon, drawn from
// the emitter's spectrum weighted by the luminous efficiency ȳ, on the 95
// wavelengths of the CIE 1931 table (360–830 nm, 5 nm):
//   p(λ_k | γ) = S_γ(λ_k) ȳ(λ_k) / Σ_j S_γ(λ_j) ȳ(λ_j).
// Every photon so keeps the luminous power it carries without spectra (the Y
// far field is the same photon histogram as today) and adds x̄(λ)/ȳ(λ) and
// z̄(λ)/ȳ(λ) of its Y to X and Z: their expectation is exactly CIE 15's 5 nm
// summation of the emitted spectrum, so X, Y and Z are unbiased in every
// direction. On the way a photon meets each surface with the material's
// weights at its own wavelength (sim::Material's spectra, dispersion), the
// same Russian roulette as the grey tracer, which keeps every estimate
// unbiased per wavelength. Direction first (the emitter's profile, as
// without spectra), then the wavelength from the spectrum at that γ: the
// intensity distribution stays the emitter's.
//
// The draw is deferred (a conditional expectation, "Rao–Blackwellised"):
// until a photon meets a material that acts differently by wavelength, its
// path does not depend on λ, so it carries the expected X/Y and Z/Y of its
// emission spectrum at its γ instead of one wavelength's; the wavelength is
// drawn (from the same p(λ | γ)) only at the first such material. Light that
// meets only grey surfaces so has no colour noise beyond that of its
// directions; the estimate stays unbiased, since λ is independent of the
// path up to that event. From the draw on the photon carries hero
// wavelengths (PhotonColour below), which change its X and Z, never its Y.
//
// X and Z are integers per texel in units of 2⁻¹⁷ of one photon's Y
// (kColourUnits): the ratio of each wavelength is rounded once, a relative
// error below 4·10⁻⁶, and 2³⁹ photons at the largest ratio (z̄/ȳ ≈ 155 at
// 360 nm) still fit in 64 bits. Integer sums keep the bytes independent of
// threads, iterations and ranks.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "photometry/colour.h"
#include "photometry/diagnostics.h"
#include "sim/detectors/far_field.h"
#include "sim/ledger.h"
#include "sim/samplers/random.h"
#include "sim/scene.h"

namespace gonio::sim {

// The wavelengths photons carry: the CIE 1931 table's.
inline constexpr int kWavelengthCount = photometry::kCmfCount;
inline double wavelength_nm(int k) { return photometry::kCmfFirstNm + photometry::kCmfStepNm * k; }

// X or Z units per photon of Y (see above).
inline constexpr std::uint64_t kColourUnits = std::uint64_t{1} << 17;

// Checks a material's spectra: values in [0, 1] (reflectance,
// transmittance), n >= 1 (ior_nm), abbe_number >= 0 and finite, and the
// weights at every wavelength sum to at most 1.
Status validate_spectral_material(const Material& m);

// The refractive index of a material at a wavelength: ior_nm, else the Abbe
// number's Cauchy curve through n_d = ior, else ior.
double ior_at(const Material& m, double wavelength_nm);
// The material as it acts at one wavelength: lobe weights scaled by its
// spectra, the dielectric's index at that wavelength, spectra cleared.
Material at_wavelength(const Material& m, double wavelength_nm);

// A spectral photon's colour on its way: its wavelength index once drawn,
// and what it needs to draw it (its emitter and cos γ at emission).
//
// Hero wavelengths (Wilkie et al. 2014, "Hero Wavelength Spectral
// Sampling", EGSR): once drawn, the wavelength λ_h (the hero, which alone
// steers the path) comes with kHeroCount − 1 companions, λ_h rotated by
// kHeroStride grid steps (mod 95: the offsets form a group, as the balance
// heuristic over "which one was the hero" needs). Each keeps the
// probability of the hero's path at its own wavelength relative to the
// hero's (the product over events of the chosen lobe's weight at λ_j over
// its weight at λ_h); an escape's X/Y is then the balance-heuristic
// combination Σ_j q_j w_j (x̄/ȳ)(λ_j) / Σ_j q_j w_j with q = p(λ | γ) — its
// Y stays one photon's, so the Y far field is unchanged, and no random
// number is drawn for it. A dispersive dielectric's refraction sends each
// wavelength elsewhere: there the companions end (their path probability
// is zero) and the hero goes on alone, as Wilkie et al. and pbrt-v4 do —
// which is why this does not help colour noise behind dispersive lenses,
// only behind surfaces whose weights vary with wavelength.
inline constexpr int kHeroCount = 5;
inline constexpr int kHeroStride = 19;  // 5 × 19 = 95 wavelengths
inline int hero_companion(int hero, int j) { return (hero + kHeroStride * j) % kWavelengthCount; }

struct PhotonColour {
  static constexpr int kUndrawn = -1;
  int wavelength = kUndrawn;
  std::uint32_t emitter = 0;
  double cos_gamma = 1.0;
  // Path probabilities of the hero's companions relative to the hero's
  // (index 0, the hero itself, stays 1); all 0 after a dispersive refraction.
  std::array<double, kHeroCount> hero_weight{1.0, 1.0, 1.0, 1.0, 1.0};
};

// Draws photons' wavelength indices for the emitters of a scene.
class WavelengthSampler {
 public:
  // Errors name the emitter. An emitter without a spectrum emits the
  // equal-energy spectrum.
  static Result<WavelengthSampler> create(const SceneDesc& scene);

  // The index k of a photon's wavelength, given its emitter and cos γ of
  // its direction from the emitter's axis. One uniform draw (two where the
  // spectrum changes with γ).
  int sample(std::uint32_t emitter, double cos_gamma, PhotonRandom& rng) const;

  // The probability of index k at a γ (for tests: the density sample() draws from).
  double pmf(std::uint32_t emitter, double cos_gamma, int k) const;

  // X and Z per photon of Y in kColourUnits of a photon whose wavelength
  // was never drawn: the expectation over p(λ | γ), rounded.
  std::pair<std::uint64_t, std::uint64_t> expected_units(std::uint32_t emitter, double cos_gamma) const;

  // X and Z per photon of Y in kColourUnits of a drawn photon at its end:
  // the hero-wavelength combination above, rounded.
  std::pair<std::uint64_t, std::uint64_t> hero_units(const PhotonColour& colour) const;

  // For each k, X and Z per photon of Y in kColourUnits: round(x̄/ȳ · 2¹⁷),
  // round(z̄/ȳ · 2¹⁷); 0 where ȳ is 0 (never drawn).
  const std::array<std::uint64_t, kWavelengthCount>& x_units() const { return x_units_; }
  const std::array<std::uint64_t, kWavelengthCount>& z_units() const { return z_units_; }

  // The radiant books (sim/ledger.h). Method: bins of integer power units.
  // Bins 0 … kWavelengthCount − 1 are the drawn wavelengths; the following
  // ones the emitters' spectrum tables (one per over_gamma entry). Every
  // photon's power goes to the table bins of its emitter at its γ (between
  // two entries split in integers in the proportion of the interpolation):
  // their watts are exact, S(λ_k) / (Km Σ S ȳ) W per lm in band k — the
  // spectrum's own radiant/luminous ratio (CIE 15 5 nm sums over 360–830 nm,
  // Km = photometry::kKm_lm_per_W). A photon never drawn also books its fate
  // there (its path did not depend on λ). A drawn one books its fate in its
  // wavelength's bin; the radiant power that drawn photons emitted in band k
  // (exact, from their tables) then ends as the drawn photons of band k did
  // (a ratio estimator stratified by wavelength; a band with fewer than
  // 256 photons drawn is pooled with its neighbours up to 256, as
  // material spectra hold their end values: consistent, and exact where
  // the fates do not depend on λ). Weighting each drawn photon by 1/ȳ(λ) instead would
  // be unbiased but useless: photons are drawn ∝ S ȳ, so the far red and
  // violet, which carry a fifth of a 3000 K lamp's watts, are almost never
  // drawn (measured: 23 % low at 8·10⁴ photons).
  std::size_t bin_count() const { return kWavelengthCount + table_count_; }
  struct BinShare {
    std::uint32_t bin[2] = {0, 0};
    std::uint64_t units[2] = {0, 0};  // units[0] + units[1] = the photon's power units
  };
  // The table bins of a photon's emitter at its γ (its wavelength, drawn or
  // not, does not matter).
  BinShare bins(const PhotonColour& colour, std::uint64_t power_units) const;
  // Per bin, its radiant power per lumen in each 5 nm band k [W/lm] (their
  // sum: the bin's W per lm).
  const std::vector<RadiantPerLm>& radiant_bins() const { return bin_radiant_; }

 private:
  struct Table {
    double gamma_rad;
    std::array<double, kWavelengthCount> cdf;  // cumulative, last = 1
    double x_per_y, z_per_y;                   // expectations of x̄/ȳ and z̄/ȳ (rounded ratios)
    std::uint32_t bin = 0;                     // its radiant bin
  };
  struct PerEmitter {
    std::vector<Table> tables;  // increasing γ
  };
  std::size_t table_count_ = 0;
  std::vector<RadiantPerLm> bin_radiant_;
  int draw(const Table& t, double u) const;
  std::vector<PerEmitter> emitters_;
  std::array<std::uint64_t, kWavelengthCount> x_units_{};
  std::array<std::uint64_t, kWavelengthCount> z_units_{};
};

}  // namespace gonio::sim
