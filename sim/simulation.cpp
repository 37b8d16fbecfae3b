#include "sim/simulation.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <initializer_list>
#include <string>
#include <utility>

namespace gonio::sim {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// Calls f on every count of a tally, in a fixed order.
template <class F>
void each_count(LedgerTally& t, F&& f) {
  for (LedgerTally::PerEmitter& e : t.emitters)
    for (TallyLine* line : {&e.emitted, &e.escaped, &e.absorbed, &e.cutoff}) {
      f(line->photons);
      f(line->power_units);
    }
  for (LedgerTally::PerMesh& m : t.meshes) {
    f(m.hits);
    for (TallyLine* line : {&m.absorbed, &m.cutoff}) {
      f(line->photons);
      f(line->power_units);
    }
  }
  f(t.rays);
  f(t.volume_events);
  for (auto* values : {&t.bins.emitted, &t.bins.escaped, &t.bins.absorbed, &t.bins.cutoff})
    for (std::uint64_t& v : *values) f(v);
}

// The box the luminance images must see: every placed vertex, point
// emitter and ray start (at least 2 cm a side around a point).
std::pair<Vec3, Vec3> luminaire_box(const SceneDesc& scene) {
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  const auto take = [&](const Vec3& p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  };
  for_each_luminaire_point(scene, take);
  if (!(lo.x <= hi.x)) lo = hi = Vec3{0.0, 0.0, 0.0};
  const Vec3 pad{0.01, 0.01, 0.01};
  const Vec3 mid = 0.5 * (lo + hi);
  return {Vec3{std::min(lo.x, mid.x - pad.x), std::min(lo.y, mid.y - pad.y), std::min(lo.z, mid.z - pad.z)},
          Vec3{std::max(hi.x, mid.x + pad.x), std::max(hi.y, mid.y + pad.y), std::max(hi.z, mid.z + pad.z)}};
}

template <class F>
void each_count(GuideTally& t, F&& f) {
  for (auto* values : {&t.importance_sum, &t.traced, &t.extra_units})
    for (std::uint64_t& v : *values) f(v);
  f(t.dropped);
}

}  // namespace

struct Simulation::Impl {
  SceneDesc scene;
  SimulationSettings settings;
  Tracer tracer;
  tbb::task_arena arena;
  tbb::enumerable_thread_specific<TracerTally> tallies;

  std::vector<std::uint64_t> texel_photons;  // over all iterations
  std::vector<std::uint64_t> texel_units;    // power units, ledger.h
  // Sobol' replicates (plain emission only): escapes per texel and
  // replicate, texel · K + r, over all iterations; empty: none.
  int replicates = 0;
  std::vector<std::uint64_t> replicate_photons;
  // Spectral scenes only: X and Z over all iterations, kColourUnits per
  // photon of Y (sim/tracer/spectral.h).
  std::vector<std::uint64_t> texel_x;
  std::vector<std::uint64_t> texel_z;
  LedgerTally books;
  std::vector<EscapedRay> escaped_rays;  // by photon index
  // Next-event estimation: the connections' power units per texel and per
  // texel and replicate, over all iterations, and the run's counts.
  NextEventSummary next_event;
  std::vector<std::uint64_t> nee_units;
  std::vector<std::uint64_t> nee_replicate_units;
  std::uint64_t nee_booked_units = 0, nee_covered_units = 0;
  std::unique_ptr<LuminanceCamera> camera;       // null: no luminance images
  LuminanceTally image_sum;                      // over all iterations
  std::unique_ptr<NearFieldPlanes> near_planes;  // null: no near field
  NearFieldTally near_sum;                       // over all iterations
  SimulationStats stats;
  const Ranks* ranks = nullptr;

  // The iteration being added: its counts (add_iteration) and its books.
  std::vector<std::uint64_t> iteration;
  LedgerTally books_iteration;

  // Guided emission only.
  std::unique_ptr<EmissionGuide> guide;
  tbb::enumerable_thread_specific<GuideTally> guide_tallies;
  GuideTally guide_iteration;

