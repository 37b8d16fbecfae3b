// libFuzzer harness: the glTF loader (io::load_gltf) with its buffer and
// light-profile loading. The input is a model, .glb when it begins with the
// magic "glTF", else .gltf, optionally followed by a line
// "\n#gonio-fuzz-file\n" and the bytes of a side file: these are written as
// fuzz.bin, fuzz.ies and fuzz.ldt beside the model, so that a model whose
// buffer or EXT_lights_ies uri names one of them has its side file mutated
// too. The model's folder also holds profile.ies and profile.ldt (valid
// sample profiles) for the seeds that name them. A crash or a sanitizer
// report is a finding (scripts/fuzz.sh).
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "io/model/gltf.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace gonio;
  static const std::string dir = fuzz::scratch_dir("gltf");
  std::string_view bytes(reinterpret_cast<const char*>(data), size);
  std::string_view side;
  constexpr std::string_view kSeparator = "\n#gonio-fuzz-file\n";
  if (const std::size_t at = bytes.find(kSeparator); at != std::string_view::npos) {
    side = bytes.substr(at + kSeparator.size());
    bytes = bytes.substr(0, at);
  }
  for (const char* name : {"fuzz.bin", "fuzz.ies", "fuzz.ldt"}) fuzz::write(dir + "/" + name, side);
  const bool binary = bytes.substr(0, 4) == "glTF";
  const std::string model = dir + (binary ? "/model.glb" : "/model.gltf");
  fuzz::write(model, bytes);
  std::vector<Finding> findings;
  Result<sim::SceneDesc> scene = io::load_gltf(model, &findings);
  if (scene.ok() && scene->emitters.empty()) fuzz::finding("load_gltf accepted a model without emitters");
  return 0;
}
