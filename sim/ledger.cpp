#include "sim/ledger.h"

#include "photometry/diagnostics.h"

namespace gonio::sim {

void LedgerTally::add(const LedgerTally& o) {
  GONIO_CHECK(o.emitters.size() == emitters.size() && o.meshes.size() == meshes.size());
  for (std::size_t i = 0; i < emitters.size(); ++i) {
    emitters[i].emitted += o.emitters[i].emitted;
    emitters[i].escaped += o.emitters[i].escaped;
    emitters[i].absorbed += o.emitters[i].absorbed;
    emitters[i].cutoff += o.emitters[i].cutoff;
  }
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    meshes[i].hits += o.meshes[i].hits;
    meshes[i].absorbed += o.meshes[i].absorbed;
    meshes[i].cutoff += o.meshes[i].cutoff;
  }
  rays += o.rays;
}

void LedgerTally::clear() {
  for (auto& e : emitters) e = {};
  for (auto& m : meshes) m = {};
  rays = 0;
}

Ledger make_ledger(const LedgerTally& t, const SceneDesc& scene, double total_flux_lm) {
  GONIO_CHECK(t.emitters.size() == scene.emitters.size() && t.meshes.size() == scene.meshes.size());
  Ledger l;
  // Power units, not photons: under guided emission photons start with
  // unequal power. For plain emission (kPowerUnits each, a power of two) this
  // is bit for bit total / photons.
  std::uint64_t emitted_units = 0;
  for (const auto& e : t.emitters) emitted_units += e.emitted.power_units;
  l.photon_power_lm = emitted_units > 0 ? total_flux_lm * static_cast<double>(kPowerUnits) /
                                              static_cast<double>(emitted_units)
                                        : 0.0;
  const double per_unit = l.photon_power_lm / static_cast<double>(kPowerUnits);
  auto line = [&](const TallyLine& x) {
    return LedgerLine{x.photons, static_cast<double>(x.power_units) * per_unit};
  };
  auto accumulate = [](LedgerLine& into, const LedgerLine& x) {
    into.photons += x.photons;
    into.flux_lm += x.flux_lm;
  };

  // Totals from integer sums, so that they close exactly before conversion.
  TallyLine em, es, ab, co;
  for (std::size_t i = 0; i < t.emitters.size(); ++i) {
    const auto& e = t.emitters[i];
    l.emitters.push_back({scene.emitters[i].name, line(e.emitted), line(e.escaped),
                          line(e.absorbed), line(e.cutoff)});
    em += e.emitted;
    es += e.escaped;
    ab += e.absorbed;
    co += e.cutoff;
  }
  l.emitted = line(em);
  l.escaped = line(es);
  l.absorbed = line(ab);
  l.cutoff = line(co);

  for (const Material& m : scene.materials) l.materials.push_back({m.name, 0, {}, {}});
  std::vector<std::uint64_t> placements(scene.meshes.size(), 0);
  for (const Instance& i : scene.instances)
    if (i.mesh < placements.size()) ++placements[i.mesh];
  for (std::size_t i = 0; i < t.meshes.size(); ++i) {
    const Mesh& mesh = scene.meshes[i];
    const auto& m = t.meshes[i];
    const std::string material =
        mesh.material < scene.materials.size() ? scene.materials[mesh.material].name : "";
    l.meshes.push_back({mesh.name, material, mesh.instanced ? placements[i] : 1, m.hits,
                        line(m.absorbed), line(m.cutoff)});
    if (mesh.material < l.materials.size()) {
      MaterialLedger& ml = l.materials[mesh.material];
      ml.hits += m.hits;
      accumulate(ml.absorbed, line(m.absorbed));
      accumulate(ml.cutoff, line(m.cutoff));
    }
  }
  return l;
}

}  // namespace gonio::sim
