// libFuzzer harness: the STEP reader and tessellator (io::read_cad_file, in
// this process: OpenCASCADE's parser, XCAF transfer and BRepMesh) on
// arbitrary bytes written to a .step file, coarsely meshed so that an
// execution stays short. OpenCASCADE's libraries are Debian's, not
// instrumented: libFuzzer's coverage is of Gonio's code only, so it mutates
// OpenCASCADE's input mostly blind, and its memory errors show only where
// they crash. gonio itself runs this code in the helper process gonio-cad
// (io/model/cad.h), where a crash or hang is an error message; here each is
// a finding to report. What the reader accepts must be a sound model: every
// index in range, every coordinate finite, and its binary form must read
// back to the same bytes.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "io/model/cad_model.h"
#include "io/model/step.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace gonio;
  static const std::string path = fuzz::scratch_dir("step") + "/fuzz.step";
  fuzz::write(path, std::string_view(reinterpret_cast<const char*>(data), size));
  io::CadTessellation t;
  t.angular_deflection_deg = 30.0;
  t.chordal_relative = 0.05;
  Result<io::CadModel> r = io::read_cad_file(path, t, false);
  if (!r.ok()) return 0;
  for (const io::CadPart& p : r->parts)
    for (const io::CadSurface& s : p.surfaces) {
      for (std::uint32_t i : s.indices)
        if (i >= s.positions.size()) fuzz::finding("read_cad_file returned a triangle index out of range");
      for (const sim::Vec3f& v : s.positions)
        if (!(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)))
          fuzz::finding("read_cad_file returned a non-finite vertex");
      if (!s.normals.empty() && s.normals.size() != s.positions.size())
        fuzz::finding("read_cad_file returned normals and positions of different counts");
    }
  for (const io::CadPlacement& p : r->placements)
    if (p.part >= r->parts.size() || !p.to_world.finite()) fuzz::finding("read_cad_file returned a bad placement");
  const std::string bytes = io::serialize_cad_model(*r);
  Result<io::CadModel> back = io::parse_cad_model(bytes, "fuzz.bin");
  if (!back.ok()) fuzz::finding("parse_cad_model refused what serialize_cad_model wrote: " + to_string(back.error()));
  if (io::serialize_cad_model(*back) != bytes) fuzz::finding("the tessellated model's binary form does not round-trip");
  return 0;
}
