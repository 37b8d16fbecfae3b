#include "tools/run/simulation_outputs.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <filesystem>
#include <limits>

#include "gonio/version.h"
#include "io/outputs/datasheet.h"
#include "io/outputs/exr.h"
#include "io/outputs/report.h"
#include "io/support/file_io.h"
#include "io/photometric/gldf.h"
#include "io/outputs/intensity_diagram.h"
#include "io/photometric/ldt.h"
#include "io/photometric/tm33.h"
#include "io/photometric/photometric_file.h"
#include "io/outputs/plot.h"
#include "photometry/direct_ratios.h"
#include "photometry/flux.h"
#include "photometry/colour.h"
#include "photometry/format.h"
#include "photometry/validation.h"
#include "sim/distributed.h"
#include "tools/run/console.h"
#include "tools/run/json_figures.h"
#include "tools/run/resampler_cache.h"

namespace gonio::app {
namespace {

using photometry::Distribution;
using photometry::Symmetry;

constexpr OutputFormat kAllFormats[] = {OutputFormat::Ies, OutputFormat::Ldt, OutputFormat::Exr,
                                        OutputFormat::LatLong, OutputFormat::Plot};
// Every name parse_formats() knows: "all" and those written only when named
// (the datasheet, GLDF, TM-33).
constexpr OutputFormat kKnownFormats[] = {OutputFormat::Ies,     OutputFormat::Ldt,  OutputFormat::Exr,
                                          OutputFormat::LatLong, OutputFormat::Plot, OutputFormat::Report,
                                          OutputFormat::Gldf,    OutputFormat::Tm33};

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t");
  return s.substr(b, e - b + 1);
}

Finding finding(Severity severity, std::string code, std::string message, const std::string& file) {
  Finding f;
  f.severity = severity;
  f.code = std::move(code);
  f.message = std::move(message);
  f.where.file = file;
  return f;
}

// The luminaire's outer dimensions: the bounding box of every placed mesh in the
// photometric frame (length along C0, width along C90, height along the
// zenith). NaN without meshes.
photometry::LuminaireDimensions bounding_box(const sim::SceneDesc& scene) {
  const photometry::PhotometricFrame& f = scene.frame;
  double lo[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                  std::numeric_limits<double>::infinity()};
  double hi[3] = {-lo[0], -lo[1], -lo[2]};
  bool any = false;
  sim::for_each_placed_vertex(scene, [&](const Vec3& p) {
    const Vec3 local = f.to_local(p);
    for (int i = 0; i < 3; ++i) {
      lo[i] = std::min(lo[i], local[i]);
      hi[i] = std::max(hi[i], local[i]);
    }
    any = true;
  });
  photometry::LuminaireDimensions d;
  if (!any) return d;
  // To 0.1 mm: the mesh positions are floats, whose rounding is no dimension.
  const auto mm10 = [](double m) { return std::round(m * 1e4) / 1e4; };
  d.length_m = mm10(hi[0] - lo[0]);
  d.width_m = mm10(hi[1] - lo[1]);
  d.height_m = mm10(hi[2] - lo[2]);
  return d;
}

std::string grid_text(const sim::CGammaGrid& g) { return g.describe(); }

std::string file_stem_name(const std::string& model) {
  return std::filesystem::path(model).filename().string();
}

void add_checks(const Distribution& d, const std::string& path, std::vector<Finding>* out) {
  for (Finding f : photometry::check(d)) {
    if (f.where.file.empty()) f.where.file = path;
    out->push_back(std::move(f));
  }
}

// Findings of an EXR channel: every value finite and ≥ 0.
void check_values(const io::ExrImage::FloatChannel& c, const std::string& path, std::vector<Finding>* out) {
  for (std::size_t i = 0; i < c.values.size(); ++i) {
    if (!std::isfinite(c.values[i]) || c.values[i] < 0.0f) {
      out->push_back(finding(Severity::Error, "exr-value",
                             "channel '" + c.name + "' holds " + format_number(c.values[i]) +
                                 " at pixel " + std::to_string(i) +
                                 "; expected a finite value >= 0",
                             path));
      return;
    }
  }
}

double relative_difference(double flux, double escaped) {
  return escaped > 0.0 && std::isfinite(flux) ? (flux - escaped) / escaped : photometry::kNaN;
}

// A written photometric file as its reader sees it: the reader's findings,
// the model checks, and the flux integrated from what was read.
template <class File>
void take_read_back(const Result<File>& back, WrittenFile* file) {
  if (!back.ok()) {
    file->findings.push_back(finding(Severity::Error, "unreadable", back.error().message, file->path));
    return;
  }
  file->findings = back->findings;
  add_checks(back->distribution, file->path, &file->findings);
  if (photometry::validate(back->distribution).ok()) file->flux_lm = photometry::total_flux_lm(back->distribution);
}

std::string ies_text(const Distribution& d, const OutputRequest& request, std::vector<Finding>* notes) {
  io::IesWriteOptions options;
  options.version = request.ies_version;
  // LM-63 has no fields for EULUMDAT's derived values: leave them to the LDT.
  Distribution ies = d;
  ies.declared_lor_percent = ies.declared_dff_percent = photometry::kNaN;
  ies.direct_ratios.clear();
  ies.luminaire = {};
  return io::write_ies(ies, options, notes);
}

Status write_ies_file(const Distribution& d, const OutputRequest& request, WrittenFile* file) {
  const std::string text = ies_text(d, request, &file->writer_notes);
  if (Status s = io::write_file_atomic(file->path, text); !s.ok()) return s;
  take_read_back(io::read_ies(file->path), file);
  return Ok{};
}

Result<std::string> ldt_text(const Distribution& d, const std::string& path, std::vector<Finding>* notes) {
  // EULUMDAT has fields for a few keywords only: give it those.
  Distribution ldt = d;
  ldt.keywords.clear();
  for (const char* key : {"MANUFAC", "LUMINAIRE", "ISSUEDATE"})
    if (const photometry::Keyword* k = d.find_keyword(key)) ldt.keywords.push_back(*k);
  if (const photometry::Keyword* k = d.find_keyword("_GONIO_RUN")) ldt.set_keyword("TEST", k->value);
  const std::string name = std::filesystem::path(path).filename().string();
  if (name.size() <= 12) ldt.set_keyword(io::kLdtFileNameKeyword, name);
  return io::write_ldt(ldt, {}, notes);
}

Status write_ldt_file(const Distribution& d, WrittenFile* file) {
  Result<std::string> text = ldt_text(d, file->path, &file->writer_notes);
  if (!text.ok()) return make_error(file->path, text.error().message);
  if (Status s = io::write_file_atomic(file->path, *text); !s.ok()) return s;
  take_read_back(io::read_ldt(file->path), file);
  return Ok{};
}

// STEM.xml: the TM-33-23 document; a spectral run's also carries the
// luminaire's total spectrum, the escaped light's (sim/ledger.h's
// RadiantLedger::escaped_band_w, 5 nm bands, normalised to peak 1), and its
// CCT as FixedCCT (the lamp set's colour). Read back with Gonio's reader.
Status write_tm33_file(const Distribution& d, const sim::Ledger& ledger, WrittenFile* file) {
  Distribution tm33 = d;
  if (ledger.spectral && ledger.radiant.escaped_w > 0.0) {
    photometry::Spectrum s;
    s.emitter = "luminaire: the escaped light (Gonio simulation)";
    s.normalized = true;
    double peak = 0.0;
    for (double w : ledger.radiant.escaped_band_w) peak = std::max(peak, w);
    for (std::size_t k = 0; k < ledger.radiant.escaped_band_w.size(); ++k) {
      s.wavelength_nm.push_back(photometry::kCmfFirstNm + photometry::kCmfStepNm * static_cast<double>(k));
      s.values.push_back(ledger.radiant.escaped_band_w[k] / peak);
    }
    tm33.spectra = {std::move(s)};
  }
  const std::string text = io::write_tm33(tm33, &file->writer_notes);
  if (Status s = io::write_file_atomic(file->path, text); !s.ok()) return s;
  Result<std::string> bytes = io::read_file(file->path, std::size_t{256} << 20);
  if (!bytes.ok()) {
    file->findings.push_back(finding(Severity::Error, "unreadable", bytes.error().message, file->path));
    return Ok{};
  }
  take_read_back(io::parse_tm33(*bytes, file->path), file);
  return Ok{};
}

// STEM.gldf: product.xml, the LDT and IES as STEM.ldt and STEM.ies hold
// them, the model as L3D; read back as `gonio check` reads a GLDF.
Status write_gldf_file(const Distribution& d, const sim::SceneDesc& scene, const OutputRequest& request,
                       WrittenFile* file) {
  const std::filesystem::path dir(request.directory);
  Result<std::string> ldt = ldt_text(d, (dir / (request.stem + ".ldt")).string(), &file->writer_notes);
  if (!ldt.ok()) return make_error(file->path, ldt.error().message);
  io::GldfProduct product;
  product.name = request.stem;
  product.description = "Gonio simulation of " + request.run.model + ", " + std::to_string(request.run.photons) +
                        " photons, seed " + std::to_string(request.run.seed);
  product.photometries.push_back({request.stem + ".ldt", "ldc/eulumdat", std::move(ldt).value(), d});
  product.photometries.push_back(
      {request.stem + ".ies", "ldc/ies", ies_text(d, request, &file->writer_notes), d});
  product.geometry = io::l3d_from_scene(scene);
  if (request.opening && request.opening->opening.shape != photometry::OpeningShape::Point) {
    // The light-emitting object is the luminous opening the files carry.
    const SimulatedOpening& o = *request.opening;
    io::L3dEmitter leo;
    leo.name = "lightEmittingObject";
    leo.position_m = o.centre_m;
    leo.size_x_m = o.opening.length_m;
    leo.size_y_m = o.opening.width_m;
    product.geometry->emitters = {leo};
  }
  product.created_unix = now_unix();
  Result<std::string> bytes = io::write_gldf(product);
  if (!bytes.ok()) return make_error(file->path, bytes.error().message);
  if (Status s = io::write_file_atomic(file->path, *bytes); !s.ok()) return s;
  auto back = io::read_photometric_files(file->path);
  if (!back.ok()) {
    file->findings.push_back(finding(Severity::Error, "unreadable", back.error().message, file->path));
    return Ok{};
  }
  for (const io::PhotometricFile& p : *back) {
    for (const Finding& f : p.findings) file->findings.push_back(f);
    add_checks(p.distribution, file->path + ":" + p.container_entry, &file->findings);
  }
  // The LDT inside: the flux a planning program reads.
  file->flux_lm = photometry::total_flux_lm(back->front().distribution);
  return Ok{};
}

std::vector<std::pair<std::string, std::string>> exr_attributes(const OutputRequest& r) {
  return {{"gonio:software", "Gonio " + r.run.program_version},
          {"gonio:model", r.run.model},
          {"gonio:photons", std::to_string(r.run.photons)},
          {"gonio:seed", std::to_string(r.run.seed)}};
}

Status write_cube_file(const sim::FarField& far_field, const OutputRequest& request, WrittenFile* file) {
  Result<io::ExrImage> image = io::far_field_image(far_field, request.colour);
  if (!image.ok()) return make_error(file->path, image.error().message);
  for (auto& a : exr_attributes(request)) image->attributes.push_back(std::move(a));
  if (Status s = io::write_exr(file->path, *image); !s.ok()) return s;
  Result<io::ExrImage> back = io::read_exr(file->path);
  if (!back.ok()) {
    file->findings.push_back(finding(Severity::Error, "unreadable", back.error().message, file->path));
    return Ok{};
  }
  if (const auto* y = back->find_float("Y")) check_values(*y, file->path, &file->findings);
  if (const auto* f = back->find_float("flux")) check_values(*f, file->path, &file->findings);
  Result<sim::FarField> field = io::far_field_from_image(*back, file->path);
  if (!field.ok()) {
    file->findings.push_back(finding(Severity::Error, "not-a-far-field", field.error().message, file->path));
    return Ok{};
  }
  file->flux_lm = field->total_flux_lm();
  return Ok{};
}

// The latitude-longitude map: the cube resampled (exactly, by overlaps) onto
// the bins of a C-γ grid whose frame has its zenith at world +Y, C0 at +Z
// and C90 at +X. Then γ = 90° + latitude and C = longitude, so pixel (x, y)
// is the grid point C = 180° − x·Δ, γ = 180° − y·Δ, and each pixel's value is
// the mean intensity over the region io::latlong_pixel_solid_angle() gives it.
Status write_latlong_file(const sim::FarField& far_field, const OutputRequest& request, WrittenFile* file) {
  // Four pixels per 90° per texel of the face, at most 0.7° (the resampler's
  // finest grids cost seconds to build).
  const int m = std::clamp(far_field.face_size() / 2, 1, 64);
  sim::CGammaGrid grid;
  grid.c_step_deg = grid.gamma_step_deg = 90.0 / m;
  const photometry::PhotometricFrame frame = photometry::make_frame({0.0, 1.0, 0.0}, {0.0, 0.0, 1.0});
  const sim::Resampler resampler = cached_resampler(far_field.face_size(), frame, grid, request.cache_dir);
  const sim::BinnedField binned = resampler.bin(far_field);
  const int width = 4 * m + 1, height = 2 * m + 1;
  io::ExrImage image = io::latlong_image(width, height);
  io::ExrImage::FloatChannel y{"Y", std::vector<float>(static_cast<std::size_t>(width) * height)};
  const int c_count = grid.c_count();
  for (int row = 0; row < height; ++row) {
    const int j = 2 * m - row;
    for (int x = 0; x < width; ++x) {
      const int i = ((2 * m - x) % c_count + c_count) % c_count;
      // Over the exact region the reader integrates, so the flux reads back exactly.
      const std::size_t bin = grid.bin(i, j);
      y.values[static_cast<std::size_t>(row) * width + x] =
          static_cast<float>(binned.flux_lm[bin] / sim::exact_bin_solid_angle(grid, bin));
    }
  }
  image.float_channels.push_back(std::move(y));
  image.attributes = {{"gonio:quantity", "far-field luminous intensity, equirectangular (OpenEXR latlong)"},
                      {"gonio:units", "Y: cd (mean over each pixel's region)"}};
  for (auto& a : exr_attributes(request)) image.attributes.push_back(std::move(a));
  if (Status s = io::write_exr(file->path, image); !s.ok()) return s;
  Result<io::ExrImage> back = io::read_exr(file->path);
  if (!back.ok()) {
    file->findings.push_back(finding(Severity::Error, "unreadable", back.error().message, file->path));
    return Ok{};
  }
  Result<double> flux = io::latlong_flux_lm(*back, file->path);
  if (!flux.ok()) {
    file->findings.push_back(finding(Severity::Error, "not-a-latlong-map", flux.error().message, file->path));
    return Ok{};
  }
  file->flux_lm = *flux;
  return Ok{};
}

Status write_plot_file(const Distribution& d, const OutputRequest& request, WrittenFile* file) {
  io::DiagramOptions options;
  options.title = file_stem_name(request.run.model) + " (Gonio simulation, " +
                  std::to_string(request.run.photons) + " photons)";
  Result<io::Figure> figure = io::intensity_diagram(d, options);
  if (!figure.ok()) return make_error(file->path, figure.error().message);
  if (Status s = io::write_figure(file->path, *figure); !s.ok()) return s;
  Result<std::string> back = io::read_file(file->path, std::size_t{64} << 20);
  if (!back.ok()) {
    file->findings.push_back(finding(Severity::Error, "unreadable", back.error().message, file->path));
  } else if (back->find("<svg") == std::string::npos || back->find("</svg>") == std::string::npos) {
    file->findings.push_back(finding(Severity::Error, "not-svg", "not a complete SVG document", file->path));
  }
  return Ok{};
}

// The datasheet of the simulated table with the run's books; read back: a
// whole HTML document that loads nothing from elsewhere.
Status write_report_file(const Distribution& d, const sim::Ledger& ledger, const OutputRequest& request,
                         WrittenFile* file) {
  io::DatasheetEntry entry;
  entry.source = file_stem_name(request.run.model) + " (Gonio simulation)";
  entry.format = "Gonio simulation, " + std::to_string(request.run.photons) + " photons";
  entry.distribution = d;
  entry.simulation_report = nlohmann::json{{"model", request.run.model},
                                           {"seed", request.run.seed},
                                           {"photons_emitted", ledger.emitted.photons},
                                           {"emitted_lm", ledger.emitted.flux_lm},
                                           {"escaped_lm", ledger.escaped.flux_lm},
                                           {"absorbed_lm", ledger.absorbed.flux_lm},
                                           {"cutoff_lm", ledger.cutoff.flux_lm}};
  if (request.near_field.is_object())
    for (const auto& [key, value] : request.near_field.items()) (*entry.simulation_report)[key] = value;
  if (ledger.spectral) (*entry.simulation_report)["radiant"] = io::radiant_json(ledger.radiant);
  if (request.colour_report.is_object()) entry.simulation_report->update(request.colour_report);
  if (Status s = io::write_datasheet(file->path, {entry}); !s.ok()) return s;
  Result<std::string> back = io::read_file(file->path, std::size_t{64} << 20);
  if (!back.ok()) {
    file->findings.push_back(finding(Severity::Error, "unreadable", back.error().message, file->path));
  } else if (back->find("<html") == std::string::npos || back->find("</html>") == std::string::npos) {
    file->findings.push_back(finding(Severity::Error, "not-html", "not a complete HTML document", file->path));
  } else if (back->find("src=\"http") != std::string::npos || back->find("href=\"http") != std::string::npos ||
             back->find("url(http") != std::string::npos) {
    file->findings.push_back(
        finding(Severity::Error, "external-resource", "the datasheet loads something from elsewhere", file->path));
  }
  return Ok{};
}

}  // namespace

