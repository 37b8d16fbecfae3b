// IES LM-63 and EULUMDAT parsing and writing speed on the largest files of
// the corpus.
//
// Per file: parse_ies / parse_ldt on bytes already in memory (µs per file,
// MB/s), and as a baseline measured in the same run, std::from_chars over
// the same numbers (the floor any text parser stands on). Parse + integrate
// (reading plus photometry::total_flux_lm, the least `gonio info` does) and
// parse + summarize (everything `gonio info` derives). write_ies / write_ldt
// of the parsed model. The corpus LDT files are small (≤ 8 KB), so the
// largest IES file is also measured as EULUMDAT, converted in memory.
// Run: build/benchmarks/gonio_io_benchmarks [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "io/support/file_io.h"
#include "io/photometric/ies.h"
#include "io/photometric/ldt.h"
#include "photometry/flux.h"
#include "photometry/summary.h"

namespace {

namespace fs = std::filesystem;

fs::path corpus_dir() {
  if (const char* env = std::getenv("GONIO_CORPUS"); env && *env) return env;
  return GONIO_BENCHMARK_CORPUS_DIR;
}

struct Sample {
  std::string name;
  std::string bytes;
};

// The largest files of the corpus with this extension (".ies", ".ldt";
// case-insensitive), largest first.
std::vector<Sample> largest_files(const std::string& extension, std::size_t count) {
  std::vector<std::pair<std::uintmax_t, fs::path>> files;
  std::error_code ec;
  const fs::path root = corpus_dir();
  if (!fs::is_directory(root, ec)) return {};
  for (const auto& entry : fs::recursive_directory_iterator(root, ec)) {
    std::string ext = entry.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    if (entry.is_regular_file() && ext == extension)
      files.emplace_back(entry.file_size(), entry.path());
  }
  std::sort(files.begin(), files.end(),
            [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<Sample> out;
  for (std::size_t i = 0; i < files.size() && i < count; ++i) {
    auto bytes = gonio::io::read_file(files[i].second.string(), gonio::io::kMaxIesFileBytes);
    if (bytes.ok()) out.push_back({files[i].second.filename().string(), std::move(*bytes)});
  }
  return out;
}

// Any format: parse_ies or parse_ldt by the sample's name.
gonio::Result<gonio::photometry::Distribution> parse_any(const Sample& s) {
  if (s.name.ends_with(".ldt") || s.name.ends_with(".LDT")) {
    auto r = gonio::io::parse_ldt(s.bytes, s.name);
    if (!r.ok()) return r.error();
    return std::move(r->distribution);
  }
  auto r = gonio::io::parse_ies(s.bytes, s.name, "");
  if (!r.ok()) return r.error();
  return std::move(r->distribution);
}

void parse_and_integrate(benchmark::State& state, const Sample* s) {
  for (auto _ : state) {
    auto d = parse_any(*s);
    if (!d.ok()) {
      state.SkipWithError(gonio::to_string(d.error()).c_str());
      return;
    }
    benchmark::DoNotOptimize(gonio::photometry::total_flux_lm(*d));
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * s->bytes.size()));
}

void parse_and_summarize(benchmark::State& state, const Sample* s) {
  for (auto _ : state) {
    auto d = parse_any(*s);
    if (!d.ok()) {
      state.SkipWithError(gonio::to_string(d.error()).c_str());
      return;
    }
    benchmark::DoNotOptimize(gonio::photometry::summarize(*d).flux_lm);
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * s->bytes.size()));
}

void parse_ldt(benchmark::State& state, const Sample* s) {
  for (auto _ : state) {
    auto r = gonio::io::parse_ldt(s->bytes, s->name);
    if (!r.ok()) {
      state.SkipWithError(gonio::to_string(r.error()).c_str());
      return;
    }
    benchmark::DoNotOptimize(r->distribution.candela.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * s->bytes.size()));
}

void write_ldt(benchmark::State& state, const Sample* s) {
  auto d = parse_any(*s);
  if (!d.ok()) {
    state.SkipWithError(gonio::to_string(d.error()).c_str());
    return;
  }
  std::size_t written = 0;
  for (auto _ : state) {
    auto text = gonio::io::write_ldt(*d, {}, nullptr);
    written = text.ok() ? text->size() : 0;
    benchmark::DoNotOptimize(text);
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * written));
}

// Baseline for one number per line (EULUMDAT): every line through
// std::from_chars.
void from_chars_lines_baseline(benchmark::State& state, const Sample* s) {
  const char* begin = s->bytes.data();
  const char* end = begin + s->bytes.size();
  for (auto _ : state) {
    double sum = 0.0;
    for (const char* p = begin; p < end;) {
      const char* q = p;
      while (q < end && *q != '\r' && *q != '\n') ++q;
      double v = 0.0;
      std::from_chars(p, q, v);
      sum += v;
      p = q;
      while (p < end && (*p == '\r' || *p == '\n')) ++p;
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * s->bytes.size()));
}

