// The model checks' cache (io/model_check.h): one JSON file per model's
// result, named by a content hash. Internal to gonio::io_model.
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

// Per mesh of a scene: whether the checks treat it as refractive.
using RefractiveFlags = std::vector<char>;
// Per mesh of a scene: its findings.
using ModelCheckResults = std::vector<std::vector<MeshFinding>>;

// FNV-1a 64 of kModelCheckRevision and, per mesh, whether it is refractive,
// its positions and its indices: everything the checks read.
std::uint64_t model_check_key(const sim::SceneDesc& scene, const RefractiveFlags& refractive);

// The entry for `key`, if the folder holds a well-formed one for a scene of
// as many meshes, each of as many vertices and triangles and as refractive;
// nothing otherwise (missing, unreadable, malformed, another revision).
std::optional<ModelCheckResults> read_cached_checks(const std::string& dir, std::uint64_t key,
                                                    const sim::SceneDesc& scene,
                                                    const RefractiveFlags& refractive);

// Stores the entry atomically (io/file_io.h); false where it cannot be
// written (the caller carries on without the cache).
bool write_cached_checks(const std::string& dir, std::uint64_t key, const sim::SceneDesc& scene,
                         const RefractiveFlags& refractive, const ModelCheckResults& results);

// The entry's file name: model-check-<16 hex digits>.json.
std::string cached_checks_name(std::uint64_t key);

}  // namespace gonio::io