  Impl(SceneDesc s, const SimulationSettings& set, Tracer t, int threads)
      : scene(std::move(s)), settings(set), tracer(std::move(t)), arena(threads),
        tallies([this] {
          TracerTally tally = tracer.make_tally();
          if (replicates == 0) {  // guided emission counts no replicates
            tally.replicates = 0;
            tally.replicate_photons.clear();
          }
          tally.capture_below = settings.capture_escaped_photons;
          if (camera) {
            tally.camera = camera.get();
            tally.images.reset(*camera);
          }
          if (near_planes) {
            tally.near_planes = near_planes.get();
            tally.near_field.reset(*near_planes);
          }
          return tally;
        }),
        texel_photons(tracer.grid().texel_count(), 0),
        texel_units(tracer.grid().texel_count(), 0),
        books(tracer.emitter_count(), tracer.mesh_count(), tracer.radiant_bin_count()),
        ranks(set.ranks),
        books_iteration(tracer.emitter_count(), tracer.mesh_count(), tracer.radiant_bin_count()),
        guide(set.importance.enabled
                  ? std::make_unique<EmissionGuide>(set.importance, set.face_size)
                  : nullptr),
        guide_tallies([this] { return guide->make_tally(); }) {
    if (guide) guide_iteration = guide->make_tally();
    if (!guide && (set.sampler == SamplerKind::Sobol || tracer.settings().next_event.enabled) &&
        set.sobol_replicates > 1) {
      replicates = set.sobol_replicates;
      replicate_photons.assign(tracer.grid().texel_count() * static_cast<std::size_t>(replicates), 0);
    }
    if (tracer.settings().next_event.enabled) {
      nee_units.assign(tracer.grid().texel_count(), 0);
      nee_replicate_units.assign(replicate_photons.size(), 0);
    }
    if (tracer.spectral()) {
      texel_x.assign(tracer.grid().texel_count(), 0);
      texel_z.assign(tracer.grid().texel_count(), 0);
    }
    if (!set.luminance.views.empty()) {
      const auto [lower, upper] = luminaire_box(scene);
      camera = std::make_unique<LuminanceCamera>(
          make_luminance_camera(set.luminance, lower, upper, scene.frame, tracer.spectral()));
      image_sum.reset(*camera);
    }
    if (!set.near_field_distances_m.empty()) {
      near_planes = std::make_unique<NearFieldPlanes>();
      near_planes->centre = pilot_centre();
      near_planes->frame = scene.frame;
      near_planes->distances_m = set.near_field_distances_m;
      near_sum.reset(*near_planes);
    }
  }

  // The planes' photometric centre (luminous_centre): the escapes of the
  // run's first kCentrePilotPhotons photons, traced here on this thread
  // (every rank traces the same ones: the same centre everywhere).
  Vec3 pilot_centre() const {
    TracerTally pilot = tracer.make_tally();
    pilot.replicates = 0;
    pilot.replicate_photons.clear();
    pilot.capture_below = kCentrePilotPhotons;
    tracer.trace_photons(settings.seed, 0, kCentrePilotPhotons, pilot);
    return luminous_centre(pilot.escaped, scene.frame, luminaire_centre(scene));
  }

  // Adds the threads' tallies of this iteration, summed across the ranks,
  // to the far field and the books (guide_iteration: the guide's tally of
  // the iteration). Returns the photons guided emission dropped.
  std::uint64_t add_iteration();
  // add_iteration in one process: each thread's tally added straight into
  // the run's totals (no buffer of the iteration's counts to sum across
  // ranks); integer sums, so the same totals.
  std::uint64_t add_iteration_here();
  // Puts the escapes this iteration kept (from `from` on) in photon order.
  void order_escapes(std::size_t from);
};

