#include "io/outputs/report.h"

#include "io/support/file_io.h"

#include <sys/resource.h>

namespace gonio::io {
namespace {

double per_second(double count, double seconds) { return seconds > 0.0 ? count / seconds : 0.0; }

void put_line(nlohmann::json& j, const char* what, const sim::LedgerLine& line) {
  j[std::string(what) + "_lm"] = line.flux_lm;
  j[std::string("photons_") + what] = line.photons;
}

}  // namespace

nlohmann::json radiant_json(const sim::RadiantLedger& r) {
  nlohmann::json bands = nlohmann::json::array(), nm = nlohmann::json::array();
  for (std::size_t k = 0; k < r.escaped_band_w.size(); ++k) {
    nm.push_back(photometry::kCmfFirstNm + photometry::kCmfStepNm * static_cast<double>(k));
    bands.push_back(r.escaped_band_w[k] / photometry::kCmfStepNm);
  }
  return {{"emitted_w", r.emitted_w},
          {"escaped_w", r.escaped_w},
          {"absorbed_w", r.absorbed_w},
          {"cutoff_w", r.cutoff_w},
          {"escaped_spectrum", {{"wavelengths_nm", nm}, {"w_per_nm", bands}}},
          {"method",
           "360-830 nm in 5 nm bands; each photon's luminous power in watts by its emitter's spectrum at its "
           "angle (S / (Km sum S ybar), exact), or, for photons whose wavelength a material drew, as the photons "
           "drawn in that band ended (sim/tracer/spectral.h)"}};
}

nlohmann::json to_json(const SimulationReport& r) {
  using nlohmann::json;
  const sim::Ledger& l = r.ledger;
  json j;
  j["program"] = {{"name", "gonio"}, {"version", r.program_version}};
  j["model"] = r.model;
  j["seed"] = r.seed;
  j["settings"] = {{"photons_per_iteration", r.photons_per_iteration},
                   {"iterations", r.iterations},
                   {"seed", r.seed},
                   {"threads", r.threads},
                   {"max_bounces", r.max_bounces},
                   {"face_size", r.face_size},
                   {"robust_embree", r.robust_embree},
                   {"bvh_quality", r.bvh_quality},
                   {"bvh_quality_auto", r.bvh_quality_auto}};
  put_line(j, "emitted", l.emitted);
  put_line(j, "escaped", l.escaped);
  put_line(j, "absorbed", l.absorbed);
  put_line(j, "cutoff", l.cutoff);
  j["photon_power_lm"] = l.photon_power_lm;
  j["ledger"] = {{"photons_close", l.photons_close()}, {"flux_imbalance_lm", l.flux_imbalance_lm()}};
  if (l.spectral) {
    j["radiant"] = radiant_json(l.radiant);
    j["ledger"]["radiant_imbalance_w"] = l.radiant.imbalance_w();
  }

  j["photons_per_s"] = per_second(static_cast<double>(r.photons), r.trace_s);
  j["rays_per_s"] = per_second(static_cast<double>(r.rays), r.trace_s);
  j["rays"] = r.rays;
  j["rays_per_photon"] = r.photons > 0 ? static_cast<double>(r.rays) / static_cast<double>(r.photons) : 0.0;
  j["wall_s"] = r.wall_s;
  j["trace_s"] = r.trace_s;
  j["setup_s"] = r.setup_s;
  j["setup"] = {{"load_s", r.setup.load_s},
                {"check_s", r.setup.check_s},
                {"validate_s", r.setup.validate_s},
                {"emission_tables_s", r.setup.emission_tables_s},
                {"bvh_s", r.setup.bvh_s},
                {"bvh_reused", r.setup.bvh_reused},
                {"shading_s", r.setup.shading_s},
                {"meshes", r.setup.meshes},
                {"meshes_from_cache", r.setup.meshes_from_cache},
                {"instances", r.setup.instances},
                {"triangles_unique", r.setup.triangles_unique},
                {"triangles_placed", r.setup.triangles_placed},
                {"max_rss_after_load_bytes", r.setup.max_rss_after_load_bytes},
                {"max_rss_after_checks_bytes", r.setup.max_rss_after_checks_bytes}};
  j["max_rss_bytes"] = r.max_rss_bytes;
  j["threads"] = r.threads;
  j["iterations_done"] = r.iterations_done;

  json emitters = json::array();
  for (const sim::EmitterLedger& e : l.emitters) {
    json x = {{"name", e.name}};
    put_line(x, "emitted", e.emitted);
    put_line(x, "escaped", e.escaped);
    put_line(x, "absorbed", e.absorbed);
    put_line(x, "cutoff", e.cutoff);
    emitters.push_back(std::move(x));
  }
  j["emitters"] = std::move(emitters);
  json meshes = json::array();
  for (const sim::MeshLedger& m : l.meshes) {
    json x = {{"name", m.name}, {"material", m.material}, {"placements", m.placements}, {"hits", m.hits}};
    put_line(x, "absorbed", m.absorbed);
    put_line(x, "cutoff", m.cutoff);
    meshes.push_back(std::move(x));
  }
  j["meshes"] = std::move(meshes);
  json materials = json::array();
  for (const sim::MaterialLedger& m : l.materials) {
    json x = {{"name", m.name}, {"hits", m.hits}};
    put_line(x, "absorbed", m.absorbed);
    put_line(x, "cutoff", m.cutoff);
    materials.push_back(std::move(x));
  }
  j["materials"] = std::move(materials);
  return j;
}

std::uint64_t peak_memory_bytes() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0;
  return static_cast<std::uint64_t>(usage.ru_maxrss) * 1024u;
}

Status write_json(const std::string& path, const nlohmann::json& json) {
  return write_file_atomic(path, json.dump(2) + "\n");
}

}  // namespace gonio::io
