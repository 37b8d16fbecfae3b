#include "sim/tracer/tracer.h"

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <new>
#include <optional>
#include <string>
#include <tuple>
#include <type_traits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "sim/bsdfs/bsdf_eval.h"
#include "sim/bsdfs/bsdf_eval_pair.h"
#include "sim/bsdfs/lobes.h"
#include "sim/bsdfs/volume.h"
#include "sim/bsdfs/material.h"

namespace gonio::sim {
namespace {

// Scattering events inside volumes a photon may have before it is cut off.
constexpr int kMaxVolumeEvents = 100000;

// The last vertex that made next-event connections, as the photon left it:
// its own escape from there is a sample of the same direct escape as the
// connections, weighted by the balance heuristic (Veach): with the
// connections' density p (M of them) and the photon's, which for the
// connected lobes is f·|cos| itself (its power does not change; lobe choice,
// absorption and survival make up its density), the photon's weight is
// f / (M·p + f) and each connection's M·p / (M·p + f) — they sum to one
// wherever either reaches — so both book power · f / (M·p + f).
// The vertex's bases and lobe weights are those its connections were drawn
// with (sim/bsdfs/bsdf_eval_pair.h's ConnectionVertex), built once.
struct CoveredVertex {
  const Material* material = nullptr;
  const ConnectionVertex* vertex = nullptr;  // Connections::vertex, built at a connected vertex
  int connections = 0;

  double book(const Vec3& wo, std::uint64_t power) const {
    if (!material) return 0.0;
    const FCosAndPdf at = non_delta_f_cos_and_pdf(*material, *vertex, wo);
    if (!(at.f_cos > 0.0)) return 0.0;
    return static_cast<double>(power) * at.f_cos / (static_cast<double>(connections) * at.pdf + at.f_cos);
  }
};

// The material's non-delta lobes as bits (has_connectable_lobes of each).
std::uint16_t connectable_lobe_bits(const Material& m) {
  unsigned bits = 0;
  for (unsigned k = 0; k < static_cast<unsigned>(kLobeCount); ++k)
    if ((kNonDeltaLobes & (1u << k)) && has_connectable_lobes(m, 1u << k)) bits |= 1u << k;
  return static_cast<std::uint16_t>(bits);
}

// std::llround of a booked share, bit for bit, without the library call:
// x = power · w with 0 ≤ w ≤ 1 and power < 2⁵³ units, so the truncation is
// exact, x − trunc(x) is exact, and halves round up as llround's do.
std::uint64_t round_units(double x) {
  const auto whole = static_cast<std::uint64_t>(x);
  return x - static_cast<double>(whole) >= 0.5 ? whole + 1 : whole;
}

bool finite(const Vec3f& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

double max_abs(const Vec3& p) { return std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}); }

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

std::string mesh_label(const Mesh& m, std::size_t i) {
  return "mesh " + std::to_string(i) + (m.name.empty() ? "" : " '" + m.name + "'");
}

Status validate_mesh(const Mesh& m, std::size_t i, std::size_t material_count) {
  const std::string what = mesh_label(m, i);
  if (m.indices.size() % 3 != 0) return make_error(what + ": index count is not a multiple of 3");
  if (m.positions.size() > (std::size_t{1} << 32) || m.triangle_count() > (std::size_t{1} << 32))
    return make_error(what + ": too many vertices or triangles");
  for (std::uint32_t idx : m.indices)
    if (idx >= m.positions.size())
      return make_error(what + ": vertex index " + std::to_string(idx) + " out of range");
  for (const Vec3f& p : m.positions)
    if (!finite(p)) return make_error(what + ": vertex position is not finite");
  if (!m.normals.empty() && m.normals.size() != m.positions.size())
    return make_error(what + ": normal count differs from vertex count");
  if (!m.tangents.empty() && m.tangents.size() != m.positions.size())
    return make_error(what + ": tangent count differs from vertex count");
  for (const Vec3f& n : m.normals)
    if (!finite(n)) return make_error(what + ": shading normal is not finite");
  for (const Vec3f& t : m.tangents)
    if (!finite(t)) return make_error(what + ": tangent is not finite");
  if (m.material >= material_count)
    return make_error(what + ": material " + std::to_string(m.material) + " does not exist");
  return Ok{};
}

Status validate_instance(const SceneDesc& scene, std::size_t i) {
  const Instance& inst = scene.instances[i];
  const std::string what = "instance " + std::to_string(i) + (inst.name.empty() ? "" : " '" + inst.name + "'");
  if (inst.mesh >= scene.meshes.size())
    return make_error(what + ": mesh " + std::to_string(inst.mesh) + " does not exist");
  if (!scene.meshes[inst.mesh].instanced)
    return make_error(what + ": " + mesh_label(scene.meshes[inst.mesh], inst.mesh) +
                      " is world geometry, not an instanced mesh");
  const Affine& a = inst.to_world;
  if (!a.finite()) return make_error(what + ": the transform is not finite");
  const double det = a.determinant();
  if (!(std::abs(det) > 1e-300) || !std::isfinite(det))
    return make_error(what + ": the transform is singular");
  return Ok{};
}

// Books a photon that did not escape (absorbed or cut off) for its emitter
// and the mesh where it ended.
void book_loss(const TraceResult& r, LedgerTally::PerEmitter& emitter, LedgerTally& books) {
  LedgerTally::PerMesh& mesh = books.meshes[r.mesh];
  if (r.fate == Fate::Absorbed) {
    emitter.absorbed.add(r.power_units);
    mesh.absorbed.add(r.power_units);
  } else {
    emitter.cutoff.add(r.power_units);
    mesh.cutoff.add(r.power_units);
  }
}

// The hero's companions after an event with `lobe` at a material acting by
// wavelength (`at`: the material at each wavelength of the grid).
void update_companions(PhotonColour& c, Lobe lobe, const Material* at, const Material& m) {
  if (lobe == Lobe::Dielectric && (!m.ior_nm.empty() || m.abbe_number > 0.0)) {
    for (int j = 1; j < kHeroCount; ++j) c.hero_weight[static_cast<std::size_t>(j)] = 0.0;
    return;
  }
  const double hero = lobe_weight(at[c.wavelength], lobe);
  if (!(hero > 0.0)) return;
  for (int j = 1; j < kHeroCount; ++j) {
    double& w = c.hero_weight[static_cast<std::size_t>(j)];
    if (w != 0.0) w *= lobe_weight(at[hero_companion(c.wavelength, j)], lobe) / hero;
  }
}

// X or Z units (kColourUnits per photon of nominal power) of a photon of
// `power` units: units × power / kPowerUnits, rounded, in integers (exact
// for power = kPowerUnits; no overflow below 2³⁹ nominal photons' power).
std::uint64_t scale_by_power(std::uint64_t units, std::uint64_t power) {
  const std::uint64_t whole = power / kPowerUnits, part = power % kPowerUnits;
  return units * whole + (units * part + kPowerUnits / 2) / kPowerUnits;
}

// Books a spectral photon's power in the radiant bins of its colour state
// at its end (sim/ledger.h): emitted and its fate together.
void book_bins(const WavelengthSampler& w, const PhotonColour& colour, const TraceResult& r,
               LedgerTally::Bins& bins) {
  std::vector<std::uint64_t>& fate = r.fate == Fate::Escaped    ? bins.escaped
                                     : r.fate == Fate::Absorbed ? bins.absorbed
                                                                : bins.cutoff;
  const WavelengthSampler::BinShare share = w.bins(colour, r.power_units);
  for (int i = 0; i < 2; ++i) bins.emitted[share.bin[i]] += share.units[i];
  if (colour.wavelength < 0) {
    for (int i = 0; i < 2; ++i) fate[share.bin[i]] += share.units[i];
  } else {
    const auto k = static_cast<std::size_t>(colour.wavelength);
    bins.emitted[k] += r.power_units;
    fate[k] += r.power_units;
  }
}

}  // namespace

