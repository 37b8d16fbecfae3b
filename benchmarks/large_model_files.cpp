#include "benchmarks/large_model_files.h"

#include <cstdio>
#include <filesystem>
#include <map>
#include <utility>
#include <vector>

#include <unistd.h>

#include "io/support/file_io.h"
#include "io/model/gltf.h"

namespace gonio::bench {
namespace {

[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "large benchmark model: %s\n", what.c_str());
  std::abort();
}

// A temporary folder for this process, removed with everything in it when
// the process exits normally.
struct Folder {
  std::filesystem::path path;
  Folder() : path(std::filesystem::temp_directory_path() / ("gonio-large-models-" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(path);
  }
  ~Folder() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  Folder(const Folder&) = delete;
  Folder& operator=(const Folder&) = delete;
};

const std::filesystem::path& model_folder() {
  static const Folder folder;
  return folder.path;
}

}  // namespace

std::string large_model_file(samples::LargeModel kind, std::size_t triangles) {
  static std::map<std::pair<int, std::size_t>, std::string> written;
  const auto key = std::make_pair(static_cast<int>(kind), triangles);
  if (auto it = written.find(key); it != written.end()) return it->second;
  const samples::Sample s = samples::large_model(kind, triangles);
  const std::filesystem::path dir = model_folder() / s.name;
  std::filesystem::create_directories(dir);
  for (const samples::SampleFile& f : s.files)
    if (Status st = io::write_file_atomic((dir / f.name).string(), f.bytes); !st.ok())
      fail(to_string(st.error()));
  return written[key] = (dir / s.model).string();
}

const sim::SceneDesc& large_model_scene(samples::LargeModel kind, std::size_t triangles) {
  static std::map<std::pair<int, std::size_t>, sim::SceneDesc> loaded;
  const auto key = std::make_pair(static_cast<int>(kind), triangles);
  if (auto it = loaded.find(key); it != loaded.end()) return it->second;
  std::vector<Finding> findings;
  Result<sim::SceneDesc> s = io::load_gltf(large_model_file(kind, triangles), &findings);
  if (!s.ok()) fail(to_string(s.error()));
  return loaded[key] = std::move(s.value());
}


}  // namespace gonio::bench
