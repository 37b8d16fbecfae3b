// The CAD parts the CAD studies read: written by FreeCAD from
// tests/cad/make_parts.py into `dir` when `file` is not there yet (`large`:
// with the 10⁶-triangle lens array, GONIO_CAD_LARGE=1). Exits with a message
// when FreeCAD cannot make them.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "io/support/process.h"

namespace gonio::bench {

inline void make_cad_parts(const std::filesystem::path& dir, const std::string& file, bool large) {
  namespace fs = std::filesystem;
  if (fs::exists(dir / file)) return;
  fs::create_directories(dir);
  setenv("GONIO_CAD_OUT", dir.c_str(), 1);
  if (large) setenv("GONIO_CAD_LARGE", "1", 1);
  Result<io::ProcessOutput> made = io::run_program(
      {"freecadcmd", (fs::path(GONIO_SOURCE_DIR) / "tests" / "cad" / "make_parts.py").string()},
      std::chrono::seconds(600), std::size_t{1} << 20, "install FreeCAD (Debian's freecad)");
  if (!made.ok() || !fs::exists(dir / file)) {
    std::fprintf(stderr, "FreeCAD could not make %s in %s\n", file.c_str(), dir.c_str());
    std::exit(1);
  }
}

}  // namespace gonio::bench
