// Next-event estimation for the far field: at every vertex where a photon
// meets a surface with non-delta lobes (diffuse reflection, diffuse
// transmission, glossy: sim/bsdf_eval.h), M connection rays go out in
// stratified directions ω_k drawn from those lobes' mixture (density p),
// and each that leaves the luminaire unobstructed (a shadow ray: Embree's
// occlusion query) books
//     power · f(wi, ω_k)·|cos θ_k| / p(ω_k) / M
// into the far-field texel of ω_k. That is the expected power the vertex
// sends out of the luminaire directly, estimated M ways at once instead of
// by the one direction the photon draws. The photon itself goes on exactly
// as without connections (they draw from their own random stream, keyed by
// seed and photon), so its path, fate and the books are the same bytes; its
// own escape after such a vertex, when its last scattering was by a
// non-delta lobe, is not binned into the far field — the connections stand
// for it — while escapes after a mirror or dielectric event, or straight
// from an emitter, are binned as always. Nothing is counted twice, and the
// estimate is unbiased: E[booked] = E[escapes not binned] per direction.
//
// The books: photons and their fates are unchanged (emitted = escaped +
// absorbed + cut off, exact). The far field's total is the binned escapes
// plus the booked connections; the escaped flux of the books is the binned
// escapes plus the covered ones (escapes left out of the far field). The
// two totals agree in expectation, not to the photon: their difference,
// booked − covered, is the estimator's noise (NextEventTally keeps both).
//
// Where connections cannot escape (the walls inside a closed box) they
// cost rays for nothing. Simulation::create traces a pilot of
// kNextEventPilotPhotons photons with connections at every mesh and keeps
// them at the meshes where at least kMinConnectionEscape of them escaped.
//
// Spectral runs: connections at materials that act differently by
// wavelength are not made (their escapes are binned); at grey materials the
// connection's X and Z are the photon's colour at the vertex, scaled like Y.
// Guided emission: not combined (Simulation::create refuses).
#pragma once

#include <cstdint>
#include <string_view>
#include <optional>
#include <vector>

namespace gonio::sim {

enum class NextEventMode : std::uint8_t { Off, On, Auto };
const char* to_string(NextEventMode m);                                // "off", "on", "auto"
std::optional<NextEventMode> parse_next_event_mode(std::string_view text);

inline constexpr int kDefaultConnections = 8;               // M per vertex
inline constexpr std::uint64_t kNextEventPilotPhotons = 8192;
inline constexpr double kMinConnectionEscape = 0.05;        // a mesh's connections that must escape
// Auto: on when at least this share of the pilot's escaped power left after
// a non-delta event at a mesh that keeps its connections.
inline constexpr double kAutoCoveredShare = 0.5;

// What the tracer does (TracerSettings::next_event).
struct NextEventSettings {
  bool enabled = false;
  int connections = kDefaultConnections;  // M ≥ 1
  std::vector<char> meshes;               // per mesh: connect at its surfaces; empty: at every mesh
  bool at(std::uint32_t mesh) const { return meshes.empty() || meshes[mesh] != 0; }
};

// A thread's connections (integer power units, like the far field's).
struct NextEventTally {
  std::vector<std::uint64_t> texel_units;      // booked per texel
  std::vector<std::uint64_t> replicate_units;  // per texel and replicate: texel · K + r (K replicates)
  std::uint64_t vertices = 0;                  // vertices connected from
  std::uint64_t connections = 0;               // shadow rays traced
  std::uint64_t escaped = 0;                   // of them, left the luminaire
  std::uint64_t booked_units = 0;              // Σ booked
  std::uint64_t covered_units = 0;             // escapes not binned (their last event connected)
  // Per mesh (the pilot's choice): connections from it, and those escaped;
  // the power of escapes whose last event was a non-delta one there.
  std::vector<std::uint64_t> mesh_connections, mesh_escaped, mesh_covered_units;

  void reset(std::size_t texels, int replicates, std::size_t meshes);
  void clear();
  void add(const NextEventTally& other);
};

// The pilot's verdict: which meshes keep connections, and whether `auto`
// turns them on (the covered share of kept meshes ≥ kAutoCoveredShare).
struct NextEventChoice {
  std::vector<char> meshes;
  double covered_share = 0.0;  // of the escaped power [0, 1]
  bool worthwhile = false;
};
NextEventChoice choose_next_event(const NextEventTally& pilot, std::uint64_t escaped_units);

}  // namespace gonio::sim
