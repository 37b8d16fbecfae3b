#include "tools/live/watch_files.h"

#include <sys/stat.h>

namespace gonio::cli {

FileStamp stamp_of(const std::string& path) {
  struct stat st {};
  FileStamp s;
  if (::stat(path.c_str(), &st) != 0) return s;
  s.exists = true;
  s.size = static_cast<std::uint64_t>(st.st_size);
  s.mtime_ns = static_cast<std::int64_t>(st.st_mtim.tv_sec) * 1'000'000'000 + st.st_mtim.tv_nsec;
  s.inode = static_cast<std::uint64_t>(st.st_ino);
  return s;
}

Snapshot snapshot_of(const std::vector<std::string>& paths) {
  Snapshot out;
  out.reserve(paths.size());
  for (const std::string& p : paths) out.push_back(stamp_of(p));
  return out;
}

void ChangeDebouncer::arm(Snapshot baseline) {
  baseline_ = std::move(baseline);
  last_ = baseline_;
  pending_ = false;
}

bool ChangeDebouncer::observe(const Snapshot& current, WatchClock::time_point now) {
  if (current != last_) {
    last_ = current;
    last_change_ = now;
    pending_ = current != baseline_;
    return false;
  }
  return pending_ && now - last_change_ >= quiet_;
}

std::optional<WatchClock::time_point> LoadRetry::failed(WatchClock::time_point now) {
  if (failures_ >= static_cast<int>(delays_.size())) return std::nullopt;
  return now + delays_[static_cast<std::size_t>(failures_++)];
}

}  // namespace gonio::cli