Simulation::Simulation(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Simulation::~Simulation() = default;
Simulation::Simulation(Simulation&&) noexcept = default;
Simulation& Simulation::operator=(Simulation&&) noexcept = default;

Result<Simulation> Simulation::create(SceneDesc scene, const SimulationSettings& settings,
                                     const Simulation* previous) {
  if (settings.photons_per_iteration < 1 || settings.photons_per_iteration >= (std::uint64_t{1} << 32))
    return make_error("photons per iteration must lie in 1..4294967295");
  if (settings.iterations < 1) return make_error("at least one iteration is needed");
  // Power is counted in 2^-24 photon units in 64-bit integers.
  if (static_cast<double>(settings.photons_per_iteration) * settings.iterations > 0x1.0p39)
    return make_error("at most 2^39 (5.5e11) photons per run");
  if (settings.threads < 0) return make_error("the thread count must be >= 0");
  if (settings.sobol_replicates < 1 || settings.sobol_replicates > kMaxSobolReplicates)
    return make_error("the Sobol' replicates must lie in 1..32");
  if (!settings.luminance.views.empty())
    if (std::string why = validate_luminance_settings(settings.luminance); !why.empty()) return make_error(why);
  if (settings.next_event_connections < 1 || settings.next_event_connections > 1024)
    return make_error("next-event connections per vertex must lie in 1..1024");
  if (settings.importance.enabled && !settings.luminance.views.empty())
    return make_error("luminance images do not combine with guided emission");
  if (settings.importance.enabled && settings.next_event == NextEventMode::On)
    return make_error("next-event estimation does not combine with guided emission");
  if (settings.importance.enabled) {
    if (settings.importance.emission_face_size < 1 || settings.importance.emission_face_size > 1024)
      return make_error("the emission grid of guided emission needs 1..1024 texels per face edge");
    if (!(settings.importance.min_acceptance > 0.0 && settings.importance.min_acceptance <= 1.0))
      return make_error("the smallest acceptance of guided emission must lie in (0, 1]");
  }
  const auto start = std::chrono::steady_clock::now();
  TracerSettings ts;
  ts.max_bounces = settings.max_bounces;
  ts.sampler = settings.sampler;
  ts.sobol_replicates = settings.sobol_replicates;
  ts.embree.robust = settings.robust_embree;
  ts.embree.quality = settings.bvh_quality.value_or(
      bvh_quality_for(scene.unique_triangle_count(), settings.photons_per_iteration *
                                                         static_cast<std::uint64_t>(settings.iterations)));
  std::shared_ptr<const EmbreeScene> reuse;
  if (previous && previous->settings().robust_embree == settings.robust_embree &&
      previous->tracer().settings().embree.quality == ts.embree.quality && same_geometry(previous->scene(), scene))
    reuse = previous->tracer().shared_embree();
  auto tracer = Tracer::create(scene, settings.face_size, ts, std::move(reuse));
  // Over ranks: all build their tracer, or none goes on to trace (the
  // others would wait for it at the first iteration).
  if (settings.ranks && settings.ranks->distributed()) {
    const std::vector<std::uint64_t> built = settings.ranks->gather(std::uint64_t{tracer.ok()});
    for (int r = 0; r < settings.ranks->size() && tracer.ok(); ++r)
      if (built[static_cast<std::size_t>(r)] == 0)
        return make_error(settings.ranks->name_of(r) + " could not build its tracer (its own error says why)");
  }
  if (!tracer.ok()) return tracer.error();
  // Next-event estimation: a pilot with connections at every mesh decides
  // where they are kept (and, for auto, whether at all); the same photons
  // on every rank, so every rank decides the same.
  NextEventSummary next_event;
  next_event.mode = settings.importance.enabled ? NextEventMode::Off : settings.next_event;
  if (next_event.mode != NextEventMode::Off) {
    Tracer& t = tracer.value();
    NextEventSettings all;
    all.enabled = true;
    // Two connections a vertex are enough to see which slots escape.
    all.connections = std::min(settings.next_event_connections, 2);
    t.set_next_event(all);
    TracerTally pilot = t.make_tally();
    t.trace_photons(settings.seed, 0, kNextEventPilotPhotons, pilot);
    std::uint64_t escaped_units = 0;
    for (const auto& e : pilot.ledger.emitters) escaped_units += e.escaped.power_units;
    // Auto: M per mesh and side by what it buys (choose_connections); on:
    // --connections everywhere connections escape.
    const double rays_per_photon =
        static_cast<double>(pilot.ledger.rays) / static_cast<double>(kNextEventPilotPhotons);
    const ConnectionChoice paid = choose_connections(pilot.next_event, escaped_units, kNextEventPilotPhotons,
                                                     all.connections, rays_per_photon,
                                                     settings.next_event_connections);
    const NextEventChoice& choice = paid.base;
    next_event.pilot_covered_share = choice.covered_share;
    next_event.pilot_multi_share = choice.multi_share;
    next_event.enabled = next_event.mode == NextEventMode::On || paid.worthwhile;
    next_event.connections_per_vertex = next_event.enabled ? settings.next_event_connections : 0;
    NextEventSettings kept;
    kept.enabled = next_event.enabled;
    kept.connections = settings.next_event_connections;
    kept.lobes = choice.lobes;
    if (next_event.mode == NextEventMode::Auto && next_event.enabled) {
      kept.counts = paid.counts;
      next_event.connections_per_vertex = *std::max_element(paid.counts.begin(), paid.counts.end());
    }
    if (next_event.enabled) next_event.lobes = choice.lobes;
    t.set_next_event(kept);
  }
  const int threads =
      settings.threads > 0 ? settings.threads : tbb::this_task_arena::max_concurrency();
  auto impl = std::make_unique<Impl>(std::move(scene), settings, std::move(tracer.value()), threads);
  impl->next_event = next_event;
  impl->stats.threads = threads;
  impl->stats.tracer_setup = impl->tracer.setup_times();
  impl->stats.ranks = settings.ranks ? settings.ranks->size() : 1;
  impl->stats.setup_s = seconds_since(start);
  return Simulation(std::move(impl));
}

void Simulation::run_iteration() { run_iteration(impl_->settings.photons_per_iteration); }

void Simulation::run_iteration(std::uint64_t n) {
  Impl& s = *impl_;
  GONIO_CHECK(n >= 1 && n < (std::uint64_t{1} << 32));
  GONIO_CHECK(static_cast<double>(s.stats.photons) + static_cast<double>(n) <= 0x1.0p39);
  const std::uint64_t first = s.stats.photons;
  const std::uint64_t chunks = (n + kChunkPhotons - 1) / kChunkPhotons;
  const IndexRange mine = s.ranks ? rank_share(chunks, s.ranks->rank(), s.ranks->size())
                                  : IndexRange{0, chunks};
  const auto start = std::chrono::steady_clock::now();
  s.arena.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<std::uint64_t>(mine.begin, mine.end, 1),
        [&](const tbb::blocked_range<std::uint64_t>& range) {
          TracerTally& tally = s.tallies.local();
          GuideTally* guide_tally = s.guide ? &s.guide_tallies.local() : nullptr;
          for (std::uint64_t c = range.begin(); c != range.end(); ++c) {
            const std::uint64_t begin = c * kChunkPhotons;
            const std::uint64_t count = std::min(kChunkPhotons, n - begin);
            if (guide_tally)
              s.tracer.trace_photons_guided(s.settings.seed, first + begin, count, *s.guide, tally,
                                            *guide_tally);
            else
              s.tracer.trace_photons(s.settings.seed, first + begin, count, tally);
          }
        },
        tbb::simple_partitioner());
  });
  s.stats.rank_photons += std::min(n, mine.end * kChunkPhotons) - std::min(n, mine.begin * kChunkPhotons);
  s.stats.rank_trace_s += seconds_since(start);
  const std::uint64_t dropped = s.add_iteration();
  s.stats.photons += n;
  s.stats.photons_traced += n - dropped;
  s.stats.rays = s.books.rays;
  s.stats.volume_events = s.books.volume_events;
  ++s.stats.iterations_done;
  // The guide learns from this iteration for the next: part of the cost of
  // guided emission, so inside the timed span.
  if (s.guide) s.guide->update(s.guide_iteration, far_field());
  s.stats.trace_s += seconds_since(start);
}

