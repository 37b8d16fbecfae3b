// gonio_make_samples DIR — writes the sample luminaires to DIR/<name>/
// (see samples/luminaires.h). The build runs it into build/samples.
// gonio_make_samples --peer DIR — writes other tools' scenes rebuilt in Gonio
// (samples/peer_scenes.h) to DIR/<name>/.
// gonio_make_samples --large KIND TRIANGLES DIR — writes one large model
// (samples/large_models.h; KIND faceted-reflector, lens-array or
// glass-part) to DIR/<KIND>-<TRIANGLES>/.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "io/support/file_io.h"
#include "samples/large_models.h"
#include "samples/luminaires.h"
#include "samples/peer_scenes.h"

namespace {

int write_large(const std::string& kind_name, const std::string& count, const std::string& dir) {
  using gonio::samples::LargeModel;
  const LargeModel kinds[] = {LargeModel::FacetedReflector, LargeModel::LensArray, LargeModel::GlassPart};
  char* end = nullptr;
  const unsigned long long triangles = std::strtoull(count.c_str(), &end, 10);
  if (count.empty() || *end != '\0' || triangles < 100 || triangles > 100'000'000ULL) {
    std::fprintf(stderr, "gonio_make_samples: TRIANGLES must be a whole number in 100..100000000, not '%s'\n",
                 count.c_str());
    return 2;
  }
  for (LargeModel kind : kinds) {
    if (gonio::samples::large_model_name(kind) != kind_name) continue;
    const gonio::samples::Sample s = gonio::samples::large_model(kind, triangles);
    const std::filesystem::path folder = std::filesystem::path(dir) / s.name;
    if (gonio::Status st = gonio::io::make_directories(folder.string()); !st.ok()) {
      std::fprintf(stderr, "gonio_make_samples: %s\n", gonio::to_string(st.error()).c_str());
      return 1;
    }
    for (const gonio::samples::SampleFile& f : s.files)
      if (gonio::Status st = gonio::io::write_file_atomic((folder / f.name).string(), f.bytes); !st.ok()) {
        std::fprintf(stderr, "gonio_make_samples: %s\n", gonio::to_string(st.error()).c_str());
        return 1;
      }
    std::printf("%s\n", (folder / s.model).string().c_str());
    return 0;
  }
  std::fprintf(stderr, "gonio_make_samples: unknown model '%s' (faceted-reflector, lens-array, glass-part)\n",
               kind_name.c_str());
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 5 && std::string(argv[1]) == "--large") return write_large(argv[2], argv[3], argv[4]);
  if (argc == 3 && std::string(argv[1]) == "--peer") {
    const gonio::Status written = gonio::samples::write_peer_samples(argv[2]);
    if (!written.ok()) {
      std::fprintf(stderr, "gonio_make_samples: %s\n", gonio::to_string(written.error()).c_str());
      return 1;
    }
    return 0;
  }
  // An option it does not know ("--help") is not a folder to write into.
  if (argc != 2 || argv[1][0] == '-') {
    std::fprintf(stderr, "usage: gonio_make_samples DIR\n       gonio_make_samples --large KIND TRIANGLES DIR\n"
                 "       gonio_make_samples --peer DIR\n");
    return argc == 2 && std::string(argv[1]) == "--help" ? 0 : 2;
  }
  const gonio::Status written = gonio::samples::write_samples(argv[1]);
  if (!written.ok()) {
    std::fprintf(stderr, "gonio_make_samples: %s\n", gonio::to_string(written.error()).c_str());
    return 1;
  }
  return 0;
}
