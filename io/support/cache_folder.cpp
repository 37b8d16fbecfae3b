#include "io/support/cache_folder.h"

#include <fcntl.h>
#include <sys/stat.h>

#include <algorithm>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <iterator>
#include <string_view>
#include <system_error>
#include <vector>

#include "io/support/content_hash.h"

namespace gonio::io {
namespace {

struct EntryKind {
  std::string_view prefix, suffix;
};
constexpr EntryKind kEntryKinds[] = {{"mesh-check-", ".json"}, {"resampler-", ".bin"}, {"cad-", ".bin"},
                                   {"glossy-energy-", ".bin"}};  // by CacheEntry

bool is_hex16(std::string_view s) {
  return s.size() == 16 && std::all_of(s.begin(), s.end(), [](char c) {
           return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
         });
}

// A temporary file of io::write_file_atomic for one of the entries:
// ".<entry>.tmp<digits>".
bool is_cache_temp_name(const std::string& name) {
  if (name.size() < 2 || name[0] != '.') return false;
  const std::size_t tmp = name.rfind(".tmp");
  if (tmp == std::string::npos || tmp < 2 || tmp + 4 == name.size()) return false;
  const std::string_view digits = std::string_view(name).substr(tmp + 4);
  if (!std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) return false;
  return is_cache_entry_name(name.substr(1, tmp - 1));
}

constexpr std::int64_t kStaleTempSeconds = 3600;

struct Entry {
  timespec used;
  std::uint64_t bytes;
  std::string path;
};

bool older(const timespec& a, const timespec& b) {
  return a.tv_sec != b.tv_sec ? a.tv_sec < b.tv_sec : a.tv_nsec < b.tv_nsec;
}

}  // namespace

std::string default_cache_dir() {
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
    return (std::filesystem::path(xdg) / "gonio").string();
  if (const char* home = std::getenv("HOME"); home && *home)
    return (std::filesystem::path(home) / ".cache" / "gonio").string();
  return "";
}

std::string cache_entry_name(CacheEntry kind, std::uint64_t key) {
  const EntryKind& k = kEntryKinds[static_cast<int>(kind)];
  return std::string(k.prefix) + to_hex(key) + std::string(k.suffix);
}

bool is_cache_entry_name(const std::string& name) {
  return std::any_of(std::begin(kEntryKinds), std::end(kEntryKinds), [&](const EntryKind& k) {
    return name.size() == k.prefix.size() + 16 + k.suffix.size() && name.starts_with(k.prefix) &&
           name.ends_with(k.suffix) && is_hex16(std::string_view(name).substr(k.prefix.size(), 16));
  });
}

void mark_cache_entry_used(const std::string& path) { ::utimensat(AT_FDCWD, path.c_str(), nullptr, 0); }

CacheTrim trim_cache(const std::string& dir, std::uint64_t limit_bytes) {
  CacheTrim out;
  if (dir.empty()) return out;
  std::vector<Entry> entries;
  std::error_code ec;
  std::filesystem::directory_iterator it(dir, ec);
  if (ec) return out;
  timespec now{};
  ::clock_gettime(CLOCK_REALTIME, &now);
  // Advanced with an error code: a folder that changes or fails while it is
  // read ends the scan rather than throwing.
  for (; !ec && it != std::filesystem::directory_iterator(); it.increment(ec)) {
    const std::filesystem::directory_entry& e = *it;
    const std::string name = e.path().filename().string();
    const bool entry = is_cache_entry_name(name);
    if (!entry && !is_cache_temp_name(name)) continue;
    struct stat st {};
    if (::lstat(e.path().c_str(), &st) != 0 || !S_ISREG(st.st_mode)) continue;
    if (!entry) {
      std::error_code ignored;
      if (now.tv_sec - st.st_mtim.tv_sec >= kStaleTempSeconds) std::filesystem::remove(e.path(), ignored);
      continue;
    }
    entries.push_back({st.st_mtim, static_cast<std::uint64_t>(st.st_size), e.path().string()});
    out.bytes += static_cast<std::uint64_t>(st.st_size);
  }
  out.entries = entries.size();
  if (limit_bytes == 0 || out.bytes <= limit_bytes) return out;
  // Least recently used first; the path (the same folder: the name) breaks
  // ties, so the order is the same on every run.
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
    return older(a.used, b.used) || (!older(b.used, a.used) && a.path < b.path);
  });
  const std::uint64_t target = limit_bytes - limit_bytes / 10;
  for (const Entry& e : entries) {
    if (out.bytes <= target) break;
    const bool removed = std::filesystem::remove(e.path, ec);
    if (ec) continue;  // still there
    out.bytes -= e.bytes;
    --out.entries;
    if (!removed) continue;  // another process removed it first
    ++out.removed_entries;
    out.removed_bytes += e.bytes;
  }
  return out;
}

}  // namespace gonio::io
