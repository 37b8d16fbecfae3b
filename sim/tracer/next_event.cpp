#include "sim/tracer/next_event.h"

#include <algorithm>

namespace gonio::sim {

const char* to_string(NextEventMode m) {
  switch (m) {
    case NextEventMode::Off: return "off";
    case NextEventMode::On: return "on";
    case NextEventMode::Auto: break;
  }
  return "auto";
}

std::optional<NextEventMode> parse_next_event_mode(std::string_view text) {
  if (text == "off") return NextEventMode::Off;
  if (text == "on") return NextEventMode::On;
  if (text == "auto") return NextEventMode::Auto;
  return std::nullopt;
}

void NextEventTally::reset(std::size_t texels, int replicates, std::size_t meshes) {
  texel_units.assign(texels, 0);
  replicate_units.assign(replicates > 1 ? texels * static_cast<std::size_t>(replicates) : 0, 0);
  for (auto* v : {&slot_connections, &slot_escaped, &slot_covered_units, &slot_multi_units}) v->assign(meshes * kSlotsPerMesh, 0);
  vertices = connections = escaped = booked_units = covered_units = direct_units = 0;
}

void NextEventTally::clear() {
  for (auto* v : {&texel_units, &replicate_units, &slot_connections, &slot_escaped, &slot_covered_units,
                  &slot_multi_units})
    std::fill(v->begin(), v->end(), std::uint64_t{0});
  vertices = connections = escaped = booked_units = covered_units = direct_units = 0;
}

void NextEventTally::add(const NextEventTally& o) {
  const std::vector<std::uint64_t>* from[] = {&o.texel_units,        &o.replicate_units,    &o.slot_connections,
                                              &o.slot_escaped,       &o.slot_covered_units, &o.slot_multi_units};
  std::vector<std::uint64_t>* to[] = {&texel_units,  &replicate_units,    &slot_connections,
                                      &slot_escaped, &slot_covered_units, &slot_multi_units};
  for (int k = 0; k < 6; ++k)
    for (std::size_t i = 0; i < to[k]->size(); ++i) (*to[k])[i] += (*from[k])[i];
  vertices += o.vertices;
  connections += o.connections;
  escaped += o.escaped;
  booked_units += o.booked_units;
  covered_units += o.covered_units;
  direct_units += o.direct_units;
}

NextEventChoice choose_next_event(const NextEventTally& pilot, std::uint64_t escaped_units) {
  NextEventChoice c;
  const std::size_t slots = pilot.slot_connections.size();
  constexpr auto kLobes = static_cast<std::size_t>(kLobeCount);
  c.lobes.assign(slots / kLobes, 0);
  double covered = 0.0, multi = 0.0;
  for (std::size_t k = 0; k < slots; ++k) {
    const double tried = static_cast<double>(pilot.slot_connections[k]);
    if (!(tried > 0.0 && static_cast<double>(pilot.slot_escaped[k]) >= kMinConnectionEscape * tried)) continue;
    c.lobes[k / kLobes] = static_cast<std::uint16_t>(c.lobes[k / kLobes] | (1u << (k % kLobes)));
    covered += static_cast<double>(pilot.slot_covered_units[k]);
    multi += static_cast<double>(pilot.slot_multi_units[k]);
  }
  const double escaped = static_cast<double>(escaped_units);
  c.covered_share = escaped > 0.0 ? covered / escaped : 0.0;
  c.multi_share = escaped > 0.0 ? multi / escaped : 0.0;
  c.worthwhile = c.covered_share >= kAutoCoveredShare;
  return c;
}

ConnectionChoice choose_connections(const NextEventTally& pilot, std::uint64_t escaped_units,
                                    std::uint64_t pilot_photons, int pilot_connections, double rays_per_photon,
                                    int max_connections) {
  ConnectionChoice out;
  out.base = choose_next_event(pilot, escaped_units);
  const std::size_t sides = out.base.lobes.size();
  out.counts.assign(sides, 0);
  constexpr auto kLobes = static_cast<std::size_t>(kLobeCount);
  // The escaped power, what left straight from an emitter weighted by
  // kDirectVarianceWeight.
  const double direct = static_cast<double>(std::min(pilot.direct_units, escaped_units));
  const double noisy = static_cast<double>(escaped_units) - (1.0 - kDirectVarianceWeight) * direct;
  if (!(noisy > 0.0) || pilot_photons == 0 || pilot_connections < 1 || max_connections < 1) return out;
  std::vector<double> a(sides, 0.0), n(sides, 0.0);
  for (std::size_t s = 0; s < sides; ++s) {
    if (out.base.lobes[s] == 0) continue;
    for (std::size_t l = 0; l < kLobes; ++l) {
      if ((out.base.lobes[s] & (1u << l)) == 0) continue;
      a[s] += static_cast<double>(pilot.slot_covered_units[s * kLobes + l]) / noisy;
      n[s] += static_cast<double>(pilot.slot_connections[s * kLobes + l]);
    }
    n[s] /= static_cast<double>(pilot_photons) * static_cast<double>(pilot_connections);
  }
  double share = 0.0;
  for (double v : a) share += v;
  out.variance_share = std::min(share, 1.0);
  const double c = kConnectionRayCost / std::max(rays_per_photon, 1.0);
  std::vector<int> m(sides, 0);
  const auto predicted = [&](const std::vector<int>& counts) {
    double variance = 1.0, cost = 1.0;
    for (std::size_t s = 0; s < sides; ++s) {
      variance -= a[s] * (1.0 - 1.0 / (counts[s] + 1.0));
      cost += c * n[s] * counts[s];
    }
    return std::max(variance, 0.0) * cost;
  };
  std::vector<int> candidates;
  for (int k : {1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64, 96, 128, 192, 255})
    if (k <= max_connections) candidates.push_back(k);
  if (max_connections < 255 && (candidates.empty() || candidates.back() != max_connections))
    candidates.push_back(max_connections);
  double best = predicted(m);
  for (int pass = 0; pass < 8; ++pass) {
    bool changed = false;
    for (std::size_t s = 0; s < sides; ++s) {
      if (!(a[s] > 0.0)) continue;
      const int was = m[s];
      int keep = was;
      for (int k : candidates) {
        m[s] = k;
        const double t = predicted(m);
        if (t < best - 1e-12) {
          best = t;
          keep = k;
        }
      }
      m[s] = 0;
      if (const double t = predicted(m); t < best - 1e-12) {
        best = t;
        keep = 0;
      }
      m[s] = keep;
      changed = changed || keep != was;
    }
    if (!changed) break;
  }
  for (std::size_t s = 0; s < sides; ++s) out.counts[s] = static_cast<std::uint16_t>(m[s]);
  out.predicted_time = best;
  out.worthwhile = best <= kAutoPredictedTime;
  return out;
}

}  // namespace gonio::sim