std::uint64_t TracerTally::photons(std::size_t texel) const {
  std::uint64_t n = texel_photons[texel];
  for (std::uint32_t w : texel_wraps) n += w == texel ? 65536u : 0u;
  return n;
}

void TracerTally::clear() {
  std::fill(texel_photons.begin(), texel_photons.end(), std::uint16_t{0});
  texel_wraps.clear();
  std::fill(replicate_photons.begin(), replicate_photons.end(), std::uint16_t{0});
  replicate_wraps.clear();
  std::fill(texel_xz.begin(), texel_xz.end(), std::uint64_t{0});
  ledger.clear();
  near_field.clear();
  next_event.clear();
  images.clear();
}

Result<Tracer> Tracer::create(const SceneDesc& scene, int face_size, const TracerSettings& settings,
                              std::shared_ptr<const EmbreeScene> reuse) {
  if (face_size < 1 || face_size > 16384) return make_error("cube-map face size must lie in 1..16384");
  if (settings.max_bounces < 0) return make_error("the bounce limit must be >= 0");
  TracerSetupTimes times;
  auto t = std::chrono::steady_clock::now();
  for (const Material& m : scene.materials)
    if (Status s = validate(m); !s.ok()) return s.error();
  for (std::size_t i = 0; i < scene.meshes.size(); ++i)
    if (Status s = validate_mesh(scene.meshes[i], i, scene.materials.size()); !s.ok())
      return s.error();
  for (std::size_t i = 0; i < scene.instances.size(); ++i)
    if (Status s = validate_instance(scene, i); !s.ok()) return s.error();
  times.validate_s = seconds_since(t);
  t = std::chrono::steady_clock::now();
  auto emission = EmissionSampler::create(scene);
  if (!emission.ok()) return emission.error();
  times.emission_s = seconds_since(t);
  t = std::chrono::steady_clock::now();
  std::shared_ptr<const EmbreeScene> embree = std::move(reuse);
  times.bvh_reused = embree != nullptr;
  if (!embree) {
    auto built = EmbreeScene::build(scene.meshes, settings.embree, scene.instances);
    if (!built.ok()) return built.error();
    embree = std::make_shared<const EmbreeScene>(std::move(built.value()));
  }
  times.bvh_s = seconds_since(t);

  t = std::chrono::steady_clock::now();
  Tracer tracer(CubeMapGrid(face_size), std::move(embree), std::move(emission.value()), settings);
  tracer.materials_ = scene.materials;
  for (Material& m : tracer.materials_) {
    prepare(m);
    tracer.material_angular_.push_back(m.angular() ? 1 : 0);
    tracer.connectable_lobes_.push_back(connectable_lobe_bits(m));
  }
  for (const Material& m : scene.materials) tracer.lobe_cdfs_.push_back(lobe_cdf(m));
  tracer.meshes_.reserve(scene.meshes.size());
  for (const Mesh& m : scene.meshes) {
    MeshData d;
    d.material = m.material;
    const std::size_t corners = m.indices.size();
    // Per corner, packed; in parallel (a 10⁶-triangle part has 3·10⁶ corners,
    // about six for each vertex: each vertex is packed once, then copied).
    const auto per_corner = [&](const std::vector<Vec3f>& per_vertex, std::vector<PackedUnit>* out) {
      if (per_vertex.empty()) return;
      std::vector<PackedUnit> packed(per_vertex.size());
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, per_vertex.size(), 16384),
                        [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t v = r.begin(); v != r.end(); ++v) packed[v] = pack_unit(per_vertex[v]);
                        });
      out->resize(corners);
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, corners, 16384),
                        [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t c = r.begin(); c != r.end(); ++c) (*out)[c] = packed[m.indices[c]];
                        });
    };
    per_corner(m.normals, &d.corner_normals);
    per_corner(m.tangents, &d.corner_tangents);
    tracer.meshes_.push_back(std::move(d));
  }
  if (scene.spectral()) {
    for (const Material& m : scene.materials)
      if (Status st = validate_spectral_material(m); !st.ok()) return st.error();
    auto wavelengths = WavelengthSampler::create(scene);
    if (!wavelengths.ok()) return wavelengths.error();
    tracer.wavelengths_ = std::make_shared<const WavelengthSampler>(std::move(wavelengths.value()));
    for (const Material& m : scene.materials)
      for (int k = 0; k < kWavelengthCount; ++k) {
        tracer.spectral_materials_.push_back(at_wavelength(m, wavelength_nm(k)));
        prepare(tracer.spectral_materials_.back());
        tracer.spectral_lobe_cdfs_.push_back(lobe_cdf(tracer.spectral_materials_.back()));
        tracer.spectral_connectable_lobes_.push_back(connectable_lobe_bits(tracer.spectral_materials_.back()));
      }
    for (const Emitter& e : scene.emitters) tracer.emitter_axes_.push_back(-1.0 * e.frame.up);
    for (const Material& m : scene.materials) tracer.material_spectral_.push_back(m.spectral() ? 1 : 0);
  }
  for (const Emitter& e : scene.emitters) tracer.emitter_two_sided_.push_back(e.two_sided ? 1 : 0);
  tracer.instances_.reserve(scene.instances.size());
  for (const Instance& i : scene.instances) tracer.instances_.push_back(i.to_world);
  times.shading_s = seconds_since(t);
  tracer.setup_times_ = times;
  tracer.offset_floor_m_ = 0x1.0p-24 * tracer.embree_->bounds().diagonal();
  double grid_mfp = settings.volume_grid_mfp;
  // For measurement only (docs/validation.md, issue 43): the grid's cells in
  // mean free paths, 0 for a ray query per free path.
  if (const char* mfp = std::getenv("GONIO_VOLUME_GRID_MFP"); mfp && *mfp) grid_mfp = std::atof(mfp);
  if (std::optional<VolumeGrid> grid = VolumeGrid::build(scene, grid_mfp))
    tracer.volume_grid_ = std::make_shared<const VolumeGrid>(std::move(*grid));
  const auto scatters = [](const Material& m) { return m.scattering_per_m > 0.0; };
  tracer.scattering_volumes_ = std::any_of(tracer.materials_.begin(), tracer.materials_.end(), scatters) ||
                               std::any_of(tracer.spectral_materials_.begin(), tracer.spectral_materials_.end(), scatters);
  return tracer;
}

