// The files a glTF 2.0 model is made of: the model itself and every external
// file its URIs name (buffers, images, EXT_lights_ies profiles), resolved
// against the model's folder as io/model/gltf.h resolves them. Data URIs are
// inside the model and name no file. `gonio watch` watches these files.
#pragma once

#include <string>
#include <vector>

#include "photometry/diagnostics.h"

namespace gonio::io {

// The model's path first, then each referenced file once, in the order of
// the JSON (buffers, images, lights). Percent-escapes in URIs are decoded.
// Errors: an unreadable model, bad JSON, or a .glb without a JSON chunk (the
// file name and what is wrong).
Result<std::vector<std::string>> gltf_files(const std::string& model);

}  // namespace gonio::io
