// The photon tracer: emits photons, follows them through the luminaire with
// Embree and the material model, and bins the escaped ones by direction into
// a far-field cube map, keeping the energy ledger.
//
// Determinism: photon i of a run draws its numbers from (seed, i) alone
// under either sampler (sim/samplers/random.h, sim/samplers/sampler.h), and everything a
// photon leaves behind is an integer (texel photon counts, power units,
// ledger counts), so sums do not depend
// on how photons are split between threads or chunks: same seed, same bytes.
//
// Robustness against self-intersection: a scattered ray starts at the hit
// point moved off the surface along the geometric normal, to the side the
// ray leaves towards, by 2⁻¹⁸·(max |coordinate| + hit distance) plus
// 2⁻²⁴ of the scene's diagonal: ~30 float ulps of the point's magnitude,
// far above Embree's rounding and far below any luminaire feature.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "photometry/diagnostics.h"
#include "sim/detectors/cube_map.h"
#include "sim/detectors/luminance_image.h"
#include "sim/tracer/embree_scene.h"
#include "sim/tracer/volume_grid.h"
#include "sim/emitters/emission.h"
#include "sim/emitters/emission_guide.h"
#include "sim/ledger.h"
#include "sim/detectors/near_field.h"
#include "sim/bsdfs/material.h"
#include "sim/tracer/next_event.h"
#include "sim/samplers/random.h"
#include "sim/samplers/sampler.h"
#include "sim/scene.h"
#include "sim/tracer/spectral.h"
#include "sim/tracer/unit_vector.h"