std::uint64_t Simulation::Impl::add_iteration_here() {
  const std::size_t texels = texel_photons.size();
  books_iteration.clear();
  NearFieldTally near_iteration;
  if (near_planes) near_iteration.reset(*near_planes);
  const std::size_t escapes_before = escaped_rays.size();
  const std::uint64_t wrap = 65536u;
  // The per-texel arrays, in blocks of texels over the run's threads (each
  // block adds every tally's counts in turn: integer sums, any order).
  const auto add_texels = [&](std::size_t lo, std::size_t hi) {
    for (const TracerTally& t : tallies) {
      for (std::size_t i = lo; i < hi; ++i) {
        const std::uint64_t c = t.texel_photons[i];
        texel_photons[i] += c;
        texel_units[i] += c * kPowerUnits;
      }
      if (!texel_x.empty())
        for (std::size_t i = lo; i < hi; ++i) {
          texel_x[i] += t.texel_xz[2 * i];
          texel_z[i] += t.texel_xz[2 * i + 1];
        }
      if (!replicate_photons.empty() && !t.replicate_photons.empty()) {
        const std::size_t k = t.replicate_photons.size() / texels;
        for (std::size_t i = lo * k; i < hi * k; ++i) replicate_photons[i] += t.replicate_photons[i];
      }
      if (!nee_units.empty()) {
        const NextEventTally& n = t.next_event;
        for (std::size_t i = lo; i < hi && i < n.texel_units.size(); ++i) {
          nee_units[i] += n.texel_units[i];
          texel_units[i] += n.texel_units[i];
        }
        const std::size_t k = n.replicate_units.size() / texels;
        for (std::size_t i = lo * k; i < hi * k; ++i) nee_replicate_units[i] += n.replicate_units[i];
      }
    }
  };
  constexpr std::size_t kBlock = 8192;
  if (texels <= kBlock) {
    add_texels(0, texels);
  } else {
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, texels, kBlock),
                        [&](const tbb::blocked_range<std::size_t>& r) { add_texels(r.begin(), r.end()); },
                        tbb::simple_partitioner());
    });
  }
  for (TracerTally& t : tallies) {
    if (near_planes) near_iteration.add(t.near_field);
    for (std::uint32_t texel : t.texel_wraps) {
      texel_photons[texel] += wrap;
      texel_units[texel] += wrap * kPowerUnits;
    }
    if (!replicate_photons.empty())
      for (std::uint32_t slot : t.replicate_wraps) replicate_photons[slot] += wrap;
    if (!nee_units.empty()) {
      const NextEventTally& n = t.next_event;
      next_event.vertices += n.vertices;
      next_event.connections += n.connections;
      next_event.escaped += n.escaped;
      nee_booked_units += n.booked_units;
      nee_covered_units += n.covered_units;
    }
    if (image_sum.active()) {
      const auto add_sets = [](std::vector<std::vector<std::uint64_t>>& to,
                               const std::vector<std::vector<std::uint64_t>>& from) {
        for (std::size_t k = 0; k < to.size() && k < from.size(); ++k)
          for (std::size_t i = 0; i < to[k].size() && i < from[k].size(); ++i) to[k][i] += from[k][i];
      };
      add_sets(image_sum.units, t.images.units);
      add_sets(image_sum.x_units, t.images.x_units);
      add_sets(image_sum.z_units, t.images.z_units);
    }
    books_iteration.add(t.ledger);
    t.clear();
    escaped_rays.insert(escaped_rays.end(), t.escaped.begin(), t.escaped.end());
    t.escaped.clear();
  }
  order_escapes(escapes_before);
  if (guide) {
    guide_iteration.clear();
    for (GuideTally& t : guide_tallies) {
      guide_iteration.add(t);
      t.clear();
    }
  }
  if (near_planes) near_sum.add(near_iteration);
  books.add(books_iteration);
  if (!guide) return 0;
  for (std::size_t i = 0; i < texels; ++i) texel_units[i] += guide_iteration.extra_units[i];
  return guide_iteration.dropped;
}