nlohmann::json colour_json(const sim::ColourOverAngle& c) {
  const auto num = [](double v) { return json_number(v); };
  const photometry::Chromaticity xy = photometry::chromaticity(c.total);
  nlohmann::json j;
  j["colour"] = {{"cie_x", num(xy.x)},          {"cie_y", num(xy.y)},
                 {"u_prime", num(c.uv.u_prime)}, {"v_prime", num(c.uv.v_prime)},
                 {"cct_k", num(c.cct.cct_k)},    {"duv", num(c.cct.duv)},
                 {"method", "CIE 1931 2 deg, 5 nm; CCT and Duv by Ohno 2014"}};
  nlohmann::json planes = nlohmann::json::array();
  for (const sim::ColourPlane& p : c.planes) {
    nlohmann::json g = nlohmann::json::array(), u = g, v = g, t = g, d = g;
    for (const sim::ColourAtGamma& a : p.points) {
      g.push_back(a.gamma_deg);
      u.push_back(num(a.uv.u_prime));
      v.push_back(num(a.uv.v_prime));
      t.push_back(num(a.cct.cct_k));
      d.push_back(num(a.cct.duv));
    }
    planes.push_back({{"c_deg", p.c_deg}, {"gamma_deg", g}, {"u_prime", u}, {"v_prime", v},
                      {"cct_k", t}, {"duv", d}});
  }
  j["colour_over_angle"] = {{"threshold_fraction", c.threshold_fraction},
                            {"mean_u_prime", num(c.mean_uv.u_prime)},
                            {"mean_v_prime", num(c.mean_uv.v_prime)},
                            {"delta_uv_max", num(c.delta_uv_max)},
                            {"bins_counted", c.bins_counted},
                            {"planes", planes}};
  return j;
}

