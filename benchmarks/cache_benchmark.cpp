// What keeping the cache folder to its limit costs a run (io/support/cache_folder.h):
// trim_cache over a folder of N entries of 4 KB, all within the limit (the
// scan every run pays), and over the same folder with the limit at half its
// size (the scan, the sort and removing half; the entries are written again
// outside the timing).
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "io/support/cache_folder.h"
#include "io/support/file_io.h"

namespace gonio::io {
namespace {

namespace fs = std::filesystem;

class Folder {
 public:
  explicit Folder(std::size_t entries)
      : path_(fs::temp_directory_path() / ("gonio-cache-bench-" + std::to_string(::getpid()))), entries_(entries) {
    fs::create_directories(path_);
    fill();
  }
  ~Folder() { fs::remove_all(path_); }
  Folder(const Folder&) = delete;
  Folder& operator=(const Folder&) = delete;
  void fill() const {
    const std::string bytes(4096, 'x');
    for (std::size_t i = 0; i < entries_; ++i) {
      char hex[17];
      std::snprintf(hex, sizeof hex, "%016zx", i);
      const fs::path p = path_ / ("resampler-" + std::string(hex) + ".bin");
      if (!fs::exists(p)) (void)write_file_atomic(p.string(), bytes);
    }
  }
  std::string path() const { return path_.string(); }
  std::uint64_t bytes() const { return 4096 * entries_; }

 private:
  fs::path path_;
  std::size_t entries_;
};

void BM_TrimCacheWithinLimit(benchmark::State& state) {
  const Folder folder(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(trim_cache(folder.path(), 2 * folder.bytes()));
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_TrimCacheWithinLimit)->Arg(100)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);

void BM_TrimCacheHalf(benchmark::State& state) {
  const Folder folder(static_cast<std::size_t>(state.range(0)));
  std::uint64_t removed = 0;
  for (auto _ : state) {
    removed += trim_cache(folder.path(), folder.bytes() / 2).removed_entries;
    state.PauseTiming();
    folder.fill();
    state.ResumeTiming();
  }
  state.counters["removed_per_trim"] = static_cast<double>(removed) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_TrimCacheHalf)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace gonio::io