namespace gonio::sim {

struct ConnectionVertex;  // sim/bsdfs/bsdf_eval_pair.h

struct TracerSettings {
  // Surface interactions a photon may scatter at; on reaching a surface
  // once more it is cut off (booked as `cutoff`, not absorbed). 0: every
  // photon that meets any surface is cut off.
  int max_bounces = 100;
  // What photon i's numbers come from (sim/samplers/sampler.h).
  SamplerKind sampler = SamplerKind::Random;
  // Sobol': interleaved independent scrambles (replicates, sim/samplers/sampler.h),
  // 1 … kMaxSobolReplicates; with more than one, plain tracing also counts
  // escapes per replicate (TracerTally::replicate_photons).
  int sobol_replicates = kSobolReplicates;
  EmbreeSceneOptions embree;
  // Next-event estimation for the far field (sim/tracer/next_event.h); with it,
  // plain tracing counts replicates under either sampler (K > 1).
  NextEventSettings next_event;
  // Volume walks (issue 43): free paths inside scattering parts that end in
  // the cell they start in, or in a cell sharing a face with it, of a grid of
  // this many mean free paths (1/(μs + μa)), and lie on one side of every
  // plane of the triangles that meet those cells, need no ray
  // query (sim/tracer/volume_grid.h). The same draws and decisions as a ray
  // query per free path (the same bytes) in closed parts with nothing
  // inside them. 0: a ray query for every free path. For measurement,
  // $GONIO_VOLUME_GRID_MFP overrides it (0: off).
  double volume_grid_mfp = 10.0;
};

// Wall time of each part of Tracer::create [s].
struct TracerSetupTimes {
  double validate_s = 0.0;  // scene checks (indices, finite values, materials)
  double emission_s = 0.0;  // emission tables (alias tables, profile samplers)
  double bvh_s = 0.0;       // Embree scene and BVH build
  double shading_s = 0.0;   // per-corner shading normals and tangents
  bool bvh_reused = false;  // the BVH of an earlier tracer of the same geometry was used
};

// What one photon did.
enum class Fate : std::uint8_t { Escaped, Absorbed, CutOff };

struct TraceResult {
  Fate fate = Fate::Escaped;
  Vec3 direction;               // unit direction it escaped along (Escaped)
  Vec3 origin;                  // start of the free path it escaped along (Escaped) [m]
  std::uint32_t mesh = 0;       // where it was absorbed or cut off
  int hits = 0;                 // surfaces reached (scattered or absorbed at)
  std::uint64_t power_units = kPowerUnits;  // its power at the end (ledger.h units)
  // Escaped: its last event was a non-delta scattering at a vertex that
  // made next-event connections, which stand for this escape in the far
  // field (sim/tracer/next_event.h); `mesh` is that vertex's, covered_slot its
  // side and lobe (next_event_slot's last two).
  bool covered = false;
  std::uint8_t covered_slot = 0;
  // Covered: what its own escape books as one more sample of that vertex's
  // direct escape (the balance heuristic against the M connections:
  // power · f / (M·p + f) at its direction, sim/tracer/next_event.h) [units].
  double covered_book = 0.0;
  // The same for the luminance images' connections (sim/detectors/
  // luminance_image.h): its last event, or its emission from an area
  // emitter, sent a connection to every view.
  bool image_covered = false;
};

// What a thread accumulates: escaped photons per texel and the books.
// Counts are 16-bit to halve the histogram's cache footprint (escapes land
// on random texels); each wrap-around of a texel's count is listed in
// `texel_wraps` and stands for 65536 more photons.

struct TracerTally {
  std::vector<std::uint16_t> texel_photons;  // photons escaped per texel, mod 65536
  std::vector<std::uint32_t> texel_wraps;    // a texel per 65536 photons
  // Spectral scenes only (empty otherwise): X and Z per texel in
  // kColourUnits per photon of Y (sim/tracer/spectral.h), interleaved (X of texel
  // t at 2t, Z at 2t + 1: one cache line per escape).
  std::vector<std::uint64_t> texel_xz;
  std::uint64_t photons(std::size_t texel) const;  // for tests: the full count (slow)
  // Sobol' with K = `replicates` > 1, plain tracing (trace_photons): escapes
  // per texel and replicate at texel · K + r, mod 65536, wraps as above (the
  // slot's index); empty (replicates 0) otherwise.
  int replicates = 0;
  std::vector<std::uint16_t> replicate_photons;
  std::vector<std::uint32_t> replicate_wraps;
  LedgerTally ledger;
  // Escapes of photons with a run-wide index below capture_below, kept
  // (EscapedRay); clear() leaves them.
  std::uint64_t capture_below = 0;
  std::vector<EscapedRay> escaped;
  // Near-field planes (sim/detectors/near_field.h): every escape is binned on them
  // when set (not owned); clear() zeroes near_field.
  const NearFieldPlanes* near_planes = nullptr;
  NearFieldTally near_field;
  // Next-event connections (TracerSettings::next_event; empty otherwise).
  NextEventTally next_event;
  // Luminance images (sim/detectors/luminance_image.h): escapes and
  // connections are booked into `images` when set (not owned); clear()
  // zeroes them.
  const LuminanceCamera* camera = nullptr;
  LuminanceTally images;

  void clear();
};

class Tracer {
 public:
  // Checks the scene (mesh indices, finite positions, normals and tangents
  // per vertex, material indices, materials, emitters) and builds the Embree
  // scene and the emission samplers. Errors name the mesh, material or
  // emitter at fault. `face_size`: texels along a cube-map face edge.
  // `reuse`: an Embree scene built before for the same geometry (meshes'
  // positions and indices, instances: sim::same_geometry) and Embree
  // options, shared instead of building another; the caller vouches for it.
  static Result<Tracer> create(const SceneDesc& scene, int face_size,
                               const TracerSettings& settings = {},
                               std::shared_ptr<const EmbreeScene> reuse = nullptr);

  // An empty tally for this scene and grid.
  TracerTally make_tally() const;

  // Emits and traces photons [first, first + count) of the run `seed`,
  // adding them to `tally`. Thread-safe (const); sets flush-to-zero and
  // denormals-are-zero for its duration.
  void trace_photons(std::uint64_t seed, std::uint64_t first, std::uint64_t count,
                     TracerTally& tally) const;

