// The vocabulary of a material's `extras.gonio` in one place: a JSON object
// in, io::MaterialExtras out (io/model/gltf_material.h documents every key).
// glTF materials read it from their extras; other model formats (the CAD
// sidecar) hand the same vocabulary in as a JSON object.
#pragma once

#include <nlohmann/json_fwd.hpp>

#include <optional>
#include <string>
#include <vector>

#include "io/model/gltf_material.h"
#include "photometry/diagnostics.h"
#include "photometry/spectrum.h"
#include "sim/scene.h"

namespace gonio::io {

// `gonio` is the object (extras.gonio); `file` names the document for
// errors, `what` the material ("material 'opal' (#2)"). Keys it does not
// know are Warning findings ("unknown-extras-key"); values of the wrong type
// or out of range are errors naming the key.
Result<MaterialExtras> read_material_extras(const nlohmann::json& gonio, const std::string& file,
                                            const std::string& what, std::vector<Finding>& findings);

// The pieces the vocabulary is made of, for the other extras of a model
// (lights, the scene): a number (absent: nullopt; not a finite number: an
// error), and an emitter's spectrum (extras.gonio.spectrum: blackbody_k,
// wavelengths_nm and values, or over_gamma; absent: empty).
Result<std::optional<double>> extras_number(const nlohmann::json& obj, const char* key, const std::string& file,
                                            const std::string& what);
Result<sim::EmitterSpectrum> read_emitter_spectrum(const nlohmann::json& obj, const std::string& file,
                                                   const std::string& what);

}  // namespace gonio::io