nlohmann::json live_colour_json(const sim::ColourOverAngle& c) {
  nlohmann::json all = colour_json(c);
  nlohmann::json j = all["colour"];
  j.erase("method");
  j["delta_uv_max"] = all["colour_over_angle"]["delta_uv_max"];
  return j;
}

const char* to_string(OutputFormat format) {
  switch (format) {
    case OutputFormat::Ies: return "ies";
    case OutputFormat::Ldt: return "ldt";
    case OutputFormat::Exr: return "exr";
    case OutputFormat::LatLong: return "latlong";
    case OutputFormat::Plot: return "plot";
    case OutputFormat::Report: return "report";
    case OutputFormat::Gldf: return "gldf";
    case OutputFormat::Tm33: return "tm33";
  }
  return "?";
}

Result<std::vector<OutputFormat>> parse_formats(const std::string& list) {
  std::vector<OutputFormat> out;
  const std::string valid = "ies, ldt, exr, latlong, plot, report, gldf, tm33 or all";
  std::size_t start = 0;
  while (start <= list.size()) {
    const std::size_t comma = std::min(list.find(',', start), list.size());
    const std::string name = trim(list.substr(start, comma - start));
    start = comma + 1;
    if (name.empty()) {
      if (comma == list.size() && !out.empty()) break;
      return make_error("", "--format: empty format name in '" + list +
                                "'; expected a comma-separated list of " + valid);
    }
    if (name == "all") {
      for (OutputFormat f : kAllFormats)
        if (std::find(out.begin(), out.end(), f) == out.end()) out.push_back(f);
      continue;
    }
    bool known = false;
    for (OutputFormat f : kKnownFormats) {
      if (name != to_string(f)) continue;
      known = true;
      if (std::find(out.begin(), out.end(), f) == out.end()) out.push_back(f);
    }
    if (!known) return make_error("", "--format: unknown format '" + name + "'; expected " + valid);
  }
  return out;
}

