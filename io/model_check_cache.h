// The model checks' cache (io/model_check.h): one JSON file per mesh's
// result, named by a content hash, so that a model edited in one part is
// checked again in that part only. Internal to gonio::io_model.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "photometry/diagnostics.h"
#include "sim/scene.h"

namespace gonio::io {

// One finding of one mesh, without the mesh's name (names do not change
// what the checks find, so renaming a part keeps its cache entry).
struct MeshFinding {
  Severity severity = Severity::Warning;
  std::string code;
  std::string detail;  // the message after the mesh's name
};

// XXH3 (io/content_hash.h) of kModelCheckRevision, whether the mesh is
// refractive, its positions and its indices: everything the checks read.
std::uint64_t mesh_check_key(const sim::Mesh& mesh, bool refractive);

// The mesh's findings stored under `key`, if the folder holds a well-formed
// entry for a mesh of as many vertices and triangles and as refractive;
// nothing otherwise (missing, unreadable, malformed, another revision).
std::optional<std::vector<MeshFinding>> read_cached_checks(const std::string& dir, std::uint64_t key,
                                                           const sim::Mesh& mesh, bool refractive);

// Stores the entry atomically (io/file_io.h); false where it cannot be
// written (the caller carries on without the cache).
bool write_cached_checks(const std::string& dir, std::uint64_t key, const sim::Mesh& mesh, bool refractive,
                         const std::vector<MeshFinding>& findings);

// The entry's file name: mesh-check-<16 hex digits>.json.
std::string cached_checks_name(std::uint64_t key);

}  // namespace gonio::io
