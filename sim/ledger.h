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
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sim/scene.h"

namespace gonio::sim {

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

  LedgerTally() = default;
  LedgerTally(std::size_t emitter_count, std::size_t mesh_count)
      : emitters(emitter_count), meshes(mesh_count) {}
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

struct Ledger {
  double photon_power_lm = 0.0;  // power of a photon of kPowerUnits (nominal) [lm]
  LedgerLine emitted, escaped, absorbed, cutoff;
  std::vector<EmitterLedger> emitters;  // in SceneDesc order
  std::vector<MeshLedger> meshes;       // in SceneDesc order
  std::vector<MaterialLedger> materials;// in SceneDesc order

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
// they started with (equally, unless emission is guided: sim/emission_guide.h).
Ledger make_ledger(const LedgerTally& tally, const SceneDesc& scene, double total_flux_lm);

}  // namespace gonio::sim
