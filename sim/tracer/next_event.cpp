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
  vertices = connections = escaped = booked_units = covered_units = 0;
}

void NextEventTally::clear() {
  for (auto* v : {&texel_units, &replicate_units, &slot_connections, &slot_escaped, &slot_covered_units,
                  &slot_multi_units})
    std::fill(v->begin(), v->end(), std::uint64_t{0});
  vertices = connections = escaped = booked_units = covered_units = 0;
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

}  // namespace gonio::sim
