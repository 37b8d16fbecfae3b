// gonio tolerance as a library function (tools/run/tolerance_run.h).
#include "tools/run/tolerance_run.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <atomic>
#include <bit>
#include <set>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <thread>
#include <string>
#include <vector>

#include "design/design_file.h"
#include "design/tolerance.h"
#include "design/tolerance_spec.h"
#include "io/outputs/luminance_images.h"
#include "io/outputs/plot.h"
#include "io/photometric/photometric_file.h"
#include "io/support/content_hash.h"
#include "io/support/file_io.h"
#include "io/support/text.h"
#include "photometry/format.h"
#include "sim/detectors/colour_over_angle.h"
#include "sim/distributed.h"
#include "tools/run/json_figures.h"
#include "tools/run/resampler_cache.h"
#include "tools/run/simulation_outputs.h"

namespace gonio::app {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using design::FigureValues;
using design::kFigureCount;

// One trace of the model with one value per tolerance.
struct Trace {
  photometry::Distribution distribution;
  FigureValues figures{};
  double seconds = 0.0;
  bool from_journal = false;  // read back from the journal (no distribution)
};

// The journal, DIR/journal.jsonl: its first line the run's settings and
// tolerances, then one line per finished trace, {key, figures, seconds}, the
// key the seed and each tolerance's value as C99 hex floats. A rerun with
// --resume reads every complete line back and traces only what is missing;
// a line cut short by an interruption is dropped. The traces are
// deterministic (common random numbers), so a figure read back is the one a
// trace would give, bit for bit.
class Journal {
 public:
  ~Journal() {
    if (file_) std::fclose(file_);
  }
  // Opens `path` for a run described by `header`; with `resume` the lines of
  // a journal with the same header are kept (how many: `reused`), a journal
  // of another run is an error.
  Status open(const std::string& path, const json& header, bool resume, std::size_t* reused) {
    std::string kept = header.dump() + "\n";
    *reused = 0;
    if (resume && fs::exists(path)) {
      Result<std::string> text = io::read_file(path, std::size_t{1} << 30);
      if (!text.ok()) return text.error();
      std::size_t start = 0, line = 0;
      while (start < text->size()) {
        const std::size_t end = text->find('\n', start);
        if (end == std::string::npos) break;  // cut short: dropped
        const std::string l = text->substr(start, end - start);
        start = end + 1;
        ++line;
        const json j = json::parse(l, nullptr, false);
        if (line == 1) {
          if (j.is_discarded() || j != header)
            return make_error(path, "written by another run (other settings, model or tolerances): run without "
                                    "--resume to start again");
          continue;
        }
        // A line of another shape (a key that is not a string, figures that
        // are not an object, seconds that are not a number) is dropped too.
        if (j.is_discarded() || !j.is_object() || !j.contains("key") || !j["key"].is_string() ||
            !j.contains("figures") || !j["figures"].is_object() || (j.contains("seconds") && !j["seconds"].is_number()))
          continue;
        FigureValues f{};
        for (std::size_t i = 0; i < kFigureCount; ++i) {
          const json& v = j["figures"].value(design::figure_info()[i].key, json());
          f[i] = v.is_number() ? v.get<double>() : photometry::kNaN;
        }
        done_[j["key"].get<std::string>()] = {f, j.value("seconds", 0.0)};
        kept += l + "\n";
        ++*reused;
      }
    }
    if (Status s = io::write_file_atomic(path, kept); !s.ok()) return s;
    file_ = std::fopen(path.c_str(), "ab");
    if (!file_) return make_error(path, "cannot be opened to append to it");
    return Ok{};
  }
  std::optional<std::pair<FigureValues, double>> find(const std::string& key) const {
    const std::lock_guard<std::mutex> lock(mutex_);
    const auto it = done_.find(key);
    if (it == done_.end()) return std::nullopt;
    return it->second;
  }
  // Whether `key` was traced by this run (under MPI: by any rank), not read back.
  bool fresh(const std::string& key) const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return fresh_.count(key) > 0;
  }
  void add(const std::string& key, const FigureValues& f, double seconds) {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (!file_ || done_.count(key)) return;
    done_[key] = {f, seconds};
    fresh_.insert(key);
    json figures = json::object();
    for (std::size_t i = 0; i < kFigureCount; ++i) figures[design::figure_info()[i].key] = json_number(f[i]);
    const std::string line = json{{"key", key}, {"figures", figures}, {"seconds", seconds}}.dump() + "\n";
    std::fputs(line.c_str(), file_);
    std::fflush(file_);
  }

 private:
  mutable std::mutex mutex_;
  std::map<std::string, std::pair<FigureValues, double>> done_;
  std::set<std::string> fresh_;
  std::FILE* file_ = nullptr;
};

std::string trace_key(const std::vector<double>& values, std::uint64_t seed) {
  std::string key = std::to_string(seed);
  char buf[64];
  for (double v : values) {
    std::snprintf(buf, sizeof buf, ",%a", v);
    key += buf;
  }
  return key;
}

// Runs that ask for luminance images (--luminance-image, as gonio simulate):
// CIE 232:2019's largest ΔUGR over the views, with the opening the trace's
// IES and LDT carry as A_p — the figure gonio simulate's report.json gives
// as cie232.delta_ugr — and the 4H × 8H UGR corrected by it.
void cie232_figures(const sim::Simulation& simulation, const OutputRequest& request, FigureValues& f) {
  if (simulation.settings().luminance.views.empty() || !request.opening) return;
  f[design::kDugr] = io::largest_delta_ugr(simulation.luminance_images(), request.opening->opening).delta_ugr;
  f[design::kUgrCie232] = f[design::kUgr] + f[design::kDugr];
}