SimulatedOpening simulated_opening(const sim::Tracer& tracer, const sim::SceneDesc& scene, std::uint64_t seed,
                                   std::uint64_t photons) {
  std::vector<Vec3> points;
  // A chunk of photons at a time: their rays, then which of them escape.
  constexpr std::uint64_t kChunk = 4096;
  std::vector<sim::RayQuery> rays;
  for (std::uint64_t first = 0; first < photons; first += kChunk) {
    rays.clear();
    tracer.record_rays(seed, first, std::min(kChunk, photons - first), &rays);
    for (const sim::RayQuery& q : rays) {
      const Vec3 dir = scene.frame.to_local(Vec3{q.direction[0], q.direction[1], q.direction[2]});
      if (!(dir.z < 0.0)) continue;  // upward or horizontal: not seen from below
      sim::RayHit hit;
      if (tracer.embree().intersect(q, &hit)) continue;  // not an escape
      points.push_back(scene.frame.to_local(Vec3{q.origin[0], q.origin[1], q.origin[2]}));
    }
  }
  return opening_of_exits(points);
}

bool opening_from_trace(const sim::Simulation& simulation, std::uint64_t photons) {
  const sim::SimulationSettings& settings = simulation.settings();
  // The trace followed photons 0 … photons − 1 as record_rays does (no
  // connection drew from their random numbers, no guide chose them) and
  // kept their escapes here, in this process.
  return settings.capture_escaped_photons >= photons && simulation.stats().photons >= photons &&
         !simulation.next_event().enabled && !simulation.emission_guide() && settings.luminance.views.empty() &&
         !(settings.ranks && settings.ranks->distributed());
}

