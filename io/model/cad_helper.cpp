// gonio-cad: reads and tessellates one STEP or IGES file with OpenCASCADE
// (io/model/step.h) for gonio, which runs it as a child process
// (io/model/cad.h) so that OpenCASCADE cannot crash or hang gonio itself.
//
//   gonio-cad MODEL OUT ERROR ANGULAR_DEG CHORDAL_RELATIVE CHORDAL_MIN_M CHORDAL_M EXACT_NORMALS
//   gonio-cad --write-step REQUEST OUT ERROR
//
// The second form writes STEP: REQUEST is io/model/step_export.h's text,
// OUT the STEP file; it prints the largest deviation of the B-spline
// profiles from the request's points [mm] on stdout.
//
// Writes the tessellated model (io/model/cad_model.h's binary form) to OUT
// and exits 0, or writes the error message to ERROR and exits 1 (2 for bad
// arguments). Nothing goes to the console: OpenCASCADE's messenger is
// silenced, and gonio reads only the two files. It ends with _Exit once the
// files are written: OpenCASCADE's global destructors (and, in sanitizer
// builds, the leak check of what its singletons hold) have nothing left to
// do for gonio.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "io/model/cad_model.h"
#include "io/model/step.h"
#include "io/support/file_io.h"

namespace {

bool number(const char* text, double& out) {
  char* end = nullptr;
  out = std::strtod(text, &end);
  return end && *end == '\0' && end != text;
}

int write_step(char** argv) {
  using namespace gonio;
  Result<std::string> text = io::read_file(argv[2], std::size_t{1} << 30);
  Result<io::StepExport> request =
      text.ok() ? io::parse_step_export(*text, argv[2]) : Result<io::StepExport>(text.error());
  double deviation = 0.0;
  Status written = request.ok() ? io::write_step_file(*request, argv[3], &deviation) : Status(request.error());
  if (!written.ok()) {
    (void)io::write_file_atomic(argv[4], written.error().message + "\n");
    std::_Exit(1);
  }
  std::printf("%.17g\n", deviation);
  std::fflush(stdout);
  std::_Exit(0);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace gonio;
  if (argc == 5 && std::string(argv[1]) == "--write-step") return write_step(argv);
  if (argc != 9) {
    std::fprintf(stderr, "usage: gonio-cad MODEL OUT ERROR ANGULAR_DEG CHORDAL_RELATIVE CHORDAL_MIN_M CHORDAL_M "
                         "EXACT_NORMALS (run by gonio)\n");
    return 2;
  }
  io::CadTessellation t;
  const std::string normals = argv[8];
  if (!number(argv[4], t.angular_deflection_deg) || !number(argv[5], t.chordal_relative) ||
      !number(argv[6], t.chordal_min_m) || !number(argv[7], t.chordal_m) || (normals != "0" && normals != "1")) {
    std::fprintf(stderr, "gonio-cad: malformed tessellation arguments\n");
    return 2;
  }
  t.exact_normals = normals == "1";
  Result<io::CadModel> model = io::read_cad_file(argv[1], t);
  if (!model.ok()) {
    (void)io::write_file_atomic(argv[3], model.error().message + "\n");
    std::_Exit(1);
  }
  if (Status s = io::write_file_atomic(argv[2], io::serialize_cad_model(*model)); !s.ok()) {
    (void)io::write_file_atomic(argv[3], "cannot write the tessellated model: " + s.error().message + "\n");
    std::_Exit(1);
  }
  std::_Exit(0);
}
