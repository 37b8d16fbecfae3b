// The CAD test parts (tests/cad/): STEP and IGES files written at test time
// by FreeCAD (make_parts.py, run with freecadcmd) and by OpenCASCADE's DRAW
// harness (make_parts.tcl, occt-draw), into build/test-data/cad/. They are
// made once per change of the two scripts (a stamp holds their hash), under
// a file lock, since ctest runs the tests as parallel processes.
#pragma once

#include <filesystem>
#include <string>

namespace gonio::test {

// The folder holding the parts, or empty with `why` saying which program is
// missing or failed (tests then call GONIO_MISSING(why)).
std::filesystem::path cad_test_parts(std::string* why);

}  // namespace gonio::test

// Ends the test (a skip, or a failure under CI=true) where the parts cannot
// be made; else declares `dir`, the folder holding them.
#define GONIO_REQUIRE_CAD_PARTS(dir)                          \
  std::string gonio_cad_why_;                                 \
  const std::filesystem::path dir = ::gonio::test::cad_test_parts(&gonio_cad_why_); \
  if (dir.empty()) GONIO_MISSING(gonio_cad_why_)