class Tracer {
 public:
  Tracer(const SimulatePlan& plan, const design::ToleranceSpec& spec, const MessageSink& on_message,
         std::shared_ptr<const design::Design> design)
      : plan_(plan), spec_(spec), on_message_(on_message), design_(std::move(design)) {}
  // Why the last trace failed (the sequential traces; the parallel ones say
  // it through `why`).
  std::string error() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return error_;
  }
  void set_journal(Journal* journal) { journal_ = journal; }
  // design::largest_scale of tolerance i on the model as loaded (after a trace).
  double largest_scale(std::size_t i) const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return i < scales_.size() ? scales_[i] : std::numeric_limits<double>::infinity();
  }

  // The distribution traced with `values` and `seed`; nothing after the
  // error was printed. The model's warnings are told at the first trace
  // only (every trace loads the model again). With a journal, a trace it
  // holds is not traced again unless `need_distribution`: its figures and
  // seconds come back without a distribution. Safe to call from several
  // threads at once.
  std::optional<Trace> trace(const std::vector<double>& values, std::uint64_t seed,
                             const photometry::Distribution* nominal, bool need_distribution = false,
                             std::string* why = nullptr) const {
    const std::string key = trace_key(values, seed);
    if (journal_ && !need_distribution)
      if (std::optional<std::pair<FigureValues, double>> done = journal_->find(key)) {
        Trace t;
        t.figures = done->first;
        t.seconds = done->second;
        t.from_journal = !journal_->fresh(key);
        return t;
      }
    std::string error;
    std::optional<Trace> t = trace_now(values, seed, nominal, error);
    if (!t) {
      if (why) *why = error;
      const std::lock_guard<std::mutex> lock(mutex_);
      error_ = error;
      return std::nullopt;
    }
    if (journal_) journal_->add(key, t->figures, t->seconds);
    return t;
  }

 private:
  std::optional<Trace> trace_now(const std::vector<double>& values, std::uint64_t seed,
                                 const photometry::Distribution* nominal, std::string& err) const {
    const auto start = std::chrono::steady_clock::now();
    SimulatePlan plan = plan_;
    plan.progressive.simulation.seed = seed;
    // Tolerances on a design's variables: the design built again with them
    // (held in memory; none changed: the model as the nominal reads it).
    if (design_ && design::changes_variables(spec_, values))
      plan.model_input.design = std::make_shared<const design::Design>(design::design_with(*design_, spec_, values));
    SimulateHooks hooks;
    const bool first = !told_.exchange(true);
    hooks.on_message = [this, first](Severity severity, const std::string& text) {
      if (!(first || severity >= Severity::Error)) return;
      const std::lock_guard<std::mutex> lock(tell_mutex_);
      tell(on_message_, severity, text);
    };
    err.clear();
    hooks.on_failed = [&err](const Error& e) { err = to_string(e); };
    hooks.adjust_scene = [&](sim::SceneDesc& scene) -> Status {
      if (Status s = design::check_tolerances(spec_, scene); !s.ok()) return s;
      {
        const std::lock_guard<std::mutex> lock(mutex_);
        if (scales_.empty())
          for (const design::Tolerance& t : spec_.tolerances) scales_.push_back(design::largest_scale(t, scene));
      }
      design::apply_tolerances(spec_, values, scene);
      return Ok{};
    };
    std::optional<SimulateResult> run = simulate(plan, hooks);
    if (!run) {
      if (err.empty()) err = "the trace failed";
      return std::nullopt;
    }
    const sim::Simulation& simulation = run->run.simulation;
    const OutputRequest request =
        table_request(simulation, plan.model, plan.grid, plan.symmetry, plan.model_input.cache_dir);
    Result<SimulatedTable> table =
        simulated_table(simulation.far_field(), simulation.scene(), simulation.ledger(), request);
    if (!table.ok()) {
      err = to_string(table.error());
      return std::nullopt;
    }
    Trace t;
    t.distribution = std::move(table->distribution);
    Result<FigureValues> f = design::figures_of(t.distribution, nominal ? *nominal : t.distribution,
                                                plan.grid.c_step_deg, plan.grid.gamma_step_deg);
    if (!f.ok()) {
      err = to_string(f.error());
      return std::nullopt;
    }
    t.figures = *f;
    // Spectral runs: the luminaire's CCT and its Δu′v′ max over angle, the
    // colour code of gonio simulate's report.json (sim/detectors/colour_over_angle.h).
    if (simulation.tracer().spectral()) {
      const sim::ColourFarField colour = simulation.colour_far_field();
      const sim::Resampler resampler = cached_resampler(plan.progressive.simulation.face_size, simulation.scene().frame,
                                                        plan.grid, plan.model_input.cache_dir);
      const sim::ColourOverAngle c = sim::colour_over_angle(resampler, simulation.far_field(), colour);
      t.figures[design::kCct] = c.cct.cct_k;
      t.figures[design::kDuvMax] = c.delta_uv_max;
    }
    cie232_figures(simulation, request, t.figures);
    t.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return t;
  }

 private:
  const SimulatePlan& plan_;
  const design::ToleranceSpec& spec_;
  const MessageSink& on_message_;
  std::shared_ptr<const design::Design> design_;
  Journal* journal_ = nullptr;
  mutable std::atomic<bool> told_{false};
  mutable std::mutex mutex_, tell_mutex_;
  mutable std::string error_;
  mutable std::vector<double> scales_;
};

// An emitter's bins for report.json: [{bin, name, probability, factor}]
// (factor for flux bins); null for other laws (their entries get no "bins").
json bins_json(const design::Tolerance& t) {
  if (t.law.kind != design::ToleranceLaw::Kind::Bins) return nullptr;
  json bins = json::array();
  for (std::size_t k = 0; k < t.law.probabilities.size(); ++k) {
    json b = {{"bin", k + 1}, {"name", t.bin_names[k]}, {"probability", t.law.probabilities[k]}};
    if (k < t.bin_factors.size()) b["factor"] = t.bin_factors[k];
    bins.push_back(b);
  }
  return bins;
}

json figures_json(const FigureValues& f) {
  json j = json::object();
  for (std::size_t i = 0; i < kFigureCount; ++i) j[design::figure_info()[i].key] = json_number(f[i]);
  return j;
}

json values_json(const design::ToleranceSpec& spec, const std::vector<double>& values) {
  json j = json::object();
  for (std::size_t i = 0; i < values.size(); ++i) j[spec.tolerances[i].label()] = values[i];
  return j;
}

std::string padded(std::string s, std::size_t width) {
  // Pads by bytes; labels are mostly ASCII.
  if (s.size() < width) s.append(width - s.size(), ' ');
  return s;
}

// STEM.ies and STEM.ldt in `dir`, listed in `files` where written. A file
// that cannot be written goes to `failures` and the run goes on (the files
// after it and report.json are still written; report.json lists them).
void write_tables(const std::string& dir, const std::string& stem, const photometry::Distribution& d, json& files,
                  std::vector<std::string>& failures) {
  for (const char* ext : {".ies", ".ldt"}) {
    const std::string name = stem + ext;
    if (Status s = io::write_photometric_file((fs::path(dir) / name).string(), d, {}, nullptr); !s.ok())
      failures.push_back(to_string(s.error()));
    else
      files.push_back(name);
  }
}

// A written trace's own report beside its tables (STEM.json): its entry of
// report.json (a trial's number, values, figures and verdicts; the nominal's
// figures) and the names of the tables it describes. A failure goes to
// `failures` (as write_tables').
void write_trace_report(const std::string& dir, const std::string& stem, json entry, json& files,
                        std::vector<std::string>& failures) {
  entry["tables"] = json::array({stem + ".ies", stem + ".ldt"});
  const std::string name = stem + ".json";
  if (Status s = io::write_file_atomic((fs::path(dir) / name).string(), entry.dump(2) + "\n"); !s.ok())
    failures.push_back(to_string(s.error()));
  else
    files.push_back(name);
}

// The Monte Carlo trials' values: a Latin hypercube over the tolerance
// space (seeded by `sampling_seed`), each law's quantile of its stratum.
std::vector<std::vector<double>> monte_carlo_values(const design::ToleranceSpec& spec, long long trials,
                                                    long long sampling_seed) {
  const std::size_t dims = spec.tolerances.size();
  const std::vector<std::vector<double>> u =
      design::latin_hypercube(static_cast<std::size_t>(trials), dims, static_cast<std::uint64_t>(sampling_seed));
  std::vector<std::vector<double>> values(u.size(), std::vector<double>(dims));
  for (std::size_t n = 0; n < u.size(); ++n)
    for (std::size_t i = 0; i < dims; ++i) values[n][i] = spec.tolerances[i].law.quantile(u[n][i]);
  return values;
}

// Under MPI, once every rank has traced the nominal (collective): whether
// every rank opened what it needs (rank 0: the journal) and traced it, and
// traced the same (its figures' bits: the same model, settings and
// tolerances). An error on every rank where not; rank 0's names the rank,
// a rank's own failure is its own error, the others' message is empty.
Status ranks_agree_on_nominal(const sim::Ranks& ranks, const std::optional<Trace>& nominal, const Status& opened,
                              const std::string& model, const std::string& why) {
  io::ContentHash figures;  // the figures' bits, with the one content hash
  if (nominal) figures.value(nominal->figures);
  const std::uint64_t hash = figures.digest();
  const std::vector<std::uint64_t> ready = ranks.gather(std::uint64_t{opened.ok() && nominal.has_value()});
  const std::vector<std::uint64_t> hashes = ranks.gather(hash);
  if (!opened.ok()) return opened.error();
  if (!nominal) return make_error(model + ": the nominal model could not be traced (" + why + "); nothing was analysed");
  for (int r = 0; r < ranks.size(); ++r) {
    if (ready[static_cast<std::size_t>(r)] != 0 && hashes[static_cast<std::size_t>(r)] == hashes[0]) continue;
    if (ranks.rank() != 0) return make_error(std::string());
    return make_error(ranks.name_of(r) + (ready[static_cast<std::size_t>(r)] == 0
                                              ? " could not get ready (its error above); nothing was analysed"
                                              : " traced another nominal than rank 0 (another model, settings or "
                                                "tolerances); nothing was analysed"));
  }
  return Ok{};
}

