// Importance-guided emission: the reference thesis's importance function
// (Krösl 2016, section 5.4.1), an option of the simulation
// (SimulationSettings::importance), measured by `gonio bench --importance`.
//
// The idea: send more photons in emission directions whose light ends in
// "regions of interest" of the far field (edges of intensity regions) and
// fewer, each carrying more power, where the far field is smooth. The thesis
// found that the few heavy photons add noise to smooth regions and switched
// it off; Gonio keeps it as an option so that anyone can measure that.
//
// Emission directions are binned on a small cube map of world directions
// (the emission grid, `emission_face_size`). Each emission texel e has an
// acceptance probability a_e = kPowerUnits / u_e with an integer power u_e ≥
// kPowerUnits: a photon drawn from the emitters as usual (sim/emitters/emission.h) is
// traced with probability a_e and then starts with power u_e power units
// (1/a_e times nominal); otherwise it is dropped before tracing. So
//   E[power traced per photon drawn] = a_e · u_e = kPowerUnits
// exactly (the draw is an exact integer test, below), for any a_e: the far
// field stays unbiased whatever the importance function, and only its noise
// changes. The photon density of emission direction ω becomes p(ω)·a(ω)
// (p: the emitters' own density) and the photon's power ∝ 1/a(ω): the
// thesis's "energy inversely proportional to the importance".
//
// The importance function (thesis, equations of 5.4.1), updated after every
// iteration:
//   1. On the far field so far, per texel T with intensity I_T > 0:
//        imp(T) = |I_N1 + I_N2 + I_N3 + I_N4 − 4 I_T| / I_T
//      (the discrete Laplacian over the four edge neighbours, across cube
//      faces, relative to the texel's own value), clamped to kMaxImportance;
//      0 where I_T = 0. Intensity rather than the thesis's photon count,
//      because texels differ in solid angle and photons in power.
//   2. During the next iteration every photon that escapes to texel T adds
//      imp(T) to the emission texel it was emitted into (back-projection:
//      the thesis's photon storage, without storing photons: the map of the
//      previous iteration is used instead of the current one).
//   3. After it, the mean importance per emission texel (sum over photons
//      traced from that texel, absorbed ones adding 0, divided by their
//      number: a mean, so that the photon density does not feed back into
//      its own importance) is smoothed by the multi-resolution filter
//      (sim/filter/preview_filter.h, bilateral, the thesis's fixed threshold: the
//      thesis filters its importance image the same way), giving g_e, and
//        a_e = max(min_acceptance, g_e / max g)
//      The floor bounds the photons' power at 1/min_acceptance times nominal.
//   The first two iterations are plain emission (every a_e = 1): the first
//   gives the far field for imp(T), the second back-projects it; guidance
//   starts with the third.
//
// Determinism: the acceptance test draws from the photon's own random
// numbers (seed, i), importance sums are integers (fixed point, 2⁻²⁴), the
// filter is deterministic, so a guided run gives the same bytes for any
// thread count, like a plain one.
#pragma once

#include <cstdint>
#include <vector>

#include "sim/detectors/cube_map.h"
#include "sim/detectors/far_field.h"
#include "sim/samplers/random.h"

namespace gonio::sim {

struct ImportanceSettings {
  bool enabled = false;            // off: plain emission (the default)
  int emission_face_size = 32;     // emission grid: texels per cube face edge, 1…1024
  double min_acceptance = 1.0 / 16.0;  // floor of a_e, in (0, 1]: photon power ≤ 16 × nominal
};

// Largest importance value booked per photon (a texel between dark
// neighbours and one photon can otherwise reach any value).
inline constexpr double kMaxImportance = 64.0;
// Fixed-point scale of importance sums.
inline constexpr double kImportanceScale = 0x1.0p24;

// What the guided tracer accumulates per thread (integers: order-free sums).
struct GuideTally {
  std::vector<std::uint64_t> importance_sum;  // per emission texel, kImportanceScale units
  std::vector<std::uint64_t> traced;          // photons traced per emission texel
  // Per far-field texel: power units of escaped photons above kPowerUnits each
  // (the tracer books kPowerUnits per escape; this is the rest).
  std::vector<std::uint64_t> extra_units;
  std::uint64_t dropped = 0;                  // photons drawn and not traced

  void add(const GuideTally& other);
  void clear();
};

class EmissionGuide {
 public:
  // A guide that accepts every photon (plain emission) until the first
  // update. GONIO_CHECKs the settings (checked by Simulation::create).
  EmissionGuide(const ImportanceSettings& settings, int far_field_face_size);

  // An empty tally of the right sizes.
  GuideTally make_tally() const;

  const CubeMapGrid& emission_grid() const { return emission_grid_; }
  std::uint32_t emission_texel(const Vec3& world_direction) const {
    return static_cast<std::uint32_t>(emission_grid_.texel_of(world_direction));
  }
  // Power a photon from emission texel e starts with, ≥ kPowerUnits.
  std::uint64_t power_units(std::uint32_t e) const { return power_units_[e]; }
  // Acceptance probability of emission texel e: kPowerUnits / power_units(e).
  double acceptance(std::uint32_t e) const;
  // Whether a photon drawn into emission texel e is traced: true with
  // probability exactly kPowerUnits / power_units(e) (one draw from rng when
  // that is below 1, none otherwise).
  bool accept(std::uint32_t e, PhotonRandom& rng) const;
  // imp(T) of far-field texel T in kImportanceScale units.
  std::uint32_t importance(std::size_t far_texel) const { return importance_[far_texel]; }

  // After an iteration: new acceptance from that iteration's tally, and new
  // imp(T) from the far field so far (same face size as the simulation's).
  void update(const GuideTally& iteration, const FarField& far_field);

  // The smoothed mean importance g_e of the last update (empty before).
  const std::vector<double>& smoothed_importance() const { return smoothed_; }

 private:
  ImportanceSettings settings_;
  CubeMapGrid emission_grid_;
  int far_face_size_;
  std::vector<std::uint64_t> power_units_;  // per emission texel
  std::vector<std::uint32_t> importance_;   // per far-field texel
  std::vector<double> smoothed_;
};

}  // namespace gonio::sim