SimulatedOpening simulated_opening(const sim::Simulation& simulation, std::uint64_t photons) {
  if (!opening_from_trace(simulation, photons))
    return simulated_opening(simulation.tracer(), simulation.scene(), simulation.settings().seed, photons);
  // The escapes by photon index: the last ray of each, as record_rays
  // recorded it (a float RayQuery), in the order simulated_opening meets them.
  const photometry::PhotometricFrame& frame = simulation.scene().frame;
  std::vector<Vec3> points;
  for (const sim::EscapedRay& r : simulation.escaped_rays()) {
    if (r.photon >= photons) break;
    const sim::RayQuery q = sim::ray_query(r.origin, r.direction);
    const Vec3 dir = frame.to_local(Vec3{q.direction[0], q.direction[1], q.direction[2]});
    if (!(dir.z < 0.0)) continue;
    points.push_back(frame.to_local(Vec3{q.origin[0], q.origin[1], q.origin[2]}));
  }
  return opening_of_exits(points);
}

SimulatedOpening opening_of_exits(const std::vector<Vec3>& exits_local) {
  SimulatedOpening out;
  constexpr double inf = std::numeric_limits<double>::infinity();
  Vec3 lo{inf, inf, inf}, hi{-inf, -inf, -inf};
  double z_sum = 0.0;
  std::vector<std::array<double, 2>> exits;  // seen from above [m]
  for (const Vec3& p : exits_local) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    z_sum += p.z;
    exits.push_back({p.x, p.y});
    ++out.exits;
  }
  if (out.exits == 0) return out;
  // To 0.1 mm, as the outer dimensions: float positions carry no finer size.
  const auto mm10 = [](double m) { return std::round(m * 1e4) / 1e4; };
  out.opening.length_m = mm10(hi.x - lo.x);
  out.opening.width_m = mm10(hi.y - lo.y);
  out.opening.shape = out.opening.length_m > 0.0 && out.opening.width_m > 0.0 ? photometry::OpeningShape::Rectangular
                                                                              : photometry::OpeningShape::Point;
  if (out.opening.shape == photometry::OpeningShape::Point) out.opening.length_m = out.opening.width_m = 0.0;
  // Round: a square extent (sides within 2 %) whose corners hold no exit —
  // at most 1 in 1000 outside the inscribed circle (1 % larger, for the
  // offsets off the surfaces). A square opening's exits fill its corners
  // (a fifth of its area lies outside that circle).
  const double l = hi.x - lo.x, w = hi.y - lo.y;
  if (out.opening.shape == photometry::OpeningShape::Rectangular && std::abs(l - w) <= 0.02 * std::max(l, w)) {
    const double cx = 0.5 * (lo.x + hi.x), cy = 0.5 * (lo.y + hi.y), r = 0.505 * std::max(l, w);
    std::size_t outside = 0;
    for (const auto& q : exits)
      if (std::hypot(q[0] - cx, q[1] - cy) > r) ++outside;
    if (outside * 1000 <= exits.size()) {
      out.opening.shape = photometry::OpeningShape::Circular;
      out.opening.length_m = out.opening.width_m = mm10(std::max(l, w));
    }
  }
  out.centre_m = {0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), z_sum / static_cast<double>(out.exits)};
  return out;
}

