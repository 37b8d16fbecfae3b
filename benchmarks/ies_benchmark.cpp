// IES LM-63 parsing and writing speed on the largest files of the corpus.
//
// Per file: parse_ies on bytes already in memory (µs per file, MB/s), and as
// a baseline measured in the same run, std::from_chars over the same
// numbers (the floor any text parser stands on). write_ies of the parsed
// model. Run: build/benchmarks/gonio_io_benchmarks [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "io/file_io.h"
#include "io/ies.h"

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

// The largest IES files of the corpus, largest first.
std::vector<Sample> largest_ies_files(std::size_t count) {
  std::vector<std::pair<std::uintmax_t, fs::path>> files;
  std::error_code ec;
  const fs::path root = corpus_dir();
  if (!fs::is_directory(root, ec)) return {};
  for (const auto& entry : fs::recursive_directory_iterator(root, ec)) {
    std::string ext = entry.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    if (entry.is_regular_file() && ext == ".ies")
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
  static const std::vector<Sample> s = largest_ies_files(4);
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
  }
  return true;
}();

}  // namespace