void Simulation::Impl::order_escapes(std::size_t from) {
  const auto by_photon = [](const EscapedRay& a, const EscapedRay& b) { return a.photon < b.photon; };
  const auto begin = escaped_rays.begin() + static_cast<std::ptrdiff_t>(from);
  if (std::is_sorted(begin, escaped_rays.end(), by_photon)) return;
  // Each thread appended its chunks in the order it traced them, a chunk's
  // photons ascending, and chunks hold disjoint ranges of photons: the
  // runs that ascend within one chunk (kChunkPhotons from the iteration's
  // first photon), sorted by their first photon and put one after another,
  // are in photon order, without sorting every escape (issue 40).
  const std::uint64_t first = stats.photons;
  const auto chunk_of = [&](const EscapedRay& r) { return (r.photon - first) / kChunkPhotons; };
  struct Run {
    std::uint64_t photon;
    std::size_t begin, end;
  };
  std::vector<Run> runs;
  for (std::size_t i = from; i < escaped_rays.size(); ++i) {
    const EscapedRay& r = escaped_rays[i];
    if (runs.empty() || r.photon <= escaped_rays[i - 1].photon || chunk_of(r) != chunk_of(escaped_rays[i - 1]))
      runs.push_back({r.photon, i, i + 1});
    else
      runs.back().end = i + 1;
  }
  std::sort(runs.begin(), runs.end(), [](const Run& a, const Run& b) { return a.photon < b.photon; });
  std::vector<EscapedRay> ordered;
  ordered.reserve(escaped_rays.size() - from);
  for (const Run& run : runs)
    ordered.insert(ordered.end(), escaped_rays.begin() + static_cast<std::ptrdiff_t>(run.begin),
                   escaped_rays.begin() + static_cast<std::ptrdiff_t>(run.end));
  std::copy(ordered.begin(), ordered.end(), begin);
  // Runs that overlap (not expected): every escape sorted, as before.
  if (!std::is_sorted(begin, escaped_rays.end(), by_photon)) std::sort(begin, escaped_rays.end(), by_photon);
}