TracerTally Tracer::make_tally() const {
  TracerTally t;
  t.texel_photons.assign(grid_.texel_count(), std::uint16_t{0});
  if ((settings_.sampler == SamplerKind::Sobol || settings_.next_event.enabled) && settings_.sobol_replicates > 1) {
    t.replicates = settings_.sobol_replicates;
    t.replicate_photons.assign(grid_.texel_count() * static_cast<std::size_t>(t.replicates), std::uint16_t{0});
  }
  if (wavelengths_) {
    t.texel_xz.assign(2 * grid_.texel_count(), std::uint64_t{0});
  }
  t.ledger = LedgerTally(emission_.emitter_count(), meshes_.size(), radiant_bin_count());
  if (settings_.next_event.enabled) t.next_event.reset(grid_.texel_count(), t.replicates, meshes_.size());
  return t;
}

Vec3 Tracer::offset(const Vec3& p, const Vec3& side_normal, double t) const {
  return p + side_normal * offset_m(max_abs(p) + t);
}

TraceResult Tracer::follow(Vec3 origin, Vec3 direction, PhotonRandom& rng, LedgerTally* books,
                           std::vector<RayQuery>* record, std::uint64_t power, PhotonColour* colour) const {
  return scattering_volumes_ ? follow<true, false>(origin, direction, rng, books, record, power, colour, nullptr)
                             : follow<false, false>(origin, direction, rng, books, record, power, colour, nullptr);
}

