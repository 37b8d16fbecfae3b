// The model checks' cache (io/model/model_check.h): JSON files named by a content
// hash, one per large mesh and one for the model's small meshes together, so
// that a model edited in one large part is checked again in that part only.
// Internal to gonio::io_model_check.
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

// Meshes of at least this many triangles have an entry of their own; the
// model's smaller ones share one (checking them all again costs little, and a
// model of thousands of small parts then reads and writes one file, not
// thousands: 2,000 boxes took 0.37 s to store one entry each).
inline constexpr std::size_t kOwnEntryTriangles = 4096;

// The meshes of a scene that one entry holds, in scene order, with whether
// the checks treat each as refractive.
struct CheckGroup {
  std::vector<std::size_t> meshes;
  std::vector<char> refractive;
};

// XXH3 (io/support/content_hash.h) of kModelCheckRevision and, per mesh of the group,
// whether it is refractive, its positions and its indices: everything the
// checks read.
std::uint64_t check_group_key(const sim::SceneDesc& scene, const CheckGroup& group);

// The group's findings (one list per mesh) stored under `key`, if the folder
// holds a well-formed entry for as many meshes, each of as many vertices and
// triangles and as refractive; nothing otherwise (missing, unreadable,
// malformed, another revision).
std::optional<std::vector<std::vector<MeshFinding>>> read_cached_checks(const std::string& dir, std::uint64_t key,
                                                                        const sim::SceneDesc& scene,
                                                                        const CheckGroup& group);

// Stores the entry atomically (io/support/file_io.h); false where it cannot be
// written (the caller carries on without the cache).
bool write_cached_checks(const std::string& dir, std::uint64_t key, const sim::SceneDesc& scene,
                         const CheckGroup& group, const std::vector<std::vector<MeshFinding>>& findings);

// The entry's file name: mesh-check-<16 hex digits>.json (io/support/cache_folder.h).
std::string cached_checks_name(std::uint64_t key);

}  // namespace gonio::io