  // Importance-guided emission (sim/emitters/emission_guide.h): draws photons
  // [first, first + count) like trace_photons, traces each with the guide's
  // acceptance probability for its emission direction, starting with the
  // guide's power, and books what the guide needs in `guide_tally` (the
  // power of escapes above kPowerUnits goes there; `tally` counts the
  // photons). The ledger books each traced photon's power as
  // emitted, so it closes exactly; dropped photons are counted in
  // guide_tally.dropped only. Spectral scenes: a photon's X and Z scale with
  // its power like its Y (sim/tracer/spectral.h).
  void trace_photons_guided(std::uint64_t seed, std::uint64_t first, std::uint64_t count,
                            const EmissionGuide& guide, TracerTally& tally,
                            GuideTally& guide_tally) const;

  // Follows one photon from a given start off any surface (validation cases
  // with beams); books nothing. `direction` need not be unit. `wavelength`:
  // an index of sim/tracer/spectral.h's grid, which the materials then act at
  // (spectral scenes only); -1: grey.
  TraceResult trace(const Vec3& origin, const Vec3& direction, PhotonRandom& rng,
                    int wavelength = -1) const;

  // Whether photons carry wavelengths (SceneDesc::spectral()), and their sampler.
  bool spectral() const { return wavelengths_ != nullptr; }
  const WavelengthSampler* wavelengths() const { return wavelengths_.get(); }
  // The radiant books' bins (WavelengthSampler::bin_count; 0 for grey scenes).
  std::size_t radiant_bin_count() const { return wavelengths_ ? wavelengths_->bin_count() : 0; }

  // A point on a surface moved off it towards unit `side_normal` by the rule
  // at the top (t: the length of the path that reached it; 0 for emission).
  Vec3 offset(const Vec3& p, const Vec3& side_normal, double t) const;

  // Emits and traces photons [first, first + count) like trace_photons but
  // records every ray query instead of booking (benchmarks replay them with
  // EmbreeScene::measure_rays to separate Embree's cost from the tracer's).
  void record_rays(std::uint64_t seed, std::uint64_t first, std::uint64_t count,
                   std::vector<RayQuery>* rays) const;

  const CubeMapGrid& grid() const { return grid_; }
  const EmbreeScene& embree() const { return *embree_; }
  const std::shared_ptr<const EmbreeScene>& shared_embree() const { return embree_; }
  const EmissionSampler& emission() const { return emission_; }
  std::size_t mesh_count() const { return meshes_.size(); }
  std::size_t emitter_count() const { return emission_.emitter_count(); }
  const TracerSettings& settings() const { return settings_; }
  // Sets next-event estimation after a pilot (Simulation::create); not
  // while photons are traced. Meshes: one entry per mesh or empty.
  void set_next_event(const NextEventSettings& next_event) { settings_.next_event = next_event; }
  const TracerSetupTimes& setup_times() const { return setup_times_; }

 private:
  struct MeshData {
    std::uint32_t material;
    // Shading normals and tangents at the three corners of each triangle,
    // stored by triangle so that a hit reads one cache line, and packed
    // (sim/tracer/unit_vector.h: 4 bytes a corner rather than 12).
    std::vector<PackedUnit> corner_normals;   // 3 per triangle, may be empty
    std::vector<PackedUnit> corner_tangents;  // 3 per triangle, may be empty
  };

  Tracer(CubeMapGrid grid, std::shared_ptr<const EmbreeScene> embree, EmissionSampler emission,
         TracerSettings settings)
      : grid_(std::move(grid)), embree_(std::move(embree)), emission_(std::move(emission)),
        settings_(settings) {}