// (kVolumes false: no material scatters, so no photon enters a medium and
// the walk's tests below are constant; kConnect false: `connect` is null, so
// no vertex is covered.)
template <bool kVolumes, bool kConnect>
TraceResult Tracer::follow(Vec3 origin, Vec3 direction, PhotonRandom& rng, LedgerTally* books,
                           std::vector<RayQuery>* record, std::uint64_t power, PhotonColour* colour,
                           Connections* connect_in) const {
  Connections* const connect = kConnect ? connect_in : nullptr;
  TraceResult r;
  RayQuery ray{};
  RayHit hit;
  Polarization polarization;
  bool covered = false;  // the last event was a connected non-delta one
  std::uint8_t covered_slot = 0;
  // The last connected vertex, for the balance heuristic's weight of the
  // photon's own escape from it (sim/tracer/next_event.h).
  CoveredVertex covered_at;
  bool image_covered = connect && connect->image_covered_at_start;
  int volume_events = 0;
  // The volume walk's grid (TracerSettings::volume_grid_mfp): right after a
  // scattering event inside a part (`medium`), a free path whose ends lie
  // in one cell (or two sharing a face) on one side of every face plane
  // listed there crossed no face, so
  // it is drawn and decided without a ray query. Its draw is the one the
  // query's branch below would make next (`drawn_s`).
  const Material* medium = nullptr;
  // Whether `medium` is a closed part's (VolumeGrid::closed): a free path
  // there that meets no face ends inside it, so an unproven path's query
  // asks only as far as the drawn path.
  bool medium_closed = false;
  double drawn_s = -1.0;
  // A volume event `s` along the path inside `m` (sim/bsdfs/volume.h):
  // absorbed (chance μa/μt, booked at the part), cut off past
  // kMaxVolumeEvents, or scattered by the phase function. False: the photon
  // ended there (r.fate says how).
  // One draw decides the event (scatter_or_absorb, issue 43).
  const auto volume_event = [&](const Material& m, double s) {
    Vec3 scattered;
    if (!scatter_or_absorb(direction, m.scattering_per_m, m.attenuation_per_m, m.scattering_g, rng, &scattered)) {
      r.fate = Fate::Absorbed;
      return false;
    }
    if (books) ++books->volume_events;
    if (++volume_events > kMaxVolumeEvents) {
      r.fate = Fate::CutOff;
      return false;
    }
    polarization.polarized = false;
    // Light scattered in a volume is not the direct escape a connection
    // stood for: its escape is binned.
    covered = image_covered = false;
    origin = origin + s * direction;
    direction = scattered;
    return true;
  };
  // The grid's memory along the walk (VolumeGrid::Walk): valid while the
  // photon moves by proven free paths only.
  VolumeGrid::Walk walk;
  for (;;) {
    const Material* query_medium = nullptr;  // a closed part's, for a bounded query
    if (kVolumes && medium) {
      const double mu_t = medium->scattering_per_m + medium->attenuation_per_m;
      drawn_s = standard_exponential(rng) / mu_t;
      if (volume_grid_->segment_free(origin, origin + drawn_s * direction, walk)) {
        const double s = drawn_s;
        drawn_s = -1.0;
        if (!volume_event(*medium, s)) return r;
        continue;
      }
      if (medium_closed) query_medium = medium;
      medium = nullptr;
    }
    if (kVolumes) walk.reset();
    ray = ray_query(origin, direction);
    // A free path drawn for the grid and not proven free there: the volume
    // branch below takes it (any other hit leaves it unused). The query
    // then only asks for a face within it: nothing there is the volume
    // event at drawn_s (a face beyond it would have been passed by), found
    // without traversing the rest of the part.
    const double pre_drawn_s = drawn_s;
    drawn_s = -1.0;
    // (The float above the drawn path's nearest, so that a face at
    // t ≤ drawn_s is found: the next float up by its bits, of the path's
    // absolute value, which is finite and may be zero.)
    if (query_medium)
      ray.t_far =
          std::bit_cast<float>(std::bit_cast<std::uint32_t>(std::abs(static_cast<float>(pre_drawn_s))) + 1u);
    if (books) ++books->rays;
    if (record) record->push_back(ray);
    if (!embree_->intersect(ray, &hit)) {
      if (query_medium) {
        if (!volume_event(*query_medium, pre_drawn_s)) return r;
        medium = query_medium;
        continue;
      }
      r.fate = Fate::Escaped;
      r.direction = direction;
      r.origin = origin;
      r.power_units = power;
      r.covered = covered;
      r.covered_slot = covered_slot;
      if (kConnect && covered) r.covered_book = covered_at.book(direction, power);
      r.image_covered = image_covered;
      return r;
    }
    const MeshData& mesh = meshes_[hit.mesh];
    // The shading normals are a likely cache miss: start loading them now.
    if (!mesh.corner_normals.empty())
      __builtin_prefetch(&mesh.corner_normals[3 * static_cast<std::size_t>(hit.triangle)]);
    // A spectral photon draws its wavelength at the first material that
    // acts differently by wavelength (sim/tracer/spectral.h).
    if (colour && colour->wavelength == PhotonColour::kUndrawn && material_spectral_[mesh.material])
      colour->wavelength = wavelengths_->sample(colour->emitter, colour->cos_gamma, rng);
    const int wavelength = colour ? colour->wavelength : PhotonColour::kUndrawn;
    const std::size_t spectral_index =
        static_cast<std::size_t>(mesh.material) * kWavelengthCount + static_cast<std::size_t>(wavelength);
    const Material& material = wavelength < 0 ? materials_[mesh.material] : spectral_materials_[spectral_index];
    const double t = hit.t;
    const Vec3 ng_raw{hit.ng[0], hit.ng[1], hit.ng[2]};
    const bool from_back = dot(ng_raw, direction) > 0.0;
    r.mesh = hit.mesh;
    r.power_units = power;
    // A photon reaching a surface from its back has crossed that mesh's
    // volume. A scattering volume (sim/bsdfs/volume.h): a free path drawn
    // with μt = μs + μa ends inside it, where the photon is absorbed
    // (chance μa/μt, booked at the part) or scattered by the phase
    // function, or reaches the surface. Otherwise Beer–Lambert.
    if (kVolumes && from_back && material.scattering_per_m > 0.0) {
      const double mu_t = material.scattering_per_m + material.attenuation_per_m;
      // Drawn before the query where the walk tried the grid first.
      const double s = pre_drawn_s >= 0.0 ? pre_drawn_s : standard_exponential(rng) / mu_t;
      if (s < t) {
        if (!volume_event(material, s)) return r;
        // The next free path starts inside this medium.
        if (volume_grid_) {
          medium = &material;
          medium_closed = volume_grid_->closed(hit.mesh);
        }
        continue;
      }
    } else if (from_back && material.attenuation_per_m > 0.0 &&
               rng.uniform() >= internal_transmittance(material.attenuation_per_m, t)) {
      r.fate = Fate::Absorbed;
      return r;
    }
    ++r.hits;
    if (books) ++books->meshes[hit.mesh].hits;
    if (r.hits > settings_.max_bounces) {
      r.fate = Fate::CutOff;
      return r;
    }

    const Vec3 ng = ng_raw * (1.0 / std::sqrt(dot(ng_raw, ng_raw)));
    SurfaceFrame frame{ng, ng, {}};
    const Lobe lobe =
        material_angular_[mesh.material]
            ? choose_lobe(lobe_cdf(material, std::abs(dot(direction, ng))), rng.uniform())
            : choose_lobe(wavelength < 0 ? lobe_cdfs_[mesh.material] : spectral_lobe_cdfs_[spectral_index],
                          rng.uniform());
    // Next-event connections here (sim/tracer/next_event.h): a material with
    // non-delta lobes at a mesh that keeps them, grey in a spectral run.
    // (The material's lobes as bits, has_connectable_lobes's answer.)
    const unsigned has_lobes =
        connect ? (wavelength < 0 ? connectable_lobes_[mesh.material] : spectral_connectable_lobes_[spectral_index]) : 0u;
    const bool non_delta = has_lobes != 0 && !(colour && material_spectral_[mesh.material]);
    const unsigned lobes_here = non_delta && connect->far_field ? settings_.next_event.lobes_at(hit.mesh, from_back) : 0u;
    const bool connect_here = (lobes_here & has_lobes) != 0;
    const bool image_here = non_delta && connect->images;
    // Connections read the shading normal for every lobe but the diffuse
    // ones, and the tangent for the glossy lobe; scatter() gets the tangent
    // only for a lobe that reads it (as without connections).
    const bool connect_shading = (connect_here || image_here) && (has_lobes & kShadingFrameLobes) != 0;
    const bool connect_tangent = (connect_here || image_here) && material.glossy > 0.0;
    Vec3 tangent{};
    if (uses_shading_frame(lobe) || connect_shading) {
      const std::size_t c = 3 * static_cast<std::size_t>(hit.triangle);
      const double u = hit.u, v = hit.v, w0 = 1.0 - u - v;
      // An instance's normals and tangents are in its mesh's frame.
      const Affine* place = hit.instance == kNoInstance ? nullptr : &instances_[hit.instance];
      if (!mesh.corner_normals.empty()) {
        const PackedUnit* n3 = &mesh.corner_normals[c];
        Vec3 n = w0 * unpack_unit(n3[0]) + u * unpack_unit(n3[1]) + v * unpack_unit(n3[2]);
        if (place) n = place->normal(n);
        const double len = length(n);
        if (len > 0.0) frame.shading_normal = n / len;
      }
      if ((uses_tangent(lobe) || connect_tangent) && !mesh.corner_tangents.empty()) {
        const PackedUnit* t3 = &mesh.corner_tangents[c];
        tangent = w0 * unpack_unit(t3[0]) + u * unpack_unit(t3[1]) + v * unpack_unit(t3[2]);
        if (place) tangent = place->linear(tangent);
      }
    }
    if (uses_tangent(lobe)) frame.tangent = tangent;
    SurfaceFrame connect_frame = frame;
    connect_frame.tangent = tangent;
    // Hero wavelengths (sim/tracer/spectral.h): each companion's path probability
    // relative to the hero's takes this event's lobe weight at its own
    // wavelength; a dispersive refraction ends the companions.
    if (wavelength >= 0 && material_spectral_[mesh.material] && lobe != Lobe::Absorb)
      update_companions(*colour, lobe, &spectral_materials_[static_cast<std::size_t>(mesh.material) * kWavelengthCount],
                        materials_[mesh.material]);
    if (connect_here) {
      // The lattice's shift from the photon's own numbers: under Sobol'
      // its next two coordinates, so the shifts are stratified across
      // photons (a second stream would not be, and a second scramble of
      // the same points would correlate with the path).
      double xi1, xi2;
      rng.uniform_pair(&xi1, &xi2);
      // The vertex once, for its connections and the photon's own share.
      covered_at.material = &material;
      // (Lobes the material lacks would weigh 0 there: not asked.)
      covered_at.vertex =
          std::construct_at(connect->vertex, material, connect_frame, -1.0 * direction, lobes_here & has_lobes);
      covered_at.connections = settings_.next_event.connections_at(hit.mesh, from_back);
      connect_from(origin + t * direction, t, direction, material, connect_frame, *covered_at.vertex, power, colour,
                   hit.mesh, from_back, xi1, xi2, *connect);
    }
    if (image_here)
      connect_images(origin + t * direction, t, direction, material, connect_frame, power, colour, *connect);
    const ScatterResult s = scatter(material, lobe, frame, direction, rng, &polarization);
    if (s.absorbed) {
      r.fate = Fate::Absorbed;
      return r;
    }
    const bool non_delta_lobe = connectable(s.lobe);
    covered = connect_here && non_delta_lobe && (lobes_here & lobe_bit(s.lobe)) != 0;
    covered_slot = static_cast<std::uint8_t>((from_back ? kLobeCount : 0) + static_cast<int>(s.lobe));
    image_covered = image_here && non_delta_lobe;
    // Back along the incoming ray before the offset: near an edge the hit
    // point can lie a rounding error beyond the neighbouring face, and an
    // offset along this face's normal alone would start the next ray behind
    // that face (a closed box leaked there). A quarter of the offset, so a
    // transmitted ray still starts on the far side.
    // Both offsets scale with the hit point's largest coordinate.
    const Vec3 p = origin + t * direction;
    const double scale = max_abs(p) + t;
    const double off = offset_m(scale);
    const bool to_front = dot(s.direction, ng) > 0.0;
    origin = p - direction * (0x1.0p-20 * scale) + (to_front ? off : -off) * ng;
    direction = s.direction;
    // Into a scattering part (or back into it, reflected at its face): the
    // next free path starts inside it, so it is drawn now and tried on the
    // grid as after a volume event (a closed part: the query would have met
    // its back face and drawn this number there).
    if (kVolumes && volume_grid_ && !to_front && material.scattering_per_m > 0.0 && volume_grid_->closed(hit.mesh)) {
      medium = &material;
      medium_closed = true;
    }
  }
}