Distribution simulated_distribution(const sim::BinnedField& binned, Symmetry symmetry, const sim::SceneDesc& scene,
                                    const sim::Ledger& ledger, const OutputRequest& request) {
  Distribution d = sim::to_distribution(binned, symmetry);
  d.file_generation = photometry::FileGenerationType::ComputerSimulation;
  d.absolute = false;
  const double emitted = ledger.emitted.flux_lm > 0.0 ? ledger.emitted.flux_lm : scene.total_flux_lm();
  photometry::LampSet lamp;
  const std::size_t n = scene.emitters.size();
  lamp.count = static_cast<int>(std::max<std::size_t>(n, 1));
  lamp.type = std::to_string(n) + (n == 1 ? " emitter" : " emitters");
  lamp.flux_lm = emitted;
  // A spectral run: the escaped light's CCT in the lamp set's colour field
  // (EULUMDAT's colour temperature) and, with Duv, in the IES user keyword
  // _CCT (LM-63 has no field of its own for it).
  std::string cct_text;
  if (request.colour && !request.colour->empty() && ledger.escaped.flux_lm > 0.0) {
    photometry::Tristimulus t;
    for (double v : request.colour->x_lm) t.X += v;
    for (double v : request.colour->z_lm) t.Z += v;
    t.Y = ledger.escaped.flux_lm;
    const photometry::CctDuv c = photometry::cct_duv(t);
    if (std::isfinite(c.cct_k)) {
      lamp.color = format_fixed(c.cct_k, 0) + " K";
      cct_text = lamp.color + ", Duv " + format_fixed(c.duv, 4) + " (Ohno 2014, CIE 1931 2 deg)";
    }
  }
  d.lamps = {lamp};
  d.luminaire = bounding_box(scene);
  if (request.opening) d.opening = request.opening->opening;

  const std::string model = file_stem_name(request.run.model);
  std::string emitters_text;
  for (std::size_t i = 0; i < n && i < 4; ++i) {
    const sim::Emitter& e = scene.emitters[i];
    emitters_text += (i ? ", " : "") +
                     (e.name.empty() ? "emitter " + std::to_string(i + 1) : e.name) + " (" +
                     (e.kind == sim::Emitter::Kind::Point
                          ? (e.profile ? "point, measured profile" : "point, isotropic")
                          : e.kind == sim::Emitter::Kind::RaySet ? "ray set"
                                                                 : "area, Lambertian") +
                     ", " + format_number(e.flux_lm) + " lm)";
  }
  if (n > 4) emitters_text += ", and " + std::to_string(n - 4) + " more";
  const std::string run = "Gonio simulation, " + std::to_string(request.run.photons) + " photons, seed " +
                          std::to_string(request.run.seed);
  d.keywords.clear();
  d.set_keyword("TEST", "none: computer simulation, no laboratory test");
  d.set_keyword("TESTLAB", "none: computer simulation with Gonio " + request.run.program_version);
  d.set_keyword("ISSUEDATE", request.run.issue_date);
  d.set_keyword("MANUFAC", "not stated in the model");
  d.set_keyword("LUMINAIRE", model);
  d.set_keyword("LAMP", emitters_text.empty() ? "no emitters" : emitters_text);
  if (!cct_text.empty()) d.set_keyword("_CCT", cct_text);
  d.set_keyword("FILEGENINFO",
                "Computer simulation by Gonio " + request.run.program_version +
                    " (photon tracing into a direction cube map, area-weighted resampling to " +
                    grid_text(binned.grid) + "). Model " + model + ", " +
                    std::to_string(request.run.photons) + " photons, seed " +
                    std::to_string(request.run.seed) + ", at most " +
                    std::to_string(request.run.max_bounces) + " bounces. Symmetry " +
                    photometry::to_string(symmetry) + ". Emitted " + format_number(emitted) +
                    " lm, escaped " + format_number(ledger.escaped.flux_lm) + " lm.");
  d.set_keyword("_GONIO_RUN", run);
  d.set_keyword("_GONIO_MODEL", model);
  d.set_keyword("_GONIO_PHOTONS", std::to_string(request.run.photons));
  d.set_keyword("_GONIO_SEED", std::to_string(request.run.seed));
  d.set_keyword("_GONIO_VERSION", request.run.program_version);

  // EULUMDAT's derived values, from this table and the books.
  const double total = photometry::total_flux_lm(d);
  d.declared_lor_percent = emitted > 0.0 ? 100.0 * ledger.escaped.flux_lm / emitted : 0.0;
  d.declared_dff_percent = total > 0.0 ? 100.0 * photometry::downward_flux_lm(d) / total : 0.0;
  const auto ratios = photometry::direct_ratios(d);
  d.direct_ratios.assign(ratios.begin(), ratios.end());
  return d;
}

