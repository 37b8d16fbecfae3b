// Next-event estimation for the far field: at every vertex where a photon
// meets a surface with non-delta lobes (diffuse reflection, diffuse
// transmission, glossy: sim/bsdfs/bsdf_eval.h), M connection rays go out in
// stratified directions ω_k drawn from those lobes' mixture (density p),
// and each that leaves the luminaire unobstructed (a shadow ray: Embree's
// occlusion query) books
//     power · f(wi, ω_k)·|cos θ_k| / p(ω_k) / M
// into the far-field texel of ω_k. That is the expected power the vertex
// sends out of the luminaire directly, estimated M ways at once instead of
// by the one direction the photon draws. The M directions are a rank-1
// lattice (k/M, k·φ mod 1) shifted by two of the photon's own numbers —
// under Sobol' its next two coordinates, so that the shifts are stratified
// across photons too (measured: 1.4× fewer photons to 1 % on the LED array
// than a separate stream; a second Owen scramble of the same points instead
// correlates with the path's coordinates and biased the bell by 1.5 %).
// The photon then goes on as it would (its later draws shift by those
// two). Its own escape after such a vertex, when its last scattering was
// by a connected non-delta lobe, is not binned into the far field — it is
// one more sample of the same direct escape, and books its share by
// multiple importance sampling (issue 43; before, the connections stood for
// it alone): with the balance heuristic over the M connections (density p)
// and the photon (whose density towards ω, per unit of its power, is
// f·|cos| itself), the connections book power · f/(M·p + f) each instead of
// power · f/(p·M), and the photon's escape books power · f/(M·p + f) at its
// direction. The weights M·p/(M·p + f) and f/(M·p + f) sum to one wherever
// either strategy reaches. Escapes after a mirror or dielectric event, or
// straight from an emitter, are binned as always. Nothing is counted twice,
// and the estimate is unbiased: E[booked] = E[escapes not binned] per
// direction.
//
// The books: every photon's fate is booked as always (emitted = escaped +
// absorbed + cut off, exact in photons). The far field's total is the
// binned escapes plus the booked connections; the escaped flux of the books
// is the binned escapes plus the covered ones (escapes left out of the far
// field). The two agree in expectation, not to the photon: their
// difference, booked − covered, is the estimator's noise (NextEventTally
// keeps both; report.json shows them).
//
// Where connections cannot escape (the walls inside a closed box, the
// reflection side of a diffuser lit from inside) they cost rays for
// nothing. Simulation::create traces a pilot of the run's first
// kNextEventPilotPhotons photons with two connections at every vertex and
// keeps them per mesh, side of incidence and lobe ("slot") where at least
// kMinConnectionEscape of them escaped; elsewhere the photons' escapes are
// binned as without.
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

#include "sim/bsdfs/bsdf_eval.h"
#include "sim/bsdfs/material.h"

namespace gonio::sim {

enum class NextEventMode : std::uint8_t { Off, On, Auto };
const char* to_string(NextEventMode m);                                // "off", "on", "auto"
std::optional<NextEventMode> parse_next_event_mode(std::string_view text);

inline constexpr int kDefaultConnections = 16;              // M per vertex
inline constexpr std::uint64_t kNextEventPilotPhotons = 1024;
inline constexpr double kMinConnectionEscape = 0.05;        // a slot's connections that must escape
// The rule auto used before issue 43 (NextEventChoice::worthwhile; auto now
// follows choose_connections): on when at least this share of the pilot's escaped power left
// after a non-delta event at a kept slot, i.e. when nearly all the far
// field would come from connections. Measured on the four samples
// (docs/luminance-and-glare.md): the LED array (1.00) wins, the bell (0.74:
// a quarter of its light leaves straight from the lamp or by the shade's
// mirror lobe, Sobol'-stratified and paid for by connections that do not
// improve it) loses, the spotlight (0) and downlight (0.26) gain nothing.
inline constexpr double kAutoCoveredShare = 0.9;

// Slots: per mesh, the side the photon arrives on (0 front, 1 back) and
// the lobe (sim::Lobe's value; the non-delta ones are used).
inline constexpr std::size_t kSlotsPerMesh = 2 * static_cast<std::size_t>(kLobeCount);
inline std::size_t next_event_slot(std::uint32_t mesh, bool back, Lobe lobe) {
  return (static_cast<std::size_t>(mesh) * 2 + (back ? 1 : 0)) * static_cast<std::size_t>(kLobeCount) +
         static_cast<std::size_t>(lobe);
}

// What the tracer does (TracerSettings::next_event).
struct NextEventSettings {
  bool enabled = false;
  int connections = kDefaultConnections;  // M ≥ 1
  // Per mesh and side (mesh · 2 + back): the lobes to connect
  // (sim/bsdfs/bsdf_eval.h's bits, 1 << Lobe); empty: every lobe everywhere.
  std::vector<std::uint16_t> lobes;
  unsigned lobes_at(std::uint32_t mesh, bool back) const {
    const std::size_t side = static_cast<std::size_t>(mesh) * 2 + (back ? 1 : 0);
    if (!counts.empty() && counts[side] == 0) return 0u;
    return lobes.empty() ? kNonDeltaLobes : lobes[side];
  }
  // Per mesh and side: M there (auto's choice, choose_connections); empty:
  // `connections` everywhere. 0 leaves the side unconnected.
  std::vector<std::uint16_t> counts;
  int connections_at(std::uint32_t mesh, bool back) const {
    return counts.empty() ? connections : counts[static_cast<std::size_t>(mesh) * 2 + (back ? 1 : 0)];
  }
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
  std::uint64_t direct_units = 0;              // escapes without a surface event (straight from an emitter)
  // Per slot (the pilot's choice): connections, those escaped, the power of
  // escapes whose last event was there, and of those after ≥ 2 events.
  std::vector<std::uint64_t> slot_connections, slot_escaped, slot_covered_units, slot_multi_units;