// Connections of one vertex traced together (sim/tracer/embree_scene.h's
// packets): a block's directions, queries and answers stay on the stack.
constexpr int kConnectionBlock = 64;

namespace {

// kConnectionBlock elements of T left unwritten until used: a std::array
// would store every element's default member initialisers at each vertex
// (about 1,000 instructions for a block, measured with callgrind: more than
// one connection costs).
template <class T>
class BlockScratch {
  static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>);

 public:
  T* data() { return std::launder(reinterpret_cast<T*>(bytes_)); }
  T& operator[](std::size_t i) { return data()[i]; }

 private:
  alignas(T) unsigned char bytes_[kConnectionBlock * sizeof(T)];
};

}  // namespace

void Tracer::connect_from(const Vec3& p, double t, const Vec3& direction, const Material& m,
                          const SurfaceFrame& frame, const ConnectionVertex& vertex, std::uint64_t power,
                          const PhotonColour* colour, std::uint32_t mesh, bool back, double xi1, double xi2,
                          Connections& c) const {
  NextEventTally& tally = c.tally->next_event;
  const int count = settings_.next_event.connections_at(mesh, back);
  // A rank-1 lattice (k/M, k·φ mod 1) shifted by (ξ1, ξ2): M stratified
  // pairs (one in each 1/M band of the first).
  constexpr double kGolden = 0.61803398874989484820;
  const double scale = max_abs(p) + t;
  const double off = offset_m(scale);
  const Vec3 start = p - direction * (0x1.0p-20 * scale);
  const Vec3& ng = frame.geometric_normal;
  ++tally.vertices;
  // Spectral runs: the photon's X and Z now (a grey vertex leaves them as
  // they are), per photon of Y.
  std::uint64_t x_units = 0, z_units = 0;
  const bool colour_units = colour && wavelengths_;
  if (colour_units) std::tie(x_units, z_units) = this->colour_units(*colour);
  const auto replicates = static_cast<std::size_t>(c.tally->replicates);
  // In blocks of kConnectionBlock: the directions first, then their shadow
  // rays (one origin, so as Embree packets), then the bookings in the order
  // of k — integer sums, so the bytes are those of one ray at a time.
  BlockScratch<ConnectionDirection> drawn;
  BlockScratch<RayQuery> queries;
  std::array<std::uint8_t, kConnectionBlock> blocked;
  std::array<std::uint8_t, kConnectionBlock> which;  // the query's draw in `drawn`
  std::array<std::size_t, kConnectionBlock> slots;
  std::array<double, kConnectionBlock> u1s, u2s;
  for (int k0 = 0; k0 < count; k0 += kConnectionBlock) {
    const int k1 = std::min(count, k0 + kConnectionBlock);
    for (int k = k0; k < k1; ++k) {
      u1s[static_cast<std::size_t>(k - k0)] = (static_cast<double>(k) + xi1) / static_cast<double>(count);
      double u2 = xi2 + static_cast<double>(k) * kGolden;
      u2 -= std::floor(u2);
      u2s[static_cast<std::size_t>(k - k0)] = u2;
    }
    connection_directions(m, vertex, u1s.data(), u2s.data(), static_cast<std::size_t>(k1 - k0), drawn.data());
    std::size_t n = 0;
    for (int k = k0; k < k1; ++k) {
      const ConnectionDirection& cd = drawn[static_cast<std::size_t>(k - k0)];
      if (!(cd.pdf > 0.0) || !(cd.f_cos > 0.0)) continue;
      const Vec3 o = start + (dot(cd.wo, ng) > 0.0 ? off : -off) * ng;
      const std::size_t slot = next_event_slot(mesh, back, cd.lobe);
      ++tally.connections;
      ++tally.slot_connections[slot];
      which[n] = static_cast<std::uint8_t>(k - k0);
      slots[n] = slot;
      queries[n] = ray_query(o, cd.wo);
      ++n;
    }
    embree_->occluded(queries.data(), n, blocked.data());
    for (std::size_t i = 0; i < n; ++i) {
      if (blocked[i]) continue;
      const ConnectionDirection& cd = drawn[which[i]];
      ++tally.escaped;
      ++tally.slot_escaped[slots[i]];
      // The balance heuristic over the M connections and the photon's own
      // escape (which books the same at its direction: CoveredVertex).
      const double w = cd.f_cos / (static_cast<double>(count) * cd.pdf + cd.f_cos);
      const double units_d = static_cast<double>(power) * w;
      const std::uint64_t units = round_units(units_d);
      const std::size_t texel = grid_.texel_of(cd.wo);
      tally.texel_units[texel] += units;
      tally.booked_units += units;
      if (replicates > 1) tally.replicate_units[texel * replicates + c.replicate] += units;
      if (colour_units) {
        const double per = units_d / static_cast<double>(kPowerUnits);
        c.tally->texel_xz[2 * texel] += static_cast<std::uint64_t>(std::llround(static_cast<double>(x_units) * per));
        c.tally->texel_xz[2 * texel + 1] += static_cast<std::uint64_t>(std::llround(static_cast<double>(z_units) * per));
      }
    }
  }
}