// Under MPI, with --spec and --inverse-steps: the traced inverse
// sensitivity's bisections (sensitivity.txt, "traced"), one per limit and
// tolerance that rank 0 will bisect, split over the ranks by rank_share of
// these pairs (a bisection's steps depend on each other: a pair stays on one
// rank). Each rank makes the decisions rank 0's loop makes, from the same
// figures, and sends its traces (the value, the figures and seconds, at most
// kMaxInverseTraces per pair) to rank 0's journal, summed as bits like
// trace_over_ranks'. Rank 0's loop then reads them back. A cache only: a
// trace it lacks (a failure, a pair cut short), rank 0 makes itself, so the
// report does not depend on it. Collective.
constexpr std::size_t kMaxInverseTraces = 2 * (8 + 50);
void inverse_over_ranks(const Tracer& tracer, const sim::Ranks& ranks, Journal* journal,
                        const design::ToleranceSpec& spec, const std::vector<design::SpecLimit>& limits,
                        const FigureValues& nominal, const FigureValues& noise,
                        const std::vector<std::array<FigureValues, 2>>& at_limits, long long steps, std::uint64_t seed,
                        const photometry::Distribution& nominal_d, const std::function<void(const std::string&)>& say) {
  const std::size_t dims = spec.tolerances.size();
  std::vector<std::pair<std::size_t, std::size_t>> pairs;  // (limit, tolerance)
  for (std::size_t l = 0; l < limits.size(); ++l)
    for (std::size_t i = 0; i < dims; ++i) {
      const std::size_t f = limits[l].figure;
      const double base = f == design::kRms ? 0.0 : nominal[f];
      const double low = at_limits[i][0][f] - base, high = at_limits[i][1][f] - base;
      if (!std::isfinite(nominal[f]) || design::below_noise(std::max(std::abs(low), std::abs(high)), noise[f]))
        continue;
      const double k = design::allowed_scale(nominal[f], low, high, limits[l]);
      if (std::isfinite(k) && k > 0.0) pairs.push_back({l, i});
    }
  constexpr std::size_t kSlot = kFigureCount + 3;  // the value, the figures, the seconds, present
  std::vector<std::uint64_t> slots(pairs.size() * kMaxInverseTraces * kSlot, 0);
  const sim::IndexRange mine = sim::rank_share(pairs.size(), ranks.rank(), ranks.size());
  for (std::size_t p = mine.begin; p < mine.end; ++p) {
    const auto [l, i] = pairs[p];
    const design::SpecLimit& limit = limits[l];
    const design::Tolerance& t = spec.tolerances[i];
    const std::size_t f = limit.figure;
    const double cap = std::min(design::kMaxInverseScale, tracer.largest_scale(i));
    std::size_t traced = 0;
    const auto holds_at = [&](double scale) -> std::optional<bool> {
      for (double limit_value : {t.law.low(), t.law.high()}) {
        const double v = scale * limit_value;
        if (v == 0.0) continue;
        std::vector<double> values(dims, 0.0);
        values[i] = v;
        const std::optional<Trace> tr = tracer.trace(values, seed, &nominal_d);
        if (!tr) return std::nullopt;
        if (traced < kMaxInverseTraces) {
          std::uint64_t* slot = &slots[(p * kMaxInverseTraces + traced++) * kSlot];
          slot[0] = std::bit_cast<std::uint64_t>(v);
          for (std::size_t k = 0; k < kFigureCount; ++k) slot[1 + k] = std::bit_cast<std::uint64_t>(tr->figures[k]);
          slot[kSlot - 2] = std::bit_cast<std::uint64_t>(tr->seconds);
          slot[kSlot - 1] = 1;
        }
        if (!limit.holds(tr->figures[f])) return false;
      }
      return true;
    };
    // As rank 0's loop: doubling from 1 while it holds, then bisection.
    double ok = 0.0, bad = std::numeric_limits<double>::infinity();
    (limit.holds(at_limits[i][0][f]) && limit.holds(at_limits[i][1][f]) ? ok : bad) = 1.0;
    if (ok == 1.0 && cap < 1.0) ok = 0.0;
    bool failed = false;
    for (double next = std::min(2.0, cap); std::isinf(bad) && ok > 0.0 && ok < cap; next = std::min(2.0 * next, cap)) {
      const std::optional<bool> h = holds_at(next);
      if (!h) {
        failed = true;
        break;
      }
      (*h ? ok : bad) = next;
      if (next >= cap) break;
    }
    for (long long step = 0; step < steps && std::isfinite(bad) && !failed; ++step) {
      const double mid = 0.5 * (ok + bad);
      const std::optional<bool> h = holds_at(mid);
      if (!h) break;
      (*h ? ok : bad) = mid;
    }
  }
  ranks.sum(slots);
  std::size_t traces = 0;
  for (std::size_t p = 0; p < pairs.size(); ++p)
    for (std::size_t n = 0; n < kMaxInverseTraces; ++n) {
      const std::uint64_t* slot = &slots[(p * kMaxInverseTraces + n) * kSlot];
      if (slot[kSlot - 1] == 0) break;
      ++traces;
      if (!journal || (p >= mine.begin && p < mine.end)) continue;  // rank 0's own: journalled as they finished
      std::vector<double> values(dims, 0.0);
      values[pairs[p].second] = std::bit_cast<double>(slot[0]);
      FigureValues figures{};
      for (std::size_t k = 0; k < kFigureCount; ++k) figures[k] = std::bit_cast<double>(slot[1 + k]);
      journal->add(trace_key(values, seed), figures, std::bit_cast<double>(slot[kSlot - 2]));
    }
  if (ranks.rank() == 0)
    say("over " + std::to_string(ranks.size()) + " MPI ranks: the inverse sensitivity's " +
        std::to_string(pairs.size()) + " bisections, " + std::to_string(traces) + " traces\n");
}

// `independent = true` parts: one tolerance per copy of the instanced mesh,
// which takes the model loaded once (every rank the same; the checks from
// the cache). Nothing to do, and no load, without them.
Status expand_copies(design::ToleranceSpec& spec, const std::string& model, const SimulatePlan& plan) {
  if (std::none_of(spec.tolerances.begin(), spec.tolerances.end(),
                   [](const design::Tolerance& t) { return t.independent; }))
    return Ok{};
  ModelLoad load = load_model(model, plan.model_input);
  if (load.error) return *load.error;
  if (!load.scene) return make_error(model, "could not be loaded to find the copies of its instanced parts");
  return design::expand_independent_copies(spec, *load.scene);
}

// One trace to make: its tolerance values and seed.
struct TraceJob {
  std::vector<double> values;
  std::uint64_t seed = 0;
};

