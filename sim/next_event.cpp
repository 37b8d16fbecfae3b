#include "sim/next_event.h"

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
  mesh_connections.assign(meshes, 0);
  mesh_escaped.assign(meshes, 0);
  mesh_covered_units.assign(meshes, 0);
  vertices = connections = escaped = booked_units = covered_units = 0;
}

void NextEventTally::clear() {
  for (auto* v : {&texel_units, &replicate_units, &mesh_connections, &mesh_escaped, &mesh_covered_units})
    std::fill(v->begin(), v->end(), std::uint64_t{0});
  vertices = connections = escaped = booked_units = covered_units = 0;
}

void NextEventTally::add(const NextEventTally& o) {
  const std::vector<std::uint64_t>* from[] = {&o.texel_units, &o.replicate_units, &o.mesh_connections,
                                              &o.mesh_escaped, &o.mesh_covered_units};
  std::vector<std::uint64_t>* to[] = {&texel_units, &replicate_units, &mesh_connections, &mesh_escaped,
                                      &mesh_covered_units};
  for (int k = 0; k < 5; ++k)
    for (std::size_t i = 0; i < to[k]->size(); ++i) (*to[k])[i] += (*from[k])[i];
  vertices += o.vertices;
  connections += o.connections;
  escaped += o.escaped;
  booked_units += o.booked_units;
  covered_units += o.covered_units;
}

NextEventChoice choose_next_event(const NextEventTally& pilot, std::uint64_t escaped_units) {
  NextEventChoice c;
  c.meshes.assign(pilot.mesh_connections.size(), 0);
  double covered = 0.0;
  for (std::size_t m = 0; m < c.meshes.size(); ++m) {
    const double tried = static_cast<double>(pilot.mesh_connections[m]);
    if (tried > 0.0 && static_cast<double>(pilot.mesh_escaped[m]) >= kMinConnectionEscape * tried) {
      c.meshes[m] = 1;
      covered += static_cast<double>(pilot.mesh_covered_units[m]);
    }
  }
  c.covered_share = escaped_units > 0 ? covered / static_cast<double>(escaped_units) : 0.0;
  c.worthwhile = c.covered_share >= kAutoCoveredShare;
  return c;
}

}  // namespace gonio::sim