std::pair<std::uint64_t, std::uint64_t> Tracer::colour_units(const PhotonColour& colour) const {
  return colour.wavelength >= 0 ? wavelengths_->hero_units(colour)
                                : wavelengths_->expected_units(colour.emitter, colour.cos_gamma);
}

void Tracer::connect_images(const Vec3& p, double t, const Vec3& direction, const Material& m,
                            const SurfaceFrame& frame, std::uint64_t power, const PhotonColour* colour,
                            Connections& c) const {
  const LuminanceCamera& camera = *c.tally->camera;
  const Vec3 wi = -1.0 * direction;
  const double scale = max_abs(p) + t;
  const double off = offset_m(scale);
  const Vec3 back = p - direction * (0x1.0p-20 * scale);
  const Vec3& ng = frame.geometric_normal;
  std::uint64_t x = 0, z = 0;
  if (colour && wavelengths_) std::tie(x, z) = colour_units(*colour);
  // The views' shadow rays share their origin: one packet a block (as
  // connect_from), booked in the order of the views.
  BlockScratch<RayQuery> queries;
  std::array<std::uint8_t, kConnectionBlock> blocked;
  std::array<std::size_t, kConnectionBlock> views;
  std::array<double, kConnectionBlock> fs;
  for (std::size_t k0 = 0; k0 < camera.planes.size(); k0 += kConnectionBlock) {
    const std::size_t k1 = std::min(camera.planes.size(), k0 + kConnectionBlock);
    std::size_t n = 0;
    for (std::size_t k = k0; k < k1; ++k) {
      const Vec3& v = camera.planes[k].toward;
      const double f = non_delta_f_cos(m, frame, wi, v);
      if (!(f > 0.0)) continue;
      const Vec3 o = back + (dot(v, ng) > 0.0 ? off : -off) * ng;
      queries[n] = ray_query(o, v);
      views[n] = k;
      fs[n] = f;
      ++n;
    }
    embree_->occluded(queries.data(), n, blocked.data());
    for (std::size_t i = 0; i < n; ++i) {
      if (blocked[i]) continue;
      c.tally->images.add_connection(camera, views[i], p, static_cast<double>(power) * fs[i], x, z);
    }
  }
}

void Tracer::connect_emission_images(const EmittedPhoton& e, Connections& c) const {
  const LuminanceCamera& camera = *c.tally->camera;
  const bool two_sided = emitter_two_sided_[e.emitter] != 0;
  constexpr double kInvPi = 0.31830988618379067154;
  for (std::size_t k = 0; k < camera.planes.size(); ++k) {
    const Vec3& v = camera.planes[k].toward;
    const double cos_v = dot(v, e.surface_normal);
    // The emitter's cosine density towards v (either side with half the
    // photons when two-sided).
    const double w = two_sided ? 0.5 * std::abs(cos_v) * kInvPi : std::max(0.0, cos_v) * kInvPi;
    if (!(w > 0.0)) continue;
    const Vec3 o = offset(e.origin, cos_v > 0.0 ? e.surface_normal : -1.0 * e.surface_normal, 0.0);
    if (embree_->occluded(ray_query(o, v))) continue;
    std::uint64_t x = 0, z = 0;
    if (wavelengths_) std::tie(x, z) = wavelengths_->expected_units(e.emitter, std::abs(cos_v));
    c.tally->images.add_connection(camera, k, e.origin, static_cast<double>(kPowerUnits) * w, x, z);
  }
}

bool Tracer::connects(const TracerTally& tally) const {
  return settings_.next_event.enabled || tally.camera != nullptr;
}