  void reset(std::size_t texels, int replicates, std::size_t meshes);
  void clear();
  void add(const NextEventTally& other);
};

// The pilot's verdict: which slots keep connections, and whether `auto`
// turns them on (covered_share ≥ kAutoCoveredShare).
struct NextEventChoice {
  std::vector<std::uint16_t> lobes;  // NextEventSettings::lobes
  double covered_share = 0.0;  // of the escaped power, leaving after a kept slot [0, 1]
  double multi_share = 0.0;    // of it, after ≥ 2 events [0, 1]
  bool worthwhile = false;
};
NextEventChoice choose_next_event(const NextEventTally& pilot, std::uint64_t escaped_units);

// Connections that pay (issue 43): M per mesh and side chosen by what they
// buy, from the pilot. The photon's own escape is one more sample of the
// same direct escape, weighted against the connections by the balance
// heuristic (sim/tracer/tracer.cpp: each books power · f / (M·p + f)), so a
// side with M connections estimates its direct escape from M + 1 samples
// for the price of M rays. The model, per side s (its kept slots):
//   a_s  its share of the far field's variance: the power escaping after a
//        connected event there, over the escaped power, in which what leaves
//        straight from the emitters counts kDirectVarianceWeight times.
//        Measured (docs/validation.md, "Next-event estimation that pays"):
//        the bell's time to 1 % at M = 16 says a = 0.76 with a covered power
//        share of 0.74 and a fifth of its light straight from the lamp (the
//        emitter's light as noisy as the rest: weight ≈ 0.9); the
//        downlight's says a = 0.45 with 0.26 covered and 0.74 straight from
//        its profile emitter (weight ≈ 0.4). The weight is 1: the power
//        share, which never overrates what connections buy;
//   n_s  its vertices per photon; c the cost of a connection over a
//        photon's (kConnectionRayCost over the pilot's rays per photon);
//   relative time to a given error  T(M) = (1 − Σ a_s + Σ a_s/(M_s + 1)) ·
//        (1 + c · Σ n_s M_s)   (T = 1: no connections),
// minimised over M_s ∈ {0, 1, 2, 3, 4, 6, 8, 12, 16, …} ≤ max_connections,
// one side at a time until nothing changes. Auto turns connections on where
// the predicted T ≤ kAutoPredictedTime.
inline constexpr double kConnectionRayCost = 1.0;  // a connection in photon rays' cost
inline constexpr double kDirectVarianceWeight = 1.0;
inline constexpr double kAutoPredictedTime = 0.85;
struct ConnectionChoice {
  NextEventChoice base;               // the kept slots (choose_next_event)
  std::vector<std::uint16_t> counts;   // NextEventSettings::counts
  double predicted_time = 1.0;        // T at the counts chosen
  double variance_share = 0.0;        // Σ a_s over the kept sides
  bool worthwhile = false;            // predicted_time ≤ kAutoPredictedTime
};
ConnectionChoice choose_connections(const NextEventTally& pilot, std::uint64_t escaped_units,
                                    std::uint64_t pilot_photons, int pilot_connections, double rays_per_photon,
                                    int max_connections);

}  // namespace gonio::sim