// Under MPI (ToleranceRunOptions::ranks): the traces whose values are known
// once the nominal is traced — the noise seeds, each tolerance at its limits
// and the Monte Carlo trials — made once over the ranks. Collective. The
// jobs rank 0's journal holds (--resume) are told to every rank and skipped;
// the others, each key once, go in rounds of ranks × `parallel` jobs, each
// rank tracing its rank_share of a round on `parallel` threads. Every job's
// figures and seconds are summed across the ranks as their bits (one rank
// writes each slot, the others leave it 0: integer sums, exact), and rank 0
// adds the other ranks' traces to its journal, in job order, after each
// round: so rank 0's report reads every one of them from the journal, the
// same bits as a trace in one process, and an interrupted job loses at most
// the round under way. A failed trace ends every rank after its round: the
// rank that failed returns its own error, rank 0 one naming that rank, the
// others an empty error message (nothing to add). `figures`: every job's
// figures, on every rank (the journal's too: rank 0 sends them with the flags).
Status trace_over_ranks(const Tracer& tracer, const sim::Ranks& ranks, Journal* journal,
                        const std::vector<TraceJob>& jobs, const photometry::Distribution& nominal, std::size_t parallel,
                        const std::function<void(const std::string&)>& say, std::vector<FigureValues>& figures) {
  const bool lead = ranks.rank() == 0;
  constexpr std::size_t kSlot = kFigureCount + 2;  // the figures, the seconds, failed (held: the flag)
  std::vector<std::string> keys;
  std::vector<std::uint64_t> held(jobs.size() * kSlot, 0);
  for (std::size_t j = 0; j < jobs.size(); ++j) {
    keys.push_back(trace_key(jobs[j].values, jobs[j].seed));
    if (!lead || !journal) continue;
    if (const std::optional<std::pair<FigureValues, double>> done = journal->find(keys.back())) {
      for (std::size_t f = 0; f < kFigureCount; ++f) held[j * kSlot + f] = std::bit_cast<std::uint64_t>(done->first[f]);
      held[j * kSlot + kSlot - 1] = 1;
    }
  }
  ranks.sum(held);
  figures.assign(jobs.size(), FigureValues{});
  std::vector<std::size_t> pending;
  std::map<std::string, std::size_t> first;  // a key's first job
  for (std::size_t j = 0; j < jobs.size(); ++j) {
    if (held[j * kSlot + kSlot - 1] != 0)
      for (std::size_t f = 0; f < kFigureCount; ++f) figures[j][f] = std::bit_cast<double>(held[j * kSlot + f]);
    else if (first.emplace(keys[j], j).second)
      pending.push_back(j);
  }
  const std::size_t round = static_cast<std::size_t>(ranks.size()) * std::max<std::size_t>(1, parallel);
  if (lead)
    say("over " + std::to_string(ranks.size()) + " MPI ranks: " + std::to_string(pending.size()) + " of " +
        std::to_string(jobs.size()) + " traces to make (" + std::to_string(jobs.size() - pending.size()) +
        " from the journal)\n");
  for (std::size_t start = 0; start < pending.size(); start += round) {
    const std::size_t count = std::min(round, pending.size() - start);
    const sim::IndexRange mine = sim::rank_share(count, ranks.rank(), ranks.size());
    std::vector<std::uint64_t> slots(count * kSlot, 0);
    std::atomic<std::size_t> next{static_cast<std::size_t>(mine.begin)};
    std::mutex mutex;
    std::string own_error;
    const auto worker = [&] {
      for (;;) {
        const std::size_t k = next++;
        if (k >= mine.end) return;
        const TraceJob& job = jobs[pending[start + k]];
        std::string why;
        const std::optional<Trace> t = tracer.trace(job.values, job.seed, &nominal, false, &why);
        std::uint64_t* slot = &slots[k * kSlot];
        if (!t) {
          slot[kSlot - 1] = 1;
          const std::lock_guard<std::mutex> lock(mutex);
          if (own_error.empty()) own_error = why.empty() ? std::string("a trace failed") : why;
          continue;
        }
        for (std::size_t f = 0; f < kFigureCount; ++f) slot[f] = std::bit_cast<std::uint64_t>(t->figures[f]);
        slot[kFigureCount] = std::bit_cast<std::uint64_t>(t->seconds);
      }
    };
    std::vector<std::thread> pool;
    for (std::size_t w = 1; w < std::min<std::size_t>(std::max<std::size_t>(1, parallel), mine.size()); ++w)
      pool.emplace_back(worker);
    worker();
    for (std::thread& th : pool) th.join();
    ranks.sum(slots);
    for (std::size_t k = 0; k < count; ++k) {
      if (slots[k * kSlot + kSlot - 1] == 0) continue;
      if (!own_error.empty()) return make_error(own_error);
      int owner = 0;
      while (owner + 1 < ranks.size() && k >= sim::rank_share(count, owner + 1, ranks.size()).begin) ++owner;
      return make_error(lead ? "a trace on " + ranks.name_of(owner) + " failed (its error above); nothing more was analysed"
                             : std::string());
    }
    for (std::size_t k = 0; k < count; ++k) {
      FigureValues& f = figures[pending[start + k]];
      for (std::size_t i = 0; i < kFigureCount; ++i) f[i] = std::bit_cast<double>(slots[k * kSlot + i]);
      if (lead && journal && !(k >= mine.begin && k < mine.end))  // rank 0's own: journalled as they finished
        journal->add(keys[pending[start + k]], f, std::bit_cast<double>(slots[k * kSlot + kFigureCount]));
    }
    if (lead)
      say("over " + std::to_string(ranks.size()) + " MPI ranks: " + std::to_string(start + count) + "/" +
          std::to_string(pending.size()) + " traces done\n");
  }
  for (std::size_t j = 0; j < jobs.size(); ++j)  // a key traced once, for each of its jobs
    if (held[j * kSlot + kSlot - 1] == 0) figures[j] = figures[first.at(keys[j])];
  return Ok{};
}

}  // namespace