std::optional<Tracer::Connections> Tracer::connections_for(std::uint64_t photon, TracerTally& tally) const {
  if (!connects(tally)) return std::nullopt;
  const bool far_field = settings_.next_event.enabled, images = tally.camera != nullptr;
  const auto k = static_cast<std::uint64_t>(tally.replicates > 1 ? tally.replicates : 1);
  return Connections{&tally, static_cast<std::uint32_t>(photon % k), far_field, images};
}

TraceResult Tracer::trace(const Vec3& origin, const Vec3& direction, PhotonRandom& rng,
                          int wavelength) const {
  FloatModeGuard float_mode;
  GONIO_CHECK(wavelength < kWavelengthCount && (wavelength < 0 || wavelengths_));
  PhotonColour colour;
  colour.wavelength = wavelength;
  return follow(origin, normalize(direction), rng, nullptr, nullptr, kPowerUnits,
                wavelength >= 0 ? &colour : nullptr);
}

PhotonColour Tracer::start_colour(const EmittedPhoton& e) const {
  PhotonColour c;
  c.emitter = e.emitter;
  c.cos_gamma = e.on_surface ? dot(e.direction, e.surface_normal) : dot(e.direction, emitter_axes_[e.emitter]);
  return c;
}

void Tracer::record_rays(std::uint64_t seed, std::uint64_t first, std::uint64_t count,
                         std::vector<RayQuery>* rays) const {
  FloatModeGuard float_mode;
  std::optional<SobolCursor> cursor;  // Sobol': the thread's photons in order
  if (settings_.sampler == SamplerKind::Sobol) cursor.emplace(seed, settings_.sobol_replicates);
  for (std::uint64_t i = first; i < first + count; ++i) {
    PhotonRandom rng = cursor ? PhotonRandom(seed, cursor->at(i)) : PhotonRandom(seed, i);
    const EmittedPhoton e = emission_.sample(rng);
    PhotonColour colour = wavelengths_ ? start_colour(e) : PhotonColour{};
    const Vec3 origin = e.on_surface ? offset(e.origin, e.surface_normal, 0.0) : e.origin;
    follow(origin, e.direction, rng, nullptr, rays, kPowerUnits, wavelengths_ ? &colour : nullptr);
  }
}

void Tracer::trace_photons(std::uint64_t seed, std::uint64_t first, std::uint64_t count,
                           TracerTally& tally) const {
  // Whether photons connect is the same for every photon of the call.
  const bool connections = connects(tally);
  if (scattering_volumes_) {
    if (connections)
      trace_photons_as<true, true>(seed, first, count, tally);
    else
      trace_photons_as<true, false>(seed, first, count, tally);
  } else {
    if (connections)
      trace_photons_as<false, true>(seed, first, count, tally);
    else
      trace_photons_as<false, false>(seed, first, count, tally);
  }
}

template <bool kVolumes, bool kConnect>
void Tracer::trace_photons_as(std::uint64_t seed, std::uint64_t first, std::uint64_t count,
                              TracerTally& tally) const {
  FloatModeGuard float_mode;
  LedgerTally& books = tally.ledger;
  // Escapes land on random texels: each count is incremented one escape
  // later, after a prefetch, so that the cache miss overlaps tracing.
  constexpr std::uint32_t kNone = ~0u;
  std::uint32_t pending = kNone;
  std::uint64_t pending_x = 0, pending_z = 0;  // spectral: the pending escape's X and Z units
  const bool spectral = wavelengths_ != nullptr;
  // Sobol' replicates: the pending escape's slot texel · K + r as well.
  const auto replicates = static_cast<std::uint64_t>(tally.replicates);
  std::uint32_t pending_slot = 0;
  auto count_escape = [&](std::uint32_t texel) {
    if (++tally.texel_photons[texel] == 0) tally.texel_wraps.push_back(texel);
    if (replicates > 0 && ++tally.replicate_photons[pending_slot] == 0) tally.replicate_wraps.push_back(pending_slot);
    if (spectral) {
      tally.texel_xz[2 * static_cast<std::size_t>(texel)] += pending_x;
      tally.texel_xz[2 * static_cast<std::size_t>(texel) + 1] += pending_z;
    }
  };
  // A covered escape's own share of its vertex's direct escape (the
  // balance heuristic's weight, TraceResult::covered_book), booked as the
  // connections are (connect_from): units, replicate, colour.
  auto book_covered_escape = [&](const TraceResult& r, const PhotonColour& colour, std::uint32_t replicate) {
    NextEventTally& ne = tally.next_event;
    const std::uint64_t units = round_units(r.covered_book);
    if (units == 0) return;
    const std::size_t texel = grid_.texel_of(r.direction);
    ne.texel_units[texel] += units;
    ne.booked_units += units;
    if (replicates > 1) ne.replicate_units[texel * replicates + replicate] += units;
    if (spectral) {
      const auto [x, z] = colour_units(colour);
      const double per = r.covered_book / static_cast<double>(kPowerUnits);
      tally.texel_xz[2 * texel] += static_cast<std::uint64_t>(std::llround(static_cast<double>(x) * per));
      tally.texel_xz[2 * texel + 1] += static_cast<std::uint64_t>(std::llround(static_cast<double>(z) * per));
    }
  };
  // The photons' last connected vertex (follow builds it there).
  ConnectionVertex covered_vertex;
  static_assert(std::is_trivially_destructible_v<ConnectionVertex>);
  std::optional<SobolCursor> cursor;  // Sobol': the thread's photons in order
  if (settings_.sampler == SamplerKind::Sobol) cursor.emplace(seed, settings_.sobol_replicates);
  for (std::uint64_t i = first; i < first + count; ++i) {
    PhotonRandom rng = cursor ? PhotonRandom(seed, cursor->at(i)) : PhotonRandom(seed, i);
    const EmittedPhoton e = emission_.sample(rng);
    LedgerTally::PerEmitter& eb = books.emitters[e.emitter];
    eb.emitted.add(kPowerUnits);
    const Vec3 origin = e.on_surface ? offset(e.origin, e.surface_normal, 0.0) : e.origin;
    PhotonColour colour = wavelengths_ ? start_colour(e) : PhotonColour{};
    std::optional<Connections> connect;
    if constexpr (kConnect) connect = connections_for(i, tally);
    if (connect) connect->vertex = &covered_vertex;
    if (connect && connect->images && e.on_surface) {
      connect_emission_images(e, *connect);
      connect->image_covered_at_start = true;
    }
    const TraceResult r = follow<kVolumes, kConnect>(origin, e.direction, rng, &books, nullptr, kPowerUnits,
                                                     wavelengths_ ? &colour : nullptr, connect ? &*connect : nullptr);
    if (spectral) book_bins(*wavelengths_, colour, r, books.bins);
    if (r.fate == Fate::Escaped && tally.camera && !r.image_covered) {
      std::uint64_t x = 0, z = 0;
      if (spectral) std::tie(x, z) = colour_units(colour);
      tally.images.add_escape(*tally.camera, r.origin, r.direction, r.power_units, x, z);
    }
    if (r.fate == Fate::Escaped && r.hits == 0 && settings_.next_event.enabled)
      tally.next_event.direct_units += r.power_units;
    if (kConnect && r.fate == Fate::Escaped && r.covered) {
      // Not binned: it books its share beside the connections (the balance
      // heuristic, sim/tracer/next_event.h).
      tally.next_event.covered_units += r.power_units;
      book_covered_escape(r, colour, connect->replicate);
      const std::size_t slot = static_cast<std::size_t>(r.mesh) * kSlotsPerMesh + r.covered_slot;
      tally.next_event.slot_covered_units[slot] += r.power_units;
      if (r.hits >= 2) tally.next_event.slot_multi_units[slot] += r.power_units;
      eb.escaped.add(r.power_units);
      if (i < tally.capture_below) tally.escaped.push_back({i, r.origin, r.direction, r.power_units});
      if (tally.near_planes) tally.near_field.add(*tally.near_planes, r.origin, r.direction, r.power_units);
      continue;
    }
    switch (r.fate) {
      case Fate::Escaped: {
        const auto texel = static_cast<std::uint32_t>(grid_.texel_of(r.direction));
        __builtin_prefetch(&tally.texel_photons[texel], 1);
        if (pending != kNone) count_escape(pending);
        pending = texel;
        if (replicates > 0) {
          pending_slot = static_cast<std::uint32_t>(texel * replicates + i % replicates);
          __builtin_prefetch(&tally.replicate_photons[pending_slot], 1);
        }
        eb.escaped.add(r.power_units);
        if (i < tally.capture_below) tally.escaped.push_back({i, r.origin, r.direction, r.power_units});
        if (spectral) {
          __builtin_prefetch(&tally.texel_xz[2 * static_cast<std::size_t>(texel)], 1);
          if (colour.wavelength >= 0) {
            std::tie(pending_x, pending_z) = wavelengths_->hero_units(colour);
          } else {
            std::tie(pending_x, pending_z) = wavelengths_->expected_units(colour.emitter, colour.cos_gamma);
          }
        }
        if (tally.near_planes) tally.near_field.add(*tally.near_planes, r.origin, r.direction, r.power_units);
        break;
      }
      case Fate::Absorbed:
      case Fate::CutOff:
        book_loss(r, eb, books);
        break;
    }
  }
  if (pending != kNone) count_escape(pending);
}

