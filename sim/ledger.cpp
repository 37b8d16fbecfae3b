#include "sim/ledger.h"

#include <algorithm>

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
  volume_events += o.volume_events;
  GONIO_CHECK(o.bins.emitted.size() == bins.emitted.size());
  for (std::size_t b = 0; b < bins.emitted.size(); ++b) {
    bins.emitted[b] += o.bins.emitted[b];
    bins.escaped[b] += o.bins.escaped[b];
    bins.absorbed[b] += o.bins.absorbed[b];
    bins.cutoff[b] += o.bins.cutoff[b];
  }
}

void LedgerTally::clear() {
  for (auto& e : emitters) e = {};
  for (auto& m : meshes) m = {};
  rays = volume_events = 0;
  for (auto* v : {&bins.emitted, &bins.escaped, &bins.absorbed, &bins.cutoff})
    std::fill(v->begin(), v->end(), std::uint64_t{0});
}

Ledger make_ledger(const LedgerTally& t, const SceneDesc& scene, double total_flux_lm,
                   const std::vector<RadiantPerLm>* radiant_bins) {
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
  if (radiant_bins && t.bins.emitted.size() == radiant_bins->size()) {
    // Watts from the bins (sim/tracer/spectral.h), summed in a fixed order.
    l.spectral = true;
    RadiantLedger& r = l.radiant;
    const std::size_t bands = photometry::kCmfCount;
    r.escaped_band_w.assign(bands, 0.0);
    std::vector<double> drawn_band_w(bands, 0.0);  // emitted by photons drawn later, per band
    const LedgerTally::Bins& b = t.bins;
    for (std::size_t j = bands; j < b.emitted.size(); ++j) {
      const RadiantPerLm& per_lm = (*radiant_bins)[j];
      const std::uint64_t drawn = b.emitted[j] - b.escaped[j] - b.absorbed[j] - b.cutoff[j];
      for (std::size_t k = 0; k < bands; ++k) {
        const double w_per_unit = per_unit * per_lm[k];
        r.emitted_w += static_cast<double>(b.emitted[j]) * w_per_unit;
        r.escaped_band_w[k] += static_cast<double>(b.escaped[j]) * w_per_unit;
        r.absorbed_w += static_cast<double>(b.absorbed[j]) * w_per_unit;
        r.cutoff_w += static_cast<double>(b.cutoff[j]) * w_per_unit;
        drawn_band_w[k] += static_cast<double>(drawn) * w_per_unit;
      }
    }
    // Drawn photons: band k's watts end as band k's drawn photons did,
    // pooled with the bands around it until they hold 256 photons of
    // nominal power (bands seldom drawn, such as the far red, would
    // otherwise hang on a handful of photons).
    constexpr double kPoolUnits = 256.0 * static_cast<double>(kPowerUnits);
    for (std::size_t k = 0; k < bands; ++k) {
      if (drawn_band_w[k] == 0.0) continue;
      double all = 0.0, escaped = 0.0, absorbed = 0.0, cutoff = 0.0;
      const auto pool = [&](std::size_t m) {
        all += static_cast<double>(b.emitted[m]);
        escaped += static_cast<double>(b.escaped[m]);
        absorbed += static_cast<double>(b.absorbed[m]);
        cutoff += static_cast<double>(b.cutoff[m]);
      };
      pool(k);
      for (std::size_t d = 1; d < bands && all < kPoolUnits; ++d) {
        if (k >= d) pool(k - d);
        if (k + d < bands) pool(k + d);
      }
      if (all == 0.0) continue;
      r.escaped_band_w[k] += drawn_band_w[k] * (escaped / all);
      r.absorbed_w += drawn_band_w[k] * (absorbed / all);
      r.cutoff_w += drawn_band_w[k] * (cutoff / all);
    }
    for (double w : r.escaped_band_w) r.escaped_w += w;
  }
  return l;
}

}  // namespace gonio::sim