Result<ToleranceRunOutcome> tolerance_analysis(const ToleranceRunOptions& options, const SimulatePlan& plan,
                                               const ToleranceRunHooks& hooks, bool* usage) {
  const std::string& model = options.model;
  const std::string& tolerances_path = options.tolerances_path;
  const std::string& out_dir = options.out_dir;
  const std::string& spec_text = options.spec_text;
  const long long trials = options.trials, noise_seeds = options.noise_seeds, sampling_seed = options.sampling_seed,
                  bins = options.bins;
  const SimulateOptions& sim = options.simulate;
  struct Settings {
    long long photons, seed;
    double c_step, gamma_step;
  } const settings{sim.photons, sim.seed, sim.c_step, sim.gamma_step};
  const Settings& opt = settings;
  // Under MPI rank 0 alone writes and shows progress (trace_over_ranks).
  const sim::Ranks one_process;
  const sim::Ranks& ranks = options.ranks ? *options.ranks : one_process;
  const bool lead = ranks.rank() == 0;
  const auto say = [&](const std::string& text) {
    if (hooks.on_output && lead) hooks.on_output(text);
  };
  for (auto [value, option] : {std::pair{&model, "MODEL"}, std::pair{&out_dir, "--out DIR"}})
    if (value->empty()) {
      if (usage) *usage = true;
      return make_error(std::string(option) + " is required");
    }
  std::vector<design::SpecLimit> limits;
  if (!spec_text.empty()) {
    Result<std::vector<design::SpecLimit>> l = design::parse_spec(spec_text);
    if (!l.ok()) {
      if (usage) *usage = true;
      return l.error();
    }
    limits = std::move(l.value());
  }
  std::vector<design::PercentileChoice> percentiles;
  if (!options.percentile_text.empty()) {
    Result<std::vector<design::PercentileChoice>> c = design::parse_percentiles(options.percentile_text);
    if (!c.ok()) {
      if (usage) *usage = true;
      return c.error();
    }
    percentiles = std::move(c.value());
  }
  // The model's own [tolerances] where it is a design file, and --tolerances FILE.
  std::shared_ptr<const design::Design> base_design = plan.model_input.design;
  if (!base_design && design::is_design_path(model)) {
    Result<design::Design> d = design::read_design_file(model);
    if (!d.ok()) return make_error(to_string(d.error()));
    base_design = std::make_shared<const design::Design>(std::move(d.value()));
  }
  const io::TomlNode* own = base_design ? base_design->document.get("tolerances") : nullptr;
  if (tolerances_path.empty() && !own) {
    if (usage) *usage = true;
    return make_error(base_design ? "--tolerances FILE is required: the design has no [tolerances] table"
                                  : "--tolerances FILE is required");
  }
  Result<design::ToleranceSpec> spec = design::ToleranceSpec{};
  if (!tolerances_path.empty()) spec = design::read_tolerances(tolerances_path);
  if (!spec.ok()) return make_error(to_string(spec.error()));
  if (own) {
    if (!own->is_table()) return make_error(model + ":" + std::to_string(own->line) + ": tolerances must be a table");
    Result<design::ToleranceSpec> from_design = design::parse_tolerance_tree(*own, base_design->path, true);
    if (!from_design.ok()) return make_error(to_string(from_design.error()));
    if (spec->tolerances.empty()) spec->path = from_design->path;
    for (design::Tolerance& t : from_design->tolerances) spec->tolerances.push_back(std::move(t));
  }
  if (Status s = design::check_variables(*spec, base_design.get()); !s.ok()) return make_error(to_string(s.error()));
  if (Status s = expand_copies(*spec, model, plan); !s.ok()) return make_error(to_string(s.error()));
  // Nothing is written over an input (the model and the files it reads, the
  // tolerance file) by any file the run writes into DIR: every later trace
  // loads the model again. Under MPI the ranks agree (each may see other
  // files): any rank's finding stops every rank.
  const Status not_over_inputs = [&]() -> Status {
    std::vector<std::string> written = {"report.json", "timing.json", "journal.jsonl", "sensitivity.txt"};
    std::vector<std::string> stems = {"nominal", "best", "worst"};
    for (const design::PercentileChoice& c : percentiles) stems.push_back(c.stem());
    for (const std::string& stem : stems)
      for (const char* ext : {".ies", ".ldt", ".json"}) written.push_back(stem + ext);
    for (std::size_t f = 0; f < kFigureCount; ++f)
      written.push_back("tornado_" + std::string(design::figure_info()[f].key) + ".svg");
    std::vector<std::string> inputs = model_files(model, plan.model_input);
    if (!tolerances_path.empty()) inputs.push_back(tolerances_path);
    for (const std::string& w : written)
      for (const std::string& input : inputs)
        if (io::same_file((fs::path(out_dir) / w).string(), input))
          return make_error(input, "gonio tolerance would write " + (fs::path(out_dir) / w).string() +
                                       " over this input (the same file); give another --out");
    return Ok{};
  }();
  if (ranks.distributed()) {
    const std::vector<std::uint64_t> over = ranks.gather(std::uint64_t{not_over_inputs.ok() ? 0u : 1u});
    if (std::any_of(over.begin(), over.end(), [](std::uint64_t v) { return v != 0; }))
      return not_over_inputs.ok() ? make_error(std::string()) : not_over_inputs.error();
  } else if (!not_over_inputs.ok()) {
    return not_over_inputs.error();
  }
  if (Status s = io::make_directories(out_dir); !s.ok()) return make_error(to_string(s.error()));

  const MessageSink rank_messages = lead ? hooks.on_message : MessageSink([&hooks](Severity severity, const std::string& text) {
    if (severity >= Severity::Error) tell(hooks.on_message, severity, text);
  });
  Tracer tracer(plan, *spec, rank_messages, base_design);
  // The journal: what a rerun with --resume reads back. Its header is what
  // makes two runs' traces the same: the model, the settings of a trace and
  // the tolerances.
  json journal_header = {{"gonio_tolerance_journal", 1},
                         {"model", model},
                         {"photons", opt.photons},
                         {"seed", opt.seed},
                         {"c_step_deg", opt.c_step},
                         {"gamma_step_deg", opt.gamma_step},
                         {"max_bounces", sim.max_bounces}};
  json journal_tolerances = json::array();
  for (const design::Tolerance& t : spec->tolerances)
    journal_tolerances.push_back(t.label() + " " + t.law.text() + " " + t.unit());
  journal_header["tolerances"] = journal_tolerances;
  if (sim.luminance_images) journal_header["luminance_images"] = *sim.luminance_images;
  Journal journal;
  std::size_t reused = 0;
  Status journal_opened = Ok{};  // rank 0 owns the journal
  if (lead)
    journal_opened = journal.open((fs::path(out_dir) / "journal.jsonl").string(), journal_header, options.resume, &reused);
  if (!journal_opened.ok() && !ranks.distributed()) return journal_opened.error();
  if (lead) tracer.set_journal(&journal);
  if (options.resume) say("resume: " + std::to_string(reused) + " traces read back from the journal\n");
  const std::size_t dims = spec->tolerances.size();
  const std::uint64_t seed = static_cast<std::uint64_t>(opt.seed);
  const std::vector<double> zeros(dims, 0.0);
  json report = {{"model", model},
                 {"tolerances_file", tolerances_path.empty() ? json(nullptr) : json(tolerances_path)},
                 {"tolerances_from_design", own != nullptr},
                 {"settings",
                  {{"photons", opt.photons},
                   {"seed", opt.seed},
                   {"c_step_deg", opt.c_step},
                   {"gamma_step_deg", opt.gamma_step},
                   {"noise_seeds", noise_seeds},
                   {"trials", trials},
                   {"sampling", "latin hypercube"},
                   {"sampling_seed", sampling_seed},
                   {"inverse_steps", options.inverse_steps}}}};
  json tolerances = json::array();
  for (const design::Tolerance& t : spec->tolerances)
    tolerances.push_back({{"name", t.label()},
                          {"unit", t.unit()},
                          {"law", t.law.text()},
                          {"low", t.law.low()},
                          {"high", t.law.high()},
                          {"line", t.line}});
  for (std::size_t i = 0; i < dims; ++i)
    if (const json listed = bins_json(spec->tolerances[i]); !listed.is_null()) tolerances[i]["bins"] = listed;
  report["tolerances"] = tolerances;
  std::vector<double> seconds;

  // The nominal, and its noise.
  say("nominal: tracing " + format_number(static_cast<double>(opt.photons)) + " photons (seed " +
      std::to_string(opt.seed) + ")\n");
  std::optional<Trace> nominal =
      journal_opened.ok() ? tracer.trace(zeros, seed, nullptr, true) : std::optional<Trace>();
  if (ranks.distributed()) {
    if (Status s = ranks_agree_on_nominal(ranks, nominal, journal_opened, model, tracer.error()); !s.ok()) return s.error();
    std::vector<TraceJob> jobs;
    for (long long k = 1; k <= noise_seeds; ++k) jobs.push_back({zeros, seed + static_cast<std::uint64_t>(k)});
    std::vector<std::array<std::size_t, 2>> limit_jobs(dims, {jobs.size(), jobs.size()});  // none: the nominal
    for (std::size_t i = 0; i < dims; ++i)
      for (int side = 0; side < 2; ++side)
        if (const double v = side == 0 ? spec->tolerances[i].law.low() : spec->tolerances[i].law.high(); v != 0.0) {
          limit_jobs[i][static_cast<std::size_t>(side)] = jobs.size();
          jobs.push_back({zeros, seed});
          jobs.back().values[i] = v;
        }
    for (std::vector<double>& values : monte_carlo_values(*spec, trials, sampling_seed))
      jobs.push_back({std::move(values), seed});
    std::vector<FigureValues> done;
    if (Status s = trace_over_ranks(tracer, ranks, lead ? &journal : nullptr, jobs, nominal->distribution,
                                    static_cast<std::size_t>(options.parallel_trials), say, done);
        !s.ok())
      return s.error();
    // The traced inverse sensitivity's bisections, split by limit and tolerance.
    if (!limits.empty() && options.inverse_steps > 0) {
      const std::vector<FigureValues> noise_traces(done.begin(), done.begin() + noise_seeds);
      std::vector<std::array<FigureValues, 2>> at(dims);
      for (std::size_t i = 0; i < dims; ++i)
        for (std::size_t side = 0; side < 2; ++side)
          at[i][side] = limit_jobs[i][side] < done.size() ? done[limit_jobs[i][side]] : nominal->figures;
      inverse_over_ranks(tracer, ranks, lead ? &journal : nullptr, *spec, limits, nominal->figures,
                         design::noise_floor(nominal->figures, noise_traces), at, options.inverse_steps, seed,
                         nominal->distribution, say);
    }
    if (!lead) {  // rank 0 writes the report from the journal
      ToleranceRunOutcome out;
      out.lead = false;
      return out;
    }
  }
  if (!nominal) return make_error(model + ": the nominal model could not be traced (" + tracer.error() + "); nothing was analysed");
  seconds.push_back(nominal->seconds);
  const photometry::Distribution& nominal_d = nominal->distribution;
  json files = json::array();
  // The files that cannot be written: the analysis goes on, report.json
  // lists them (output_failures), and the run then fails (exit 1).
  std::vector<std::string> output_failures;
  write_tables(out_dir, "nominal", nominal_d, files, output_failures);
  report["nominal"] = figures_json(nominal->figures);
  write_trace_report(out_dir, "nominal", {{"trial", "nominal"}, {"figures", report["nominal"]}}, files,
                     output_failures);
  std::vector<FigureValues> independent;
  json noise_runs = json::array();
  for (long long k = 1; k <= noise_seeds; ++k) {
    say("noise floor " + std::to_string(k) + "/" + std::to_string(noise_seeds) + ": the nominal with seed " +
        std::to_string(seed + static_cast<std::uint64_t>(k)) + "\n");
    std::optional<Trace> t = tracer.trace(zeros, seed + static_cast<std::uint64_t>(k), &nominal_d);
    if (!t) return make_error("a noise trace failed (" + tracer.error() + "); nothing more was analysed");
    seconds.push_back(t->seconds);
    independent.push_back(t->figures);
    noise_runs.push_back({{"seed", seed + static_cast<std::uint64_t>(k)}, {"figures", figures_json(t->figures)}});
  }
  const FigureValues noise = design::noise_floor(nominal->figures, independent);
  report["noise"] = {{"runs", noise_runs},
                     {"floor", figures_json(noise)},
                     {"below_noise_when", "|change| < " + format_number(design::kNoiseFactor) +
                                              " × the standard deviation over the nominal and its re-traces"}};

  // Sensitivity: each tolerance alone at its limits.
  std::vector<std::array<double, 2>> limit_values(dims);
  std::vector<std::array<FigureValues, 2>> at_limits(dims);
  for (std::size_t i = 0; i < dims; ++i) {
    const design::Tolerance& t = spec->tolerances[i];
    limit_values[i] = {t.law.low(), t.law.high()};
    for (int side = 0; side < 2; ++side) {
      const double v = limit_values[i][static_cast<std::size_t>(side)];
      say("sensitivity " + std::to_string(2 * i + static_cast<std::size_t>(side) + 1) + "/" +
          std::to_string(2 * dims) + ": " + t.label() + " = " + format_number(v) + " " + t.unit() + "\n");
      if (v == 0.0) {  // the nominal itself, bit for bit
        at_limits[i][static_cast<std::size_t>(side)] = nominal->figures;
        continue;
      }
      std::vector<double> values = zeros;
      values[i] = v;
      std::optional<Trace> trace = tracer.trace(values, seed, &nominal_d);
      if (!trace) return make_error("a sensitivity trace failed (" + tracer.error() + "); nothing more was analysed");
      seconds.push_back(trace->seconds);
      at_limits[i][static_cast<std::size_t>(side)] = trace->figures;
    }
  }
  json sensitivity = json::object();
  std::string table = "Sensitivity of " + model + " (" +
                      (tolerances_path.empty() ? std::string("its [tolerances]")
                       : own                   ? tolerances_path + " and its [tolerances]"
                                               : tolerances_path) +
                      "), " +
                      format_number(static_cast<double>(opt.photons)) + " photons per trace, seed " +
                      std::to_string(opt.seed) + ".\nChange of each figure with each tolerance alone at its low and high limit;\n" +
                      "below noise: |change| < " + format_number(design::kNoiseFactor) +
                      " σ of the nominal traced with independent seeds (not ranked).\n";
  std::vector<std::string> plot_failures;
  for (std::size_t f = 0; f < kFigureCount; ++f) {
    const design::FigureInfo& info = design::figure_info()[f];
    if (!std::isfinite(nominal->figures[f])) {
      // CCT and Δu′v′ in a grey run, UGR without a luminous area, …: no table.
      table += "\n" + std::string(info.text) + " [" + info.unit + "]: not defined for this model\n";
      sensitivity[info.key] = {{"unit", info.unit}, {"nominal", nullptr}, {"noise", nullptr}, {"rows", json::array()}};
      continue;
    }
    std::vector<design::SensitivityRow> ranked, below;
    for (std::size_t i = 0; i < dims; ++i) {
      const design::Tolerance& t = spec->tolerances[i];
      design::SensitivityRow r;
      r.label = t.label() + " " + t.law.text() + " " + t.unit();
      r.low = limit_values[i][0];
      r.high = limit_values[i][1];
      // The RMS difference is from the nominal already.
      const double base = f == design::kRms ? 0.0 : nominal->figures[f];
      r.change_low = at_limits[i][0][f] - base;
      r.change_high = at_limits[i][1][f] - base;
      const bool quiet = design::below_noise(r.largest(), noise[f]);
      (quiet ? below : ranked).push_back(r);
    }
    std::stable_sort(ranked.begin(), ranked.end(),
                     [](const design::SensitivityRow& a, const design::SensitivityRow& b) { return a.largest() > b.largest(); });
    table += "\n" + std::string(info.text) + " [" + info.unit + "]: nominal " + format_number(nominal->figures[f]) +
             ", noise σ " + format_number(noise[f]) + "\n";
    json rows = json::array();
    for (const auto* group : {&ranked, &below})
      for (const design::SensitivityRow& r : *group) {
        const bool quiet = group == &below;
        table += "  " + padded(r.label, 44) + "  " + padded(format_number(r.change_low, 4), 12) +
                 padded(format_number(r.change_high, 4), 12) + (quiet ? "below noise" : "") + "\n";
        rows.push_back({{"tolerance", r.label},
                        {"low", r.low},
                        {"high", r.high},
                        {"change_low", json_number(r.change_low)},
                        {"change_high", json_number(r.change_high)},
                        {"below_noise", quiet}});
      }
    sensitivity[info.key] = {{"unit", info.unit},
                             {"nominal", json_number(nominal->figures[f])},
                             {"noise", json_number(noise[f])},
                             {"rows", rows}};
    std::vector<design::SensitivityRow> all = ranked;
    all.insert(all.end(), below.begin(), below.end());
    const std::string svg = (fs::path(out_dir) / ("tornado_" + std::string(info.key) + ".svg")).string();
    if (Status s = io::write_figure(svg, design::tornado_figure(info.text, info.unit, all, noise[f])); !s.ok())
      plot_failures.push_back(to_string(s.error()));
  }
  report["sensitivity"] = sensitivity;
  // The inverse: per --spec limit, how far each tolerance may be scaled:
  // linear from its changes at its limits, then traced — the tolerance alone
  // at k·(low, high), both sides within the limit, k doubled from 1 until a
  // side leaves it (up to kMaxInverseScale), then --inverse-steps bisection
  // steps, each trace on the same photons (common random numbers).
  json inverse = json::array();
  const long long inverse_steps = options.inverse_steps;
  if (!limits.empty())
    table += "\nLargest tolerances that keep a figure within its limit (each alone; a factor of the\n"
             "tolerance as given): linear from the changes at the limits, and traced by bisection on\n"
             "the factor (" + std::to_string(inverse_steps) + " steps; the largest factor that held … the smallest that failed):\n";
  for (const design::SpecLimit& limit : limits) {
    const std::size_t f = limit.figure;
    table += "\n" + limit.text() + " (nominal " + format_number(nominal->figures[f]) + ")\n";
    for (std::size_t i = 0; i < dims; ++i) {
      const design::Tolerance& t = spec->tolerances[i];
      const double base = f == design::kRms ? 0.0 : nominal->figures[f];
      const double low = at_limits[i][0][f] - base, high = at_limits[i][1][f] - base;
      const bool undefined = !std::isfinite(nominal->figures[f]);
      const bool quiet = !undefined && design::below_noise(std::max(std::abs(low), std::abs(high)), noise[f]);
      const bool discrete = t.law.kind == design::ToleranceLaw::Kind::Bins;  // a bin number cannot be scaled
      const double k = undefined || discrete ? photometry::kNaN : design::allowed_scale(nominal->figures[f], low, high, limit);
      std::string says = discrete      ? "bins: a discrete law, not scaled"
                         : undefined   ? "not defined for this model"
                         : quiet       ? "below noise: not estimated"
                         : std::isinf(k) ? "any (no change towards the limit)"
                                         : "× " + format_number(k, 3) + ": " + format_number(k * t.law.low(), 3) +
                                               " … " + format_number(k * t.law.high(), 3) + " " + t.unit();
      json entry = {{"limit", limit.text()},
                    {"tolerance", t.label()},
                    {"scale", undefined || quiet || !std::isfinite(k) ? json(nullptr) : json(k)},
                    {"why", discrete ? "bins" : undefined ? "not defined" : quiet ? "below noise" : std::isinf(k) ? "no change towards the limit" : ""}};
      // Traced, where the linear estimate is finite and positive.
      if (inverse_steps > 0 && !undefined && !quiet && std::isfinite(k) && k > 0.0) {
        // A relative tolerance stays above −100 %, a reflectance keeps the lobes within 1.
        const double cap = std::min(design::kMaxInverseScale, tracer.largest_scale(i));
        std::size_t traces = 0;
        std::string trace_error;
        const auto holds_at = [&](double scale) -> std::optional<bool> {
          for (double limit_value : {t.law.low(), t.law.high()}) {
            const double v = scale * limit_value;
            if (v == 0.0) continue;
            std::vector<double> values = zeros;
            values[i] = v;
            say("inverse sensitivity, " + limit.text() + ": " + t.label() + " = " + format_number(v) + " " + t.unit() +
                " (× " + format_number(scale, 4) + ")\n");
            std::optional<Trace> tr = tracer.trace(values, seed, &nominal_d);
            if (!tr) return std::nullopt;
            ++traces;
            seconds.push_back(tr->seconds);
            if (!limit.holds(tr->figures[f])) return false;
          }
          return true;
        };
        double ok = 0.0, bad = std::numeric_limits<double>::infinity();
        (limit.holds(at_limits[i][0][f]) && limit.holds(at_limits[i][1][f]) ? ok : bad) = 1.0;
        if (ok == 1.0 && cap < 1.0) ok = 0.0;  // cannot happen for a law the file accepted; kept safe
        for (double next = std::min(2.0, cap); std::isinf(bad) && ok > 0.0 && ok < cap;
             next = std::min(2.0 * next, cap)) {
          const std::optional<bool> h = holds_at(next);
          if (!h) return make_error("an inverse-sensitivity trace failed (" + tracer.error() + "); nothing more was analysed");
          (*h ? ok : bad) = next;
          if (next >= cap) break;
        }
        for (long long step = 0; step < inverse_steps && std::isfinite(bad); ++step) {
          const double mid = 0.5 * (ok + bad);
          const std::optional<bool> h = holds_at(mid);
          if (!h) return make_error("an inverse-sensitivity trace failed (" + tracer.error() + "); nothing more was analysed");
          (*h ? ok : bad) = mid;
        }
        entry["traced_scale"] = ok;
        entry["traced_fails_at"] = std::isinf(bad) ? json(nullptr) : json(bad);
        entry["traced_low"] = ok * t.law.low();
        entry["traced_high"] = ok * t.law.high();
        entry["traces"] = traces;
        says += "; traced × " + format_number(ok, 3) + " … " +
                (std::isinf(bad) ? "(held up to " + format_number(cap, 3) + ")" : format_number(bad, 3)) + ": " +
                format_number(ok * t.law.low(), 3) + " … " + format_number(ok * t.law.high(), 3) + " " + t.unit();
      }
      table += "  " + padded(t.label() + " " + t.law.text() + " " + t.unit(), 44) + "  " + says + "\n";
      inverse.push_back(entry);
    }
  }
  report["inverse_sensitivity"] = inverse;
  if (Status s = io::write_file_atomic((fs::path(out_dir) / "sensitivity.txt").string(), table); !s.ok())
    output_failures.push_back(to_string(s.error()));
  say(table);
  if (hooks.on_warning)
    for (const std::string& f : plot_failures) hooks.on_warning("tornado chart not drawn: " + f);
  report["plot_failures"] = plot_failures;

  // Monte Carlo: every tolerance drawn at once.
  json mc_trials = json::array();
  std::vector<std::vector<double>> figure_values(kFigureCount);
  std::size_t passed = 0;
  std::vector<std::size_t> passed_by(limits.size(), 0);
  std::optional<std::size_t> best, worst;
  std::vector<photometry::Distribution> kept(2);  // best, worst
  double best_rms = 0.0, worst_rms = 0.0;
  // The trials: --parallel-trials at once, each from its own values and the
  // common seed, so their figures do not depend on the order they finish in.
  const std::vector<std::vector<double>> trial_values = monte_carlo_values(*spec, trials, sampling_seed);
  const std::vector<std::vector<double>>& u = trial_values;
  std::vector<std::optional<Trace>> results(u.size());
  {
    std::atomic<std::size_t> next{0};
    std::atomic<bool> stop{false};
    std::mutex mutex;
    std::string first_error;
    std::size_t finished = 0;
    const auto worker = [&] {
      for (;;) {
        const std::size_t n = next++;
        if (n >= u.size() || stop) return;
        std::string why;
        std::optional<Trace> t = tracer.trace(trial_values[n], seed, &nominal_d, false, &why);
        const std::lock_guard<std::mutex> lock(mutex);
        if (!t) {
          if (!stop.exchange(true))
            first_error = "Monte Carlo trial " + std::to_string(n + 1) + " failed (" + why + "); nothing more was analysed";
          return;
        }
        t->distribution = {};  // best and worst are traced again below
        ++finished;
        char seconds_text[32];
        std::snprintf(seconds_text, sizeof seconds_text, "%.2f", t->seconds);
        say("trial " + std::to_string(n + 1) + "/" + std::to_string(u.size()) + " (" + std::to_string(finished) +
            " done): " + (t->from_journal ? std::string("from the journal") : std::string(seconds_text) + " s") +
            ", beam " + format_number(t->figures[design::kBeamC0], 4) + "/" +
            format_number(t->figures[design::kBeamC90], 4) + " deg, peak " +
            format_number(t->figures[design::kPeakCd], 5) + " cd, flux " + format_number(t->figures[design::kFlux], 5) +
            " lm, rms " + format_number(t->figures[design::kRms], 3) + " %\n");
        results[n] = std::move(t);
      }
    };
    const std::size_t workers =
        std::max<std::size_t>(1, std::min<std::size_t>(static_cast<std::size_t>(options.parallel_trials), u.size()));
    std::vector<std::thread> pool;
    for (std::size_t w = 1; w < workers; ++w) pool.emplace_back(worker);
    worker();
    for (std::thread& th : pool) th.join();
    if (stop) return make_error(first_error);
  }
  std::vector<double> trial_seconds;
  for (std::size_t n = 0; n < u.size(); ++n) {
    const std::vector<double>& values = trial_values[n];
    std::optional<Trace>& t = results[n];
    seconds.push_back(t->seconds);
    trial_seconds.push_back(t->seconds);
    bool in_spec = true;
    json verdicts = json::object();
    for (std::size_t l = 0; l < limits.size(); ++l) {
      const bool ok = limits[l].holds(t->figures[limits[l].figure]);
      verdicts[limits[l].text()] = ok;
      if (ok) ++passed_by[l];
      in_spec = in_spec && ok;
    }
    if (in_spec) ++passed;
    for (std::size_t f = 0; f < kFigureCount; ++f) figure_values[f].push_back(t->figures[f]);
    const double rms = t->figures[design::kRms];
    if (!best || rms < best_rms) {
      best = n;
      best_rms = rms;
    }
    if (!worst || rms > worst_rms) {
      worst = n;
      worst_rms = rms;
    }
    mc_trials.push_back({{"trial", n + 1},
                         {"values", values_json(*spec, values)},
                         {"figures", figures_json(t->figures)},
                         {"in_spec", limits.empty() ? json(nullptr) : json(in_spec)},
                         {"limits", verdicts}});
  }
  // The best and worst trials traced again for their tables (the same
  // photons: the same distribution as in the Monte Carlo run).
  if (best)
    for (int k = 0; k < 2; ++k) {
      const std::size_t n = k == 0 ? *best : *worst;
      std::optional<Trace> t = tracer.trace(trial_values[n], seed, &nominal_d, true);
      if (!t) return make_error("the trial " + std::to_string(n + 1) + " traced again failed (" + tracer.error() + ")");
      kept[static_cast<std::size_t>(k)] = std::move(t->distribution);
    }
  json histograms = json::object();
  for (std::size_t f = 0; f < kFigureCount && !u.empty(); ++f) {
    const design::Histogram h = design::histogram(figure_values[f], static_cast<std::size_t>(bins));
    histograms[design::figure_info()[f].key] = {{"edges", h.edges}, {"counts", h.counts}};
  }
  json yield = json::object();
  if (!limits.empty() && !u.empty()) {
    for (std::size_t l = 0; l < limits.size(); ++l)
      yield[limits[l].text()] = static_cast<double>(passed_by[l]) / static_cast<double>(u.size());
    yield["all"] = static_cast<double>(passed) / static_cast<double>(u.size());
  }
  if (best)
    for (int k = 0; k < 2; ++k) {
      const char* stem = k == 0 ? "best" : "worst";
      write_tables(out_dir, stem, kept[static_cast<std::size_t>(k)], files, output_failures);
      write_trace_report(out_dir, stem, mc_trials[k == 0 ? *best : *worst], files, output_failures);
    }
  // The trials at the --percentile choices of their figure (nearest rank
  // over the trials where the figure is defined), traced again for their
  // tables like best and worst.
  json percentile_trials = json::array();
  for (const design::PercentileChoice& c : percentiles) {
    const std::vector<double>& v = figure_values[c.figure];
    const std::optional<std::size_t> n = design::nearest_rank(v, c.percent);
    std::size_t defined = 0;
    for (double x : v) defined += std::isfinite(x) ? 1 : 0;
    json entry = {{"figure", design::figure_info()[c.figure].key}, {"percentile", c.percent}, {"of", defined}};
    if (!n) {
      entry["trial"] = nullptr;
      entry["why"] = u.empty() ? "no trials" : "the figure is not defined for this model";
      percentile_trials.push_back(entry);
      continue;
    }
    say("percentile " + c.text() + ": trial " + std::to_string(*n + 1) + " (" +
        format_number(v[*n]) + " " + design::figure_info()[c.figure].unit + "), traced again\n");
    std::optional<Trace> t = tracer.trace(trial_values[*n], seed, &nominal_d, true);
    if (!t) return make_error("the trial " + std::to_string(*n + 1) + " traced again failed (" + tracer.error() + ")");
    json written = json::array();
    write_tables(out_dir, c.stem(), t->distribution, written, output_failures);
    for (const json& name : written) files.push_back(name);
    json trace_entry = mc_trials[*n];
    trace_entry["percentile"] = {{"figure", design::figure_info()[c.figure].key}, {"percent", c.percent}};
    const std::size_t tables_written = written.size();
    write_trace_report(out_dir, c.stem(), trace_entry, written, output_failures);
    if (written.size() > tables_written) files.push_back(written.back());
    entry["trial"] = *n + 1;
    entry["value"] = json_number(v[*n]);
    entry["rank"] = static_cast<std::size_t>(
        std::max(1.0, std::ceil(c.percent * static_cast<double>(defined) / 100.0)));
    entry["files"] = written;
    percentile_trials.push_back(entry);
  }
  report["monte_carlo"] = {{"trials", mc_trials},
                           {"histograms", histograms},
                           {"yield", yield},
                           {"best_trial", best ? json(*best + 1) : json(nullptr)},
                           {"worst_trial", worst ? json(*worst + 1) : json(nullptr)},
                           {"best_and_worst_by", "RMS difference from the nominal"},
                           {"percentile_trials", percentile_trials},
                           {"percentile_rule",
                            "nearest rank: the trials where the figure is defined sorted ascending (ties by trial "
                            "number), the one at rank max(1, ceil(P/100 * n)) of n"}};
  double total = 0.0;
  for (double s : seconds) total += s;
  // Wall times in timing.json, not in report.json: the report is the same
  // bytes for any --parallel-trials and for a run resumed from its journal.
  json timing = {{"traces", seconds.size()},
                 {"seconds_per_trace", seconds.empty() ? 0.0 : total / static_cast<double>(seconds.size())},
                 {"seconds", seconds},
                 {"trial_seconds", trial_seconds},
                 {"read_from_journal", reused}};
  if (Status s = io::write_file_atomic((fs::path(out_dir) / "timing.json").string(), timing.dump(2) + "\n"); !s.ok())
    output_failures.push_back(to_string(s.error()));
  else
    files.push_back("timing.json");
  files.push_back("journal.jsonl");
  report["files"] = files;
  report["output_failures"] = output_failures;
  std::string not_written;
  for (const std::string& f : output_failures) not_written += "\n  " + f;
  if (Status s = io::write_file_atomic((fs::path(out_dir) / "report.json").string(), report.dump(2) + "\n"); !s.ok())
    return make_error(to_string(s.error()) + (not_written.empty() ? "" : "; nor were:" + not_written));
  if (!output_failures.empty())
    return make_error(std::to_string(output_failures.size()) + " file(s) could not be written after tracing (every other "
                      "file and report.json were; report.json lists these under output_failures):" + not_written);
  ToleranceRunOutcome out;
  out.timing = std::move(timing);
  out.report = std::move(report);
  out.report_path = (fs::path(out_dir) / "report.json").string();
  out.table = std::move(table);
  return out;
}

}  // namespace gonio::app
