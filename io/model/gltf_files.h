// The files a glTF 2.0 model is made of: the model itself and every external
// file its URIs name (buffers, images, EXT_lights_ies profiles), resolved
// against the model's folder as io/model/gltf.h resolves them. Data URIs are
// inside the model and name no file. `gonio watch` watches these files.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "photometry/diagnostics.h"

namespace gonio::io {

// The model's path first, then each referenced file once, in the order of
// the JSON (buffers, images, lights). Percent-escapes in URIs are decoded.
// Errors: an unreadable model, bad JSON, or a .glb without a JSON chunk (the
// file name and what is wrong).
Result<std::vector<std::string>> gltf_files(const std::string& model);

// Why a file reference `uri` (percent-decoded, relative to the folder
// `base_dir` of the model or sidecar that names it) leaves that folder, or
// nothing when it stays inside: an absolute path, a `..` that climbs out,
// or a symbolic link on the way that resolves outside. Files that do not
// exist resolve as far as they do.
std::optional<std::string> outside_the_folder(const std::string& base_dir, const std::string& uri);

// The error text for such a reference: `reference` names what refers to the
// file ("uri '../x.bin'"), `why` is outside_the_folder's answer.
std::string outside_message(const std::string& reference, const std::string& why);

}  // namespace gonio::io
