#include "tests/fuzz/fuzz_support.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <system_error>

namespace gonio::fuzz {
namespace fs = std::filesystem;

namespace {

std::string read_whole(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    std::fprintf(stderr, "fuzz: cannot read %s\n", path.c_str());
    std::abort();
  }
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

fs::path scratch_root() {
  std::error_code ec;
  if (fs::is_directory("/dev/shm", ec)) return "/dev/shm";
  return fs::temp_directory_path();
}

}  // namespace

void write(const std::string& path, std::string_view bytes) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f || std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size() || std::fclose(f) != 0) {
    std::fprintf(stderr, "fuzz: cannot write %s\n", path.c_str());
    std::abort();
  }
}

std::string scratch_dir(const std::string& harness) {
  // The process id, zero-padded: the folder's name has the same length in
  // every run, so messages naming files in it do too (a run repeats
  // exactly with the same libFuzzer seed; scripts/fuzz.sh).
  char pid[16];
  std::snprintf(pid, sizeof pid, "%010ld", static_cast<long>(::getpid()));
  const fs::path dir = scratch_root() / ("gonio-fuzz-" + harness + "-" + pid);
  std::error_code ec;
  fs::remove_all(dir, ec);
  fs::create_directories(dir, ec);
  if (ec) {
    std::fprintf(stderr, "fuzz: cannot create %s: %s\n", dir.c_str(), ec.message().c_str());
    std::abort();
  }
  write((dir / "tilt.dat").string(), "1\n3\n0 45 90\n1 0.9 0.8\n");
  // Relative to the checkout, where scripts/fuzz.sh runs the harnesses: no
  // path of the checkout is compiled in, so that the binaries, and with
  // them the addresses a run sees, are the same in any clone.
  const fs::path curves = fs::path("samples") / "curves";
  write((dir / "profile.ies").string(), read_whole(curves / "downlight.ies"));
  write((dir / "profile.ldt").string(), read_whole(curves / "downlight.ldt"));
  static const std::string kept = dir.string();
  std::atexit([] {
    std::error_code ignored;
    fs::remove_all(kept, ignored);
  });
  return dir.string();
}

void finding(const std::string& what) {
  std::fprintf(stderr, "fuzz finding: %s\n", what.c_str());
  std::abort();
}

}  // namespace gonio::fuzz