OutputRequest table_request(const sim::Simulation& simulation, const std::string& model, const sim::CGammaGrid& grid,
                            const std::optional<photometry::Symmetry>& symmetry, const std::string& cache_dir) {
  const sim::SimulationSettings& settings = simulation.settings();
  OutputRequest request;
  request.grid = grid;
  request.symmetry = symmetry;
  request.cache_dir = cache_dir;
  request.opening = simulated_opening(simulation);
  request.run.program_version = kVersion;
  request.run.model = model;
  request.run.photons = simulation.stats().photons;
  request.run.seed = settings.seed;
  request.run.max_bounces = settings.max_bounces;
  request.run.issue_date = format_utc(now_unix(), "%Y-%m-%d");
  return request;
}

Result<SimulatedTable> simulated_table(const sim::FarField& far_field, const sim::SceneDesc& scene,
                                       const sim::Ledger& ledger, const OutputRequest& request) {
  if (request.symmetry) {
    if (Status s = sim::check_grid_supports(request.grid, *request.symmetry); !s.ok()) return s.error();
  }
  std::shared_ptr<const sim::Resampler> own;
  const sim::Resampler* resampler = request.resampler;
  if (!resampler || resampler->face_size() != far_field.face_size()) {
    own = shared_resampler(far_field.face_size(), scene.frame, request.grid, request.cache_dir);
    resampler = own.get();
  }
  const sim::BinnedField binned = resampler->bin(far_field);
  SimulatedTable table;
  if (request.symmetry) {
    table.symmetry = *request.symmetry;
    table.symmetry_reason =
        "symmetry " + std::string(photometry::to_string(table.symmetry)) + ", as requested (--symmetry)";
  } else {
    table.decision = sim::detect_symmetry(binned);
    table.symmetry = table.decision.symmetry;
    table.symmetry_reason = table.decision.explanation;
  }
  table.distribution = simulated_distribution(binned, table.symmetry, scene, ledger, request);
  return table;
}

Result<OutputResult> write_outputs(const sim::FarField& far_field, const sim::SceneDesc& scene,
                                   const sim::Ledger& ledger, const OutputRequest& request) {
  OutputResult result;
  const auto wants = [&](OutputFormat f) {
    return std::find(request.formats.begin(), request.formats.end(), f) != request.formats.end();
  };
  const bool needs_table = wants(OutputFormat::Ies) || wants(OutputFormat::Ldt) || wants(OutputFormat::Plot) ||
                           wants(OutputFormat::Report) || wants(OutputFormat::Gldf) || wants(OutputFormat::Tm33);
  if (needs_table) {
    Result<SimulatedTable> table = simulated_table(far_field, scene, ledger, request);
    if (!table.ok()) return table.error();
    result.distribution = std::move(table->distribution);
    result.symmetry = table->symmetry;
    result.symmetry_reason = std::move(table->symmetry_reason);
    result.decision = std::move(table->decision);
  }

  const std::filesystem::path dir(request.directory);
  for (OutputFormat f : request.formats) {
    WrittenFile file;
    file.format = f;
    Status s = Ok{};
    switch (f) {
      case OutputFormat::Ies:
        file.path = (dir / (request.stem + ".ies")).string();
        s = write_ies_file(result.distribution, request, &file);
        break;
      case OutputFormat::Ldt:
        file.path = (dir / (request.stem + ".ldt")).string();
        s = write_ldt_file(result.distribution, &file);
        break;
      case OutputFormat::Exr:
        file.path = (dir / "farfield.exr").string();
        s = write_cube_file(far_field, request, &file);
        break;
      case OutputFormat::LatLong:
        file.path = (dir / "farfield-latlong.exr").string();
        s = write_latlong_file(far_field, request, &file);
        break;
      case OutputFormat::Plot:
        file.path = (dir / (request.stem + ".svg")).string();
        s = write_plot_file(result.distribution, request, &file);
        break;
      case OutputFormat::Report:
        file.path = (dir / (request.stem + ".html")).string();
        s = write_report_file(result.distribution, ledger, request, &file);
        break;
      case OutputFormat::Gldf:
        file.path = (dir / (request.stem + ".gldf")).string();
        s = write_gldf_file(result.distribution, scene, request, &file);
        break;
      case OutputFormat::Tm33:
        file.path = (dir / (request.stem + ".xml")).string();
        s = write_tm33_file(result.distribution, ledger, &file);
        break;
    }
    if (!s.ok()) {
      result.failed.push_back({f, file.path, s.error()});
      continue;
    }
    // Against the far field the files were made from: the escaped flux
    // without next-event estimation, an unbiased estimate of it with
    // (sim/tracer/next_event.h: the two then differ by the estimator's noise).
    file.flux_difference = relative_difference(file.flux_lm, far_field.total_flux_lm());
    result.files.push_back(std::move(file));
  }
  return result;
}

namespace {

nlohmann::json findings_json(const std::vector<Finding>& findings) {
  nlohmann::json a = nlohmann::json::array();
  for (const Finding& f : findings)
    a.push_back({{"severity", to_string(f.severity)}, {"code", f.code}, {"message", f.message},
                 {"where", to_string(f.where)}});
  return a;
}


}  // namespace