  // One photon's next-event connections: where they book.
  struct Connections {
    TracerTally* tally;
    std::uint32_t replicate;   // photon mod K
    bool far_field;            // next-event estimation for the far field
    bool images;               // connections to the luminance images (tally->camera)
    bool image_covered_at_start = false;  // its emission connected to the images
    // Where the photon's last connected vertex is built (the thread's, kept
    // outside the photon's own frame).
    ConnectionVertex* vertex = nullptr;
  };
  // One photon's path. Compiled for what the scene and the run need
  // (issue 43): kVolumes, a scattering volume may be met (scattering_volumes_:
  // the volume walk's state); kConnect, connections may be made (`connect`
  // may be non-null: the balance heuristic's state). Chosen once per call of
  // trace_photons; a photon without either pays for neither.
  template <bool kVolumes, bool kConnect>
  TraceResult follow(Vec3 origin, Vec3 direction, PhotonRandom& rng, LedgerTally* books,
                     std::vector<RayQuery>* record, std::uint64_t power, PhotonColour* colour,
                     Connections* connect) const;
  // Without connections, for this tracer's scene.
  TraceResult follow(Vec3 origin, Vec3 direction, PhotonRandom& rng, LedgerTally* books,
                     std::vector<RayQuery>* record = nullptr,
                     std::uint64_t power = kPowerUnits, PhotonColour* colour = nullptr) const;
  // trace_photons's loop for one choice of follow's flags.
  template <bool kVolumes, bool kConnect>
  void trace_photons_as(std::uint64_t seed, std::uint64_t first, std::uint64_t count, TracerTally& tally) const;
  // The connections from a vertex at p (reached along `t` of `direction`)
  // with the material and frame there (sim/tracer/next_event.h).
  void connect_from(const Vec3& p, double t, const Vec3& direction, const Material& material,
                    const SurfaceFrame& frame, const ConnectionVertex& vertex, std::uint64_t power,
                    const PhotonColour* colour, std::uint32_t mesh, bool back, double xi1, double xi2,
                    Connections& c) const;
  // The luminance images' connections from a vertex (as connect_from) and
  // from an area emitter's emission.
  void connect_images(const Vec3& p, double t, const Vec3& direction, const Material& material,
                      const SurfaceFrame& frame, std::uint64_t power, const PhotonColour* colour,
                      Connections& c) const;
  void connect_emission_images(const EmittedPhoton& e, Connections& c) const;
  // The X and Z units per photon of Y of a photon's colour now (spectral).
  std::pair<std::uint64_t, std::uint64_t> colour_units(const PhotonColour& colour) const;
  // Whether photons traced into `tally` make connections: next-event
  // estimation of the far field is on, or the tally has luminance images.
  bool connects(const TracerTally& tally) const;
  // Connections for photon i under this tracer's settings (null when off).
  std::optional<Connections> connections_for(std::uint64_t photon, TracerTally& tally) const;
  // A spectral photon's colour state at emission (nothing drawn yet).
  PhotonColour start_colour(const EmittedPhoton& e) const;
  // The offset's length for scale = max |coordinate| + t: 2⁻¹⁸·scale plus
  // the floor [m].
  double offset_m(double scale) const { return 0x1.0p-18 * scale + offset_floor_m_; }
  // TracerSettings::volume_grid_mfp's grid (null: none).
  std::shared_ptr<const VolumeGrid> volume_grid_;
  // Some material (at some wavelength) scatters in its volume
  // (Material::scattering_per_m > 0): follow<true, ...>.
  bool scattering_volumes_ = false;

  CubeMapGrid grid_;
  std::shared_ptr<const EmbreeScene> embree_;
  EmissionSampler emission_;
  TracerSettings settings_;
  std::vector<MeshData> meshes_;
  std::vector<Affine> instances_;  // SceneDesc::instances' transforms
  std::vector<Material> materials_;
  std::vector<LobeCdf> lobe_cdfs_;  // per material
  std::vector<char> material_angular_;  // per material: weights vary with incidence (Material::angular)
  // Per material (and per spectral material): the non-delta lobes it has
  // (sim/bsdfs/bsdf_eval.h's bits, has_connectable_lobes), asked at every
  // hit where connections are made.
  std::vector<std::uint16_t> connectable_lobes_, spectral_connectable_lobes_;
  // Spectral scenes: each material at each wavelength (material ·
  // kWavelengthCount + k) with its lobe table, and the wavelength sampler.
  std::vector<Material> spectral_materials_;
  std::vector<LobeCdf> spectral_lobe_cdfs_;
  std::shared_ptr<const WavelengthSampler> wavelengths_;
  std::vector<char> material_spectral_;  // per material: acts differently by wavelength
  std::vector<Vec3> emitter_axes_;  // per emitter: its γ = 0 direction (point emitters)
  std::vector<char> emitter_two_sided_;  // per emitter
  double offset_floor_m_ = 0.0;
  TracerSetupTimes setup_times_;
};

}  // namespace gonio::sim