void parse(benchmark::State& state, const Sample* s) {
  for (auto _ : state) {
    auto r = gonio::io::parse_ies(s->bytes, s->name, "");
    if (!r.ok()) {
      state.SkipWithError(gonio::to_string(r.error()).c_str());
      return;
    }
    benchmark::DoNotOptimize(r->distribution.candela.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * s->bytes.size()));
}

// Baseline: every whitespace- or comma-separated token after the TILT line
// through std::from_chars, nothing else.
void from_chars_baseline(benchmark::State& state, const Sample* s) {
  const std::size_t tilt = s->bytes.find("TILT=");
  const std::size_t start = s->bytes.find('\n', tilt == std::string::npos ? 0 : tilt);
  const char* begin = s->bytes.data() + (start == std::string::npos ? 0 : start);
  const char* end = s->bytes.data() + s->bytes.size();
  for (auto _ : state) {
    double sum = 0.0;
    for (const char* p = begin; p < end;) {
      while (p < end && (*p == ' ' || *p == '\t' || *p == ',' || *p == '\r' || *p == '\n')) ++p;
      const char* q = p;
      while (q < end && !(*q == ' ' || *q == '\t' || *q == ',' || *q == '\r' || *q == '\n')) ++q;
      double v = 0.0;
      std::from_chars(p, q, v);
      sum += v;
      p = q;
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * s->bytes.size()));
}

void write(benchmark::State& state, const Sample* s) {
  auto r = gonio::io::parse_ies(s->bytes, s->name, "");
  if (!r.ok()) {
    state.SkipWithError(gonio::to_string(r.error()).c_str());
    return;
  }
  std::size_t written = 0;
  for (auto _ : state) {
    std::string text = gonio::io::write_ies(r->distribution, {}, nullptr);
    written = text.size();
    benchmark::DoNotOptimize(text.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * written));
}

const std::vector<Sample>& samples() {
  static const std::vector<Sample> s = largest_files(".ies", 4);
  return s;
}

// The largest LDT files of the corpus, and the largest IES file written as
// EULUMDAT (the same grid through the other parser).
const std::vector<Sample>& ldt_samples() {
  static const std::vector<Sample> s = [] {
    std::vector<Sample> out = largest_files(".ldt", 2);
    if (!samples().empty()) {
      const Sample& big = samples().front();
      auto d = gonio::io::parse_ies(big.bytes, big.name, "");
      if (d.ok()) {
        auto text = gonio::io::write_ldt(d->distribution, {}, nullptr);
        if (text.ok()) out.insert(out.begin(), Sample{big.name + ".ldt", std::move(*text)});
      }
    }
    return out;
  }();
  return s;
}

const bool registered = [] {
  if (samples().empty()) {
    benchmark::RegisterBenchmark("ies/corpus_missing", [](benchmark::State& state) {
      state.SkipWithError(
          ("no IES files under " + corpus_dir().string() + " (set GONIO_CORPUS)").c_str());
    });
    return true;
  }
  for (const Sample& s : samples()) {
    const std::string size = " (" + std::to_string(s.bytes.size() / 1024) + " KiB)";
    benchmark::RegisterBenchmark(("ies/parse/" + s.name + size).c_str(), parse, &s)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("ies/from_chars_baseline/" + s.name + size).c_str(),
                                 from_chars_baseline, &s)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("ies/write/" + s.name + size).c_str(), write, &s)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("ies/parse_and_integrate/" + s.name + size).c_str(),
                                 parse_and_integrate, &s)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("ies/parse_and_summarize/" + s.name + size).c_str(),
                                 parse_and_summarize, &s)
        ->Unit(benchmark::kMicrosecond);
  }
  for (const Sample& s : ldt_samples()) {
    const std::string size = " (" + std::to_string(s.bytes.size() / 1024) + " KiB)";
    benchmark::RegisterBenchmark(("ldt/parse/" + s.name + size).c_str(), parse_ldt, &s)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("ldt/from_chars_baseline/" + s.name + size).c_str(),
                                 from_chars_lines_baseline, &s)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("ldt/parse_and_integrate/" + s.name + size).c_str(),
                                 parse_and_integrate, &s)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("ldt/parse_and_summarize/" + s.name + size).c_str(),
                                 parse_and_summarize, &s)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("ldt/write/" + s.name + size).c_str(), write_ldt, &s)
        ->Unit(benchmark::kMicrosecond);
  }
  return true;
}();

}  // namespace