std::uint64_t Simulation::Impl::add_iteration() {
  if (!(ranks && ranks->distributed())) return add_iteration_here();
  // This iteration's counts, one word each: per texel the escaped photons,
  // then the books, then the guide's tally. Integer sums: the order of
  // threads and of ranks does not matter.
  const std::size_t texels = texel_photons.size();
  // Spectral: X and Z per texel follow the photon counts in the same vector.
  const std::size_t colour_words = texel_x.empty() ? texels : 3 * texels;
  // Sobol' replicates' counts follow, then next-event units per texel and
  // per texel and replicate, then its five counts.
  const std::size_t nee_words = nee_units.empty() ? 0 : nee_units.size() + nee_replicate_units.size() + 5;
  const std::size_t nee_base = colour_words + replicate_photons.size();
  // Luminance images' units (and X, Z) last.
  const std::size_t image_base = nee_base + nee_words;
  std::size_t image_words = 0;
  for (const auto* set : {&image_sum.units, &image_sum.x_units, &image_sum.z_units})
    for (const auto& v : *set) image_words += v.size();
  const std::size_t words = image_base + image_words;
  iteration.assign(words, 0);
  books_iteration.clear();
  NearFieldTally near_iteration;
  if (near_planes) near_iteration.reset(*near_planes);
  for (TracerTally& t : tallies) {
    if (near_planes) near_iteration.add(t.near_field);
    for (std::size_t i = 0; i < texels; ++i) iteration[i] += t.texel_photons[i];
    if (colour_words > texels)
      for (std::size_t i = 0; i < texels; ++i) {
        iteration[texels + i] += t.texel_xz[2 * i];
        iteration[2 * texels + i] += t.texel_xz[2 * i + 1];
      }
    for (std::uint32_t texel : t.texel_wraps) iteration[texel] += 65536u;
    if (!replicate_photons.empty()) {
      std::uint64_t* rep = iteration.data() + colour_words;
      for (std::size_t i = 0; i < t.replicate_photons.size(); ++i) rep[i] += t.replicate_photons[i];
      for (std::uint32_t slot : t.replicate_wraps) rep[slot] += 65536u;
    }
    if (nee_words > 0) {
      const NextEventTally& n = t.next_event;
      std::uint64_t* w = iteration.data() + nee_base;
      for (std::size_t i = 0; i < n.texel_units.size(); ++i) w[i] += n.texel_units[i];
      w += n.texel_units.size();
      for (std::size_t i = 0; i < n.replicate_units.size(); ++i) w[i] += n.replicate_units[i];
      w += n.replicate_units.size();
      w[0] += n.vertices;
      w[1] += n.connections;
      w[2] += n.escaped;
      w[3] += n.booked_units;
      w[4] += n.covered_units;
    }
    if (image_words > 0) {
      std::uint64_t* w = iteration.data() + image_base;
      for (const auto* set : {&t.images.units, &t.images.x_units, &t.images.z_units})
        for (const auto& v : *set) {
          for (std::size_t i = 0; i < v.size(); ++i) w[i] += v[i];
          w += v.size();
        }
    }
    books_iteration.add(t.ledger);
    t.clear();
    escaped_rays.insert(escaped_rays.end(), t.escaped.begin(), t.escaped.end());
    t.escaped.clear();
  }
  std::sort(escaped_rays.begin(), escaped_rays.end(),
            [](const EscapedRay& a, const EscapedRay& b) { return a.photon < b.photon; });
  if (guide) {
    guide_iteration.clear();
    for (GuideTally& t : guide_tallies) {
      guide_iteration.add(t);
      t.clear();
    }
  }
  if (ranks && ranks->distributed()) {
    each_count(books_iteration, [&](std::uint64_t& v) { iteration.push_back(v); });
    if (guide) each_count(guide_iteration, [&](std::uint64_t& v) { iteration.push_back(v); });
    for (auto* values : {&near_iteration.near_units, &near_iteration.far_units, &near_iteration.moved,
                         &near_iteration.cell_near_units, &near_iteration.cell_far_units, &near_iteration.cell_moved})
      iteration.insert(iteration.end(), values->begin(), values->end());
    auto t = std::chrono::steady_clock::now();
    ranks->barrier();
    stats.wait_s += seconds_since(t);
    t = std::chrono::steady_clock::now();
    ranks->sum(iteration);
    const double reduce_s = seconds_since(t);
    stats.reduce_s += reduce_s;
    if (stats.reduce_fastest_s == 0.0 || reduce_s < stats.reduce_fastest_s) stats.reduce_fastest_s = reduce_s;
    std::size_t k = words;
    each_count(books_iteration, [&](std::uint64_t& v) { v = iteration[k++]; });
    if (guide) each_count(guide_iteration, [&](std::uint64_t& v) { v = iteration[k++]; });
    for (auto* values : {&near_iteration.near_units, &near_iteration.far_units, &near_iteration.moved,
                         &near_iteration.cell_near_units, &near_iteration.cell_far_units, &near_iteration.cell_moved})
      for (std::uint64_t& v : *values) v = iteration[k++];
  }
  if (near_planes) near_sum.add(near_iteration);
  for (std::size_t i = 0; i < texels; ++i) {
    texel_photons[i] += iteration[i];
    texel_units[i] += iteration[i] * kPowerUnits;
  }
  if (colour_words > texels)
    for (std::size_t i = 0; i < texels; ++i) {
      texel_x[i] += iteration[texels + i];
      texel_z[i] += iteration[2 * texels + i];
    }
  for (std::size_t i = 0; i < replicate_photons.size(); ++i) replicate_photons[i] += iteration[colour_words + i];
  if (nee_words > 0) {
    const std::uint64_t* w = iteration.data() + nee_base;
    for (std::size_t i = 0; i < texels; ++i) {
      nee_units[i] += w[i];
      texel_units[i] += w[i];
    }
    w += texels;
    for (std::size_t i = 0; i < nee_replicate_units.size(); ++i) nee_replicate_units[i] += w[i];
    w += nee_replicate_units.size();
    next_event.vertices += w[0];
    next_event.connections += w[1];
    next_event.escaped += w[2];
    nee_booked_units += w[3];
    nee_covered_units += w[4];
  }
  if (image_words > 0) {
    const std::uint64_t* w = iteration.data() + image_base;
    for (auto* set : {&image_sum.units, &image_sum.x_units, &image_sum.z_units})
      for (auto& v : *set) {
        for (std::size_t i = 0; i < v.size(); ++i) v[i] += w[i];
        w += v.size();
      }
  }
  books.add(books_iteration);
  if (!guide) return 0;
  for (std::size_t i = 0; i < texels; ++i) texel_units[i] += guide_iteration.extra_units[i];
  return guide_iteration.dropped;
}

