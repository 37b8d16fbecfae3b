// Tables derived from two material parameters (the glossy lobe's energy per
// roughness, the ABg kernel's per (B, g)), built once per process and
// shared: the tracer prepares every material when it starts, and many
// materials share parameters.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <utility>

namespace gonio::sim {

// One cache per table type T (not per builder: a table offered by one
// caller is found by every other, whatever it would build with).
template <class T>
struct TableCache {
  static inline std::mutex mutex;
  static inline std::map<std::pair<double, double>, std::shared_ptr<const T>> tables;
};

// The table for `key`, built by `build(key.first, key.second)` the first
// time and kept. Thread-safe; one cache per table type T. Two threads asking
// for a new key at once may both build it; the first stored wins.
template <class T, class Build>
std::shared_ptr<const T> cached_table(std::pair<double, double> key, Build build) {
  using Cache = TableCache<T>;
  {
    std::lock_guard<std::mutex> lock(Cache::mutex);
    if (auto it = Cache::tables.find(key); it != Cache::tables.end()) return it->second;
  }
  std::shared_ptr<const T> t = build(key.first, key.second);
  std::lock_guard<std::mutex> lock(Cache::mutex);
  return Cache::tables.emplace(key, std::move(t)).first->second;
}

}  // namespace gonio::sim
