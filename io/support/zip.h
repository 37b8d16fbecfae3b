// ZIP archives in memory, for GLDF and L3D containers. io/support/zip.cpp is the
// only file that includes libzip.
//
// Reading is defensive: every entry name is checked before anything is
// read (no absolute names, no drive letters or backslashes, no ".."
// component, no duplicates), every entry's declared size and the archive's
// total are capped, and an entry that inflates beyond its declared size (a
// zip bomb that lies in its header) is refused while it is read, after at
// most one byte more than it declared. Nothing is ever written to disk: the
// caller decides what to do with the bytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "photometry/diagnostics.h"

namespace gonio::io {

struct ZipEntry {
  std::string name;   // '/'-separated path inside the archive
  std::string bytes;  // uncompressed contents
};

struct ZipLimits {
  std::size_t max_entries = 4096;
  std::size_t max_entry_bytes = std::size_t{256} << 20;  // uncompressed, per entry
  std::size_t max_total_bytes = std::size_t{512} << 20;  // uncompressed, all entries
};

// Every entry of the archive in `bytes` (directories left out), in archive
// order. `name` names the archive in errors.
Result<std::vector<ZipEntry>> read_zip(std::string_view bytes, const std::string& name,
                                       const ZipLimits& limits = {});

// Whether an entry name is safe to use as a relative path: not empty, not
// absolute, no backslash or drive letter, no "." or ".." component.
bool is_safe_entry_name(std::string_view name);

// An archive holding `entries` in this order, deflated, each with the
// modification time `mtime_unix` (seconds since 1970, UTC), so that the same
// entries and time give the same bytes. Errors: an unsafe or repeated name.
Result<std::string> write_zip(const std::vector<ZipEntry>& entries, std::int64_t mtime_unix);

}  // namespace gonio::io
