// Whole-file reading with the checks every reader needs, and atomic writes.
//
// Outputs are written to a temporary file beside the target and renamed over
// it, so a failure never leaves a half-written file and a reader of the path
// (a viewer watching a preview) sees either the old or the new contents.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "photometry/diagnostics.h"

namespace gonio::io {

// Reads a regular file whole. Errors name the path: missing, a directory or
// other non-regular file, unreadable, or larger than `max_bytes`.
Result<std::string> read_file(const std::string& path, std::size_t max_bytes);
// The same into the byte vector a library asks for (tinygltf's buffers), so
// that a large buffer is read once rather than read and copied.
Result<std::vector<unsigned char>> read_file_bytes(const std::string& path, std::size_t max_bytes);

// Writes `bytes` to `path` atomically (temporary file in the same directory,
// flushed, then renamed). The directory must exist.
Status write_file_atomic(const std::string& path, std::string_view bytes);

// Creates a directory and its parents if missing.
Status make_directories(const std::string& path);

// Whether two paths name the same existing file (through links too): what a
// command checks before it writes an output where it may have read an input.
bool same_file(const std::string& a, const std::string& b);

}  // namespace gonio::io
