// The energy ledger: where the emitted light went — escaped to the far
// field, absorbed (by which mesh and material), or cut off by the bounce
// limit — per emitter, per mesh and per material.
//
// The tracer counts in integers: photons, and photon power in fixed-point
// units (kPowerUnits per photon of nominal power; only importance-guided
// emission gives photons other powers, and scattering never changes them).
// So the books close exactly and whatever the thread count:
//   emitted = escaped + absorbed + cutoff        (photons and power units)
// and in lumens to rounding (units × photon power / kPowerUnits).
//
// Spectral runs also keep radiant books: the same power units once more,
// per bin of sim::WavelengthSampler (an emitter's spectrum table, or a drawn
// wavelength), booked when the photon ends, from its colour state then; the
// watts follow at the end (the method: WavelengthSampler::bin_count). The
// emitted watts are exact, and emitted = escaped + absorbed + cutoff holds
// in W to rounding.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "photometry/colour.h"

#include "sim/scene.h"

namespace gonio::sim {

// A radiant bin's watts per lumen in each 5 nm band of the CIE 1931 table
// (sim/tracer/spectral.h's WavelengthSampler::radiant_bins).
using RadiantPerLm = std::array<double, photometry::kCmfCount>;

// Fixed-point units of power per photon of nominal power (2^24).
inline constexpr std::uint64_t kPowerUnits = std::uint64_t{1} << 24;

// One line of the books: a photon count and their power.
struct TallyLine {
  std::uint64_t photons = 0;
  std::uint64_t power_units = 0;
  void add(std::uint64_t power) {
    ++photons;
    power_units += power;
  }
  TallyLine& operator+=(const TallyLine& o) {
    photons += o.photons;
    power_units += o.power_units;
    return *this;
  }
};

// The integer books the tracer keeps (per thread, then summed: integer sums
// do not depend on order).
struct LedgerTally {
  struct PerEmitter {
    TallyLine emitted, escaped, absorbed, cutoff;
  };
  struct PerMesh {
    std::uint64_t hits = 0;  // photons that reached the surface
    TallyLine absorbed, cutoff;
  };
  std::vector<PerEmitter> emitters;
  std::vector<PerMesh> meshes;
  std::uint64_t rays = 0;                // ray queries traced
  std::uint64_t volume_events = 0;       // free paths that ended inside a volume
  // Spectral runs only (empty otherwise): power units per radiant bin
  // (WavelengthSampler::bin_count). A table bin's `emitted` holds every
  // photon's share, its fates those of photons never drawn; a wavelength
  // bin's lines hold the photons drawn at it (emitted: all of them).
  struct Bins {
    std::vector<std::uint64_t> emitted, escaped, absorbed, cutoff;
  };
  Bins bins;

  LedgerTally() = default;
  LedgerTally(std::size_t emitter_count, std::size_t mesh_count, std::size_t bin_count = 0)
      : emitters(emitter_count), meshes(mesh_count) {
    for (auto* v : {&bins.emitted, &bins.escaped, &bins.absorbed, &bins.cutoff}) v->assign(bin_count, 0);
  }
  void add(const LedgerTally& other);
  void clear();
};

// A line in lumens.
struct LedgerLine {
  std::uint64_t photons = 0;
  double flux_lm = 0.0;  // [lm]
};

struct EmitterLedger {
  std::string name;
  LedgerLine emitted, escaped, absorbed, cutoff;
};

struct MeshLedger {
  std::string name;
  std::string material;
  std::uint64_t placements = 1;  // 1 for world geometry; an instanced mesh's instances
                                 // (its counts are the sums over them)
  std::uint64_t hits = 0;  // photons that reached its surface (scattered, absorbed or cut off there)
  LedgerLine absorbed;     // absorbed at its surface or inside its volume
  LedgerLine cutoff;       // cut off by the bounce limit on reaching it
};

struct MaterialLedger {
  std::string name;
  std::uint64_t hits = 0;
  LedgerLine absorbed, cutoff;
};

// The radiant books of a spectral run [W], over 360–830 nm.
struct RadiantLedger {
  double emitted_w = 0.0, escaped_w = 0.0, absorbed_w = 0.0, cutoff_w = 0.0;
  // The escaped radiant power in each 5 nm band of sim/tracer/spectral.h's grid
  // (band k centred on wavelength_nm(k)) [W]; the luminaire's total spectrum.
  std::vector<double> escaped_band_w;
  // emitted − escaped − absorbed − cutoff [W]: zero to rounding.
  double imbalance_w() const { return emitted_w - escaped_w - absorbed_w - cutoff_w; }
};

struct Ledger {
  double photon_power_lm = 0.0;  // power of a photon of kPowerUnits (nominal) [lm]
  LedgerLine emitted, escaped, absorbed, cutoff;
  std::vector<EmitterLedger> emitters;  // in SceneDesc order
  std::vector<MeshLedger> meshes;       // in SceneDesc order
  std::vector<MaterialLedger> materials;// in SceneDesc order
  bool spectral = false;                 // a spectral run: `radiant` holds its books
  RadiantLedger radiant;

  // emitted = escaped + absorbed + cutoff, in photons (exact).
  bool photons_close() const {
    return emitted.photons == escaped.photons + absorbed.photons + cutoff.photons;
  }
  // emitted − escaped − absorbed − cutoff [lm]: zero to rounding.
  double flux_imbalance_lm() const {
    return emitted.flux_lm - escaped.flux_lm - absorbed.flux_lm - cutoff.flux_lm;
  }
};

// Lumens from the integer books: `total_flux_lm` is the flux the emitters
// send out, shared by the photons emitted in proportion to the power units
// they started with (equally, unless emission is guided: sim/emitters/emission_guide.h).
// `radiant_bins`: a spectral run's bins (WavelengthSampler::radiant_bins;
// null for grey runs), which give the radiant books.
Ledger make_ledger(const LedgerTally& tally, const SceneDesc& scene, double total_flux_lm,
                   const std::vector<RadiantPerLm>* radiant_bins = nullptr);

}  // namespace gonio::sim
