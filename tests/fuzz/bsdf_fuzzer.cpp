// libFuzzer harness: the measured-BSDF readers (io/materials/bsdf_file.h) on
// arbitrary bytes — BSDF XML (Klems matrices, tensor trees) where the input
// starts with '<', else a goniometer CSV table — and, for what they
// accept, the table's own promises: every incidence scatters at most what
// it receives, evaluate and albedo are finite and >= 0, and a sampled
// direction is a unit vector on the side its row's data lies. A crash, a
// sanitizer report or a broken promise is a finding (scripts/fuzz.sh).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "io/materials/bsdf_file.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace gonio;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  std::vector<Finding> findings;
  const bool xml = !bytes.empty() && bytes.front() == '<';
  Result<sim::TabulatedBsdf> r = xml ? io::read_bsdf_xml(bytes, "fuzz.xml", findings)
                                     : io::read_bsdf_csv(bytes, "fuzz.csv", findings);
  if (!r.ok()) return 0;
  const sim::TabulatedBsdf& t = *r;
  for (const sim::TabulatedBsdf::Side* side : {&t.front, &t.back})
    for (const sim::TabulatedBsdf::Row& row : side->rows)
      if (!(row.reflect_albedo + row.transmit_albedo <= 1.0 + 1e-6))
        fuzz::finding("a row scatters more than it receives after finish()");
  for (bool front : {true, false}) {
    for (double theta : {0.0, 33.0, 89.0}) {
      const double a = theta * 3.14159265358979323846 / 180.0;
      const Vec3 wi{-std::sin(a) * 0.6, -std::sin(a) * 0.8, std::cos(a)};
      const double albedo = t.albedo(front, wi);
      if (!(albedo >= 0.0 && albedo <= 1.0 + 1e-6)) fuzz::finding("albedo outside [0, 1]");
      for (double u : {0.0, 0.37, 0.999}) {
        const Vec3 wo = t.sample(front, wi, u, 1.0 - u, u, 0.5);
        const double len = std::sqrt(wo.x * wo.x + wo.y * wo.y + wo.z * wo.z);
        if (albedo > 0.0 && !(std::abs(len - 1.0) < 1e-9)) fuzz::finding("a sampled direction is not a unit vector");
        if (len > 0.0) {
          const double f = t.evaluate(front, wi, wo);
          if (!(std::isfinite(f) && f >= 0.0)) fuzz::finding("evaluate is negative or not finite");
        }
      }
    }
  }
  return 0;
}