nlohmann::json to_json(const OutputResult& r, const sim::CGammaGrid& grid, double escaped_lm) {
  using nlohmann::json;
  json j;
  j["grid"] = {{"c_step_deg", grid.c_step_deg}, {"gamma_step_deg", grid.gamma_step_deg}};
  // Non-uniform grids: the angles themselves (the steps above are then unused).
  if (!grid.c_angles_deg.empty()) j["grid"]["c_angles_deg"] = grid.c_angles_deg;
  if (!grid.gamma_angles_deg.empty()) j["grid"]["gamma_angles_deg"] = grid.gamma_angles_deg;
  json sym = {{"chosen", photometry::to_string(r.symmetry)}, {"reason", r.symmetry_reason}};
  json tests = json::array();
  for (const sim::SymmetryTest& t : r.decision.tests)
    tests.push_back({{"symmetry", photometry::to_string(t.symmetry)},
                     {"chi_square", t.chi_square},
                     {"degrees_of_freedom", t.degrees_of_freedom},
                     {"p_value", t.p_value},
                     {"groups", t.groups},
                     {"rejected", t.rejected},
                     {"detectable_deviation", json_number(t.detectable_deviation)}});
  sym["tests"] = std::move(tests);
  j["symmetry"] = std::move(sym);
  j["escaped_lm"] = escaped_lm;
  json files = json::array();
  for (const WrittenFile& f : r.files) {
    files.push_back({{"path", f.path},
                     {"format", to_string(f.format)},
                     {"flux_lm", json_number(f.flux_lm)},
                     {"flux_difference", json_number(f.flux_difference)},
                     {"clean", f.clean()},
                     {"findings", findings_json(f.findings)},
                     {"writer_notes", findings_json(f.writer_notes)}});
  }
  j["files"] = std::move(files);
  json failed = json::array();
  for (const FailedFile& f : r.failed)
    failed.push_back({{"path", f.path}, {"format", to_string(f.format)}, {"error", to_string(f.error)}});
  j["failed"] = std::move(failed);
  return j;
}

namespace {

std::string signed_percent(double fraction) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%+.3f %%", 100.0 * fraction);
  return buf;
}

std::string lumens(double flux_lm) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.9g lm", flux_lm);
  return buf;
}

}  // namespace

EnergyCheck check_energy(const sim::Ledger& l, const std::vector<WrittenFile>& files, double min_lor,
                         double flux_tolerance) {
  EnergyCheck check;
  const std::uint64_t accounted = l.escaped.photons + l.absorbed.photons + l.cutoff.photons;
  const double accounted_lm = l.escaped.flux_lm + l.absorbed.flux_lm + l.cutoff.flux_lm;
  const bool closes = l.photons_close() && std::abs(l.flux_imbalance_lm()) <= 1e-9 * l.emitted.flux_lm;
  if (!closes)
    check.failures.push_back("the books do not close: emitted " + std::to_string(l.emitted.photons) + " photons (" +
                             lumens(l.emitted.flux_lm) + "), escaped + absorbed + cut off " +
                             std::to_string(accounted) + " photons (" + lumens(accounted_lm) + ")");
  check.lor = l.emitted.flux_lm > 0.0 ? l.escaped.flux_lm / l.emitted.flux_lm : 0.0;
  if (check.lor < min_lor)
    check.failures.push_back("light output ratio " + std::to_string(check.lor) + " is under --min-lor " +
                             std::to_string(min_lor));
  nlohmann::json file_checks = nlohmann::json::array();
  for (const WrittenFile& f : files) {
    const bool has_flux = std::isfinite(f.flux_lm);
    const bool flux_ok = !has_flux || std::abs(f.flux_difference) <= flux_tolerance ||
                         (l.escaped.flux_lm == 0.0 && f.flux_lm == 0.0);
    if (!flux_ok && !(l.escaped.flux_lm > 0.0))
      check.failures.push_back(f.path + ": flux " + std::to_string(f.flux_lm) +
                               " lm read back, but no light left the model");
    else if (!flux_ok)
      check.failures.push_back(
          f.path + ": flux " + std::to_string(f.flux_lm) + " lm read back differs from the escaped " +
          std::to_string(l.escaped.flux_lm) + " lm by " + signed_percent(f.flux_difference) +
          ", more than --flux-tolerance " + std::to_string(100.0 * flux_tolerance) +
          " %: the grid cannot carry this distribution (a beam narrower than the steps?); a finer "
          "--gamma-step/--c-step may, or accept it with a larger --flux-tolerance");
    if (!f.clean()) {
      for (const Finding& x : f.findings)
        if (x.severity >= Severity::Warning)
          check.failures.push_back(to_string(x.where) + ": " + to_string(x.severity) + ": " + x.message + " [" +
                                   x.code + "]");
    }
    file_checks.push_back({{"path", f.path}, {"flux_ok", flux_ok}, {"clean", f.clean()}});
  }
  check.json = {{"photons_close", l.photons_close()},
                {"flux_imbalance_lm", l.flux_imbalance_lm()},
                {"lor", check.lor},
                {"min_lor", min_lor},
                {"flux_tolerance", flux_tolerance},
                {"files", std::move(file_checks)},
                {"passed", check.passed()},
                {"failures", check.failures}};
  return check;
}

int energy_exit_code(const std::string& model, const EnergyCheck& check) {
  for (const std::string& f : check.failures) print_error(model + ": energy check failed: " + f);
  return check.passed() ? kExitOk : kExitFailure;
}

}  // namespace gonio::app
