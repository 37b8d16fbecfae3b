#include "tests/io/model/cad_parts.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include "io/support/content_hash.h"
#include "io/support/process.h"
#include "tests/support/test_support.h"

#ifndef GONIO_TEST_DATA_DIR
#error "GONIO_TEST_DATA_DIR must name the build's test-data folder"
#endif

namespace gonio::test {

namespace fs = std::filesystem;

fs::path cad_test_parts(std::string* why) {
  const fs::path dir = fs::path(GONIO_TEST_DATA_DIR) / "cad";
  const fs::path py = source_dir() / "tests" / "cad" / "make_parts.py";
  const fs::path tcl = source_dir() / "tests" / "cad" / "make_parts.tcl";
  const std::string stamp_text = io::content_hash_hex(read_file(py) + read_file(tcl));
  fs::create_directories(dir);
  const int lock = ::open((dir / ".lock").c_str(), O_CREAT | O_RDWR, 0644);
  if (lock >= 0) ::flock(lock, LOCK_EX);
  struct Unlock {
    int fd;
    ~Unlock() {
      if (fd >= 0) ::close(fd);
    }
  } unlock{lock};
  const fs::path stamp = dir / "stamp";
  std::error_code ec;
  if (fs::exists(stamp, ec) && read_file(stamp) == stamp_text) return dir;

  ScopedEnv out("GONIO_CAD_OUT", dir.c_str());
  // FreeCAD's and DRAW's exit codes say little (DRAW's batch mode exits 0
  // after a failed command): the files they were to write are the test.
  const auto limit = std::chrono::seconds(300);
  Result<io::ProcessOutput> fc = io::run_program({"freecadcmd", py.string()}, limit, std::size_t{1} << 20,
                                                 "install Debian's freecad (scripts/setup.sh)");
  if (!fc.ok() || !fs::exists(dir / "lamp.step") || !fs::exists(dir / "pcx_lens.igs")) {
    *why = "FreeCAD's freecadcmd could not make the CAD test parts: " +
           (fc.ok() ? io::last_lines(fc->out + fc->err, 400) : fc.error().message);
    return {};
  }
  Result<io::ProcessOutput> draw = io::run_program({"occt-draw", "-b", "-f", tcl.string()}, limit, std::size_t{1} << 20,
                                                   "install Debian's occt-draw and libocct-draw-dev (scripts/setup.sh)");
  if (!draw.ok() || !fs::exists(dir / "colours_inch.step") || !fs::exists(dir / "block.igs")) {
    *why = "OpenCASCADE's DRAW harness occt-draw could not make the CAD test parts: " +
           (draw.ok() ? io::last_lines(draw->out + draw->err, 400) : draw.error().message);
    return {};
  }
  write_file(stamp, stamp_text);
  return dir;
}

}  // namespace gonio::test
