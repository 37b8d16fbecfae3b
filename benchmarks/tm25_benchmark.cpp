// IES TM-25 ray-file reading and writing speed (MB/s): the OSRAM ray set of
// the corpus (2.8 MB, 100,000 rays of 7 items) in memory, and the same rays
// repeated to 2,000,000 (56 MB), as parse_tm25 reads them (header checks,
// the count against the bytes, every item finite, directions unit, flux
// sums) and as write_tm25 writes them; read_tm25_file adds the file read.
// Run: build/benchmarks/gonio_io_benchmarks --benchmark_filter=Tm25
#include <benchmark/benchmark.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

#include "io/photometric/tm25.h"
#include "io/support/file_io.h"

namespace {

namespace fs = std::filesystem;

fs::path osram_path() {
  const char* env = std::getenv("GONIO_CORPUS");
  const fs::path corpus = env && *env ? fs::path(env) : fs::path(GONIO_BENCHMARK_CORPUS_DIR);
  return corpus / "rayfiles" / "rayfile_LERTDUW_S2WP_blue_100k_20161013_IES_TM25.TM25RAY";
}

// The OSRAM file with its rays repeated `copies` times (the count adjusted).
std::string osram_bytes(int copies) {
  auto bytes = gonio::io::read_file(osram_path().string(), std::size_t{1} << 30);
  if (!bytes.ok()) return {};
  auto set = gonio::io::parse_tm25(*bytes, "osram");
  if (!set.ok()) return {};
  const std::size_t header = bytes->size() - set->items.size() * 4;
  std::string out = bytes->substr(0, header);
  for (int c = 0; c < copies; ++c) out += bytes->substr(header);
  const std::uint64_t n = set->ray_count() * static_cast<std::uint64_t>(copies);
  std::memcpy(out.data() + 20, &n, sizeof n);
  return out;
}

void BM_Tm25Parse(benchmark::State& state) {
  const std::string bytes = osram_bytes(static_cast<int>(state.range(0)));
  if (bytes.empty()) {
    state.SkipWithError("the OSRAM ray file of ../shared/corpus is missing");
    return;
  }
  for (auto _ : state) {
    auto set = gonio::io::parse_tm25(bytes, "osram");
    benchmark::DoNotOptimize(set);
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(bytes.size()));
}
BENCHMARK(BM_Tm25Parse)->Arg(1)->Arg(20)->Unit(benchmark::kMillisecond);

void BM_Tm25ReadFile(benchmark::State& state) {
  const std::string path = osram_path().string();
  if (!fs::exists(path)) {
    state.SkipWithError("the OSRAM ray file of ../shared/corpus is missing");
    return;
  }
  for (auto _ : state) {
    auto set = gonio::io::read_tm25_file(path);
    benchmark::DoNotOptimize(set);
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(fs::file_size(path)));
}
BENCHMARK(BM_Tm25ReadFile)->Unit(benchmark::kMillisecond);

void BM_Tm25Write(benchmark::State& state) {
  const std::string bytes = osram_bytes(static_cast<int>(state.range(0)));
  if (bytes.empty()) {
    state.SkipWithError("the OSRAM ray file of ../shared/corpus is missing");
    return;
  }
  auto set = gonio::io::parse_tm25(bytes, "osram");
  for (auto _ : state) {
    auto out = gonio::io::write_tm25(*set);
    benchmark::DoNotOptimize(out);
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(bytes.size()));
}
BENCHMARK(BM_Tm25Write)->Arg(1)->Arg(20)->Unit(benchmark::kMillisecond);

}  // namespace