const EmissionGuide* Simulation::emission_guide() const { return impl_->guide.get(); }

NextEventSummary Simulation::next_event() const {
  const Impl& s = *impl_;
  NextEventSummary out = s.next_event;
  const double per_unit = s.stats.photons > 0 ? total_flux_lm() / static_cast<double>(s.stats.photons) /
                                                    static_cast<double>(kPowerUnits)
                                              : 0.0;
  out.booked_lm = static_cast<double>(s.nee_booked_units) * per_unit;
  out.covered_lm = static_cast<double>(s.nee_covered_units) * per_unit;
  return out;
}

const SimulationSettings& Simulation::settings() const { return impl_->settings; }
const SceneDesc& Simulation::scene() const { return impl_->scene; }
const Tracer& Simulation::tracer() const { return impl_->tracer; }
SimulationStats Simulation::stats() const { return impl_->stats; }
double Simulation::total_flux_lm() const { return impl_->tracer.emission().total_flux_lm(); }

const std::vector<EscapedRay>& Simulation::escaped_rays() const { return impl_->escaped_rays; }

FarField Simulation::far_field() const {
  const Impl& s = *impl_;
  const std::size_t n = s.texel_units.size();
  std::vector<double> flux(n, 0.0);
  if (s.guide) {
    // Photons started with unequal power: share the flux by power emitted.
    std::uint64_t emitted_units = 0;
    for (const auto& e : s.books.emitters) emitted_units += e.emitted.power_units;
    if (emitted_units > 0) {
      const double per_unit = total_flux_lm() / static_cast<double>(emitted_units);
      for (std::size_t i = 0; i < n; ++i) flux[i] = static_cast<double>(s.texel_units[i]) * per_unit;
    }
  } else if (s.stats.photons > 0) {
    const double per_unit = total_flux_lm() / static_cast<double>(s.stats.photons) /
                            static_cast<double>(kPowerUnits);
    for (std::size_t i = 0; i < n; ++i) flux[i] = static_cast<double>(s.texel_units[i]) * per_unit;
  }
  return FarField(s.tracer.grid().face_size(), std::move(flux), s.texel_photons);
}

int Simulation::sobol_replicates() const { return impl_->replicates; }

FarField Simulation::replicate_far_field(int replicate) const {
  const Impl& s = *impl_;
  GONIO_CHECK(replicate >= 0 && replicate < s.replicates);
  const std::size_t n = s.texel_photons.size();
  const auto k = static_cast<std::uint64_t>(s.replicates);
  const auto r = static_cast<std::uint64_t>(replicate);
  // Photons i < N with i mod K = r.
  const std::uint64_t photons = s.stats.photons / k + (r < s.stats.photons % k ? 1 : 0);
  std::vector<double> flux(n, 0.0);
  std::vector<std::uint64_t> counts(n, 0);
  const double per_photon = photons > 0 ? total_flux_lm() / static_cast<double>(photons) : 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    counts[i] = s.replicate_photons[i * k + r];
    flux[i] = static_cast<double>(counts[i]) * per_photon;
    // Next-event connections of the replicate's photons.
    if (!s.nee_replicate_units.empty())
      flux[i] += static_cast<double>(s.nee_replicate_units[i * k + r]) * per_photon / static_cast<double>(kPowerUnits);
  }
  return FarField(s.tracer.grid().face_size(), std::move(flux), std::move(counts));
}

