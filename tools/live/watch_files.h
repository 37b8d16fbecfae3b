// How `gonio watch` notices that a model changed on disk, and when it loads
// it again: polling, debouncing, and retrying a half-written file. The logic
// takes the clock as an argument, so that tests can drive it.
//
// - A file's stamp is (exists, size, mtime in ns, inode): an editor that
//   writes in place changes size or mtime, one that writes a temporary and
//   renames it changes the inode.
// - Debounce: a change is acted on once the stamps differ from those the
//   current run was loaded from and have stayed the same for `quiet` (a
//   modeller writing a file in several bursts triggers one reload, after its
//   last write).
// - Retry: a model that fails to load may be half-written by a program that
//   is still saving (its stamp can stop changing before the bytes are
//   complete, e.g. within one mtime tick). It is tried again after each of
//   the retry delays; after the last one the error is shown, and the next
//   change starts over.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace gonio::cli {

using WatchClock = std::chrono::steady_clock;

struct FileStamp {
  bool exists = false;
  std::uint64_t size = 0;      // [bytes]
  std::int64_t mtime_ns = 0;   // modification time [ns since the epoch]
  std::uint64_t inode = 0;
  bool operator==(const FileStamp&) const = default;
};

// The stamp of a path now (exists = false where it cannot be stat'ed).
FileStamp stamp_of(const std::string& path);

// Stamps of several files, in order.
using Snapshot = std::vector<FileStamp>;
Snapshot snapshot_of(const std::vector<std::string>& paths);

class ChangeDebouncer {
 public:
  explicit ChangeDebouncer(std::chrono::milliseconds quiet) : quiet_(quiet) {}

  // The files as the current run loaded them.
  void arm(Snapshot baseline);
  // A poll of the files at `now`: true when they differ from the baseline
  // and have not changed since at least `quiet` before `now`.
  bool observe(const Snapshot& current, WatchClock::time_point now);

 private:
  std::chrono::milliseconds quiet_;
  Snapshot baseline_;
  Snapshot last_;
  WatchClock::time_point last_change_{};
  bool pending_ = false;
};

class LoadRetry {
 public:
  explicit LoadRetry(std::vector<std::chrono::milliseconds> delays) : delays_(std::move(delays)) {}

  // A fresh change: retries start from the first delay again.
  void reset() { failures_ = 0; }
  // A load failed at `now`: when to try again, or nothing when the retries
  // are spent (show the error; wait for the next change).
  std::optional<WatchClock::time_point> failed(WatchClock::time_point now);
  int failures() const { return failures_; }
  int retries() const { return static_cast<int>(delays_.size()); }

 private:
  std::vector<std::chrono::milliseconds> delays_;
  int failures_ = 0;
};

}  // namespace gonio::cli