void Tracer::trace_photons_guided(std::uint64_t seed, std::uint64_t first, std::uint64_t count,
                                  const EmissionGuide& guide, TracerTally& tally,
                                  GuideTally& guide_tally) const {
  FloatModeGuard float_mode;
  LedgerTally& books = tally.ledger;
  const bool spectral = wavelengths_ != nullptr;
  std::optional<SobolCursor> cursor;  // Sobol': the thread's photons in order
  if (settings_.sampler == SamplerKind::Sobol) cursor.emplace(seed, settings_.sobol_replicates);
  for (std::uint64_t i = first; i < first + count; ++i) {
    PhotonRandom rng = cursor ? PhotonRandom(seed, cursor->at(i)) : PhotonRandom(seed, i);
    const EmittedPhoton e = emission_.sample(rng);
    const std::uint32_t source_texel = guide.emission_texel(e.direction);
    if (!guide.accept(source_texel, rng)) {
      ++guide_tally.dropped;
      continue;
    }
    const std::uint64_t power = guide.power_units(source_texel);
    LedgerTally::PerEmitter& eb = books.emitters[e.emitter];
    eb.emitted.add(power);
    ++guide_tally.traced[source_texel];
    const Vec3 origin = e.on_surface ? offset(e.origin, e.surface_normal, 0.0) : e.origin;
    // Spectral scenes: the photon's colour as in trace_photons; its X and Z
    // carry its power like its Y (x_units per kPowerUnits of power).
    PhotonColour colour = spectral ? start_colour(e) : PhotonColour{};
    const TraceResult r = follow(origin, e.direction, rng, &books, nullptr, power, spectral ? &colour : nullptr);
    if (spectral) book_bins(*wavelengths_, colour, r, books.bins);
    switch (r.fate) {
      case Fate::Escaped: {
        const auto texel = static_cast<std::uint32_t>(grid_.texel_of(r.direction));
        if (++tally.texel_photons[texel] == 0) tally.texel_wraps.push_back(texel);
        if (spectral) {
          std::uint64_t x = 0, z = 0;
          if (colour.wavelength >= 0) {
            std::tie(x, z) = wavelengths_->hero_units(colour);
          } else {
            std::tie(x, z) = wavelengths_->expected_units(colour.emitter, colour.cos_gamma);
          }
          tally.texel_xz[2 * static_cast<std::size_t>(texel)] += scale_by_power(x, r.power_units);
          tally.texel_xz[2 * static_cast<std::size_t>(texel) + 1] += scale_by_power(z, r.power_units);
        }
        guide_tally.extra_units[texel] += r.power_units - kPowerUnits;
        guide_tally.importance_sum[source_texel] += guide.importance(texel);
        eb.escaped.add(r.power_units);
        if (i < tally.capture_below) tally.escaped.push_back({i, r.origin, r.direction, r.power_units});
        if (tally.near_planes) tally.near_field.add(*tally.near_planes, r.origin, r.direction, r.power_units);
        break;
      }
      case Fate::Absorbed:
      case Fate::CutOff:
        book_loss(r, eb, books);
        break;
    }
  }
}

}  // namespace gonio::sim