ColourFarField Simulation::colour_far_field() const {
  const Impl& s = *impl_;
  ColourFarField c;
  if (s.texel_x.empty()) return c;
  const std::size_t n = s.texel_x.size();
  c.x_lm.assign(n, 0.0);
  c.z_lm.assign(n, 0.0);
  if (s.stats.photons == 0) return c;
  double per_unit = total_flux_lm() / static_cast<double>(s.stats.photons) / static_cast<double>(kColourUnits);
  if (s.guide) {
    // Photons started with unequal power (X and Z scaled by it, like Y):
    // share the flux by power emitted, as far_field() does.
    std::uint64_t emitted_units = 0;
    for (const auto& e : s.books.emitters) emitted_units += e.emitted.power_units;
    per_unit = emitted_units > 0 ? total_flux_lm() * static_cast<double>(kPowerUnits) /
                                       static_cast<double>(emitted_units) / static_cast<double>(kColourUnits)
                                 : 0.0;
  }
  for (std::size_t i = 0; i < n; ++i) {
    c.x_lm[i] = static_cast<double>(s.texel_x[i]) * per_unit;
    c.z_lm[i] = static_cast<double>(s.texel_z[i]) * per_unit;
  }
  return c;
}

const NearFieldPlanes* Simulation::near_field_planes() const { return impl_->near_planes.get(); }

std::vector<LuminanceImage> Simulation::luminance_images() const {
  const Impl& s = *impl_;
  if (!s.camera) return {};
  double per_unit = 0.0;
  if (s.stats.photons > 0) per_unit = total_flux_lm() / static_cast<double>(s.stats.photons) / static_cast<double>(kPowerUnits);
  if (s.guide) {
    std::uint64_t emitted_units = 0;
    for (const auto& e : s.books.emitters) emitted_units += e.emitted.power_units;
    per_unit = emitted_units > 0 ? total_flux_lm() / static_cast<double>(emitted_units) : 0.0;
  }
  const double per_colour_unit = per_unit * static_cast<double>(kPowerUnits) / static_cast<double>(kColourUnits);
  return sim::luminance_images(*s.camera, s.image_sum, per_unit, per_colour_unit);
}

std::vector<NearFieldPlane> Simulation::near_field() const {
  const Impl& s = *impl_;
  if (!s.near_planes) return {};
  double per_unit = 0.0;
  if (s.guide) {
    std::uint64_t emitted_units = 0;
    for (const auto& e : s.books.emitters) emitted_units += e.emitted.power_units;
    if (emitted_units > 0) per_unit = total_flux_lm() / static_cast<double>(emitted_units);
  } else if (s.stats.photons > 0) {
    per_unit = total_flux_lm() / static_cast<double>(s.stats.photons) / static_cast<double>(kPowerUnits);
  }
  return sim::near_field_planes(*s.near_planes, s.near_sum, per_unit, static_cast<double>(s.stats.photons));
}

Ledger Simulation::ledger() const {
  const WavelengthSampler* w = impl_->tracer.wavelengths();
  return make_ledger(impl_->books, impl_->scene, total_flux_lm(), w ? &w->radiant_bins() : nullptr);
}

Result<Simulation> simulate(
    SceneDesc scene, const SimulationSettings& settings,
    const std::function<void(const SimulationProgress&, const Simulation&)>& on_iteration) {
  auto sim = Simulation::create(std::move(scene), settings);
  if (!sim.ok()) return sim;
  Simulation& s = sim.value();
  const std::uint64_t total = settings.photons_per_iteration * static_cast<std::uint64_t>(settings.iterations);
  for (int k = 0; k < settings.iterations; ++k) {
    s.run_iteration();
    if (on_iteration) {
      const SimulationStats st = s.stats();
      SimulationProgress p;
      p.iteration = k + 1;
      p.iterations = settings.iterations;
      p.photons_done = st.photons;
      p.photons_total = total;
      p.elapsed_s = st.trace_s;
      p.photons_per_s = st.photons_per_s();
      p.remaining_s = p.photons_per_s > 0.0
                          ? static_cast<double>(total - st.photons) / p.photons_per_s
                          : 0.0;
      on_iteration(p, s);
    }
  }
  return sim;
}

}  // namespace gonio::sim
