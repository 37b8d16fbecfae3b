// libFuzzer harness: the IES LM-63 reader (io::parse_ies) on arbitrary bytes,
// and, for what it accepts, the plausibility checks, the flux integral and the
// writer, whose output must parse again. TILT=<file> resolves in a fixed
// folder holding one valid tilt file (fuzz_support.h). A crash, a sanitizer
// report or a broken round trip is a finding (scripts/fuzz.sh).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "io/photometric/ies.h"
#include "photometry/distribution.h"
#include "photometry/flux.h"
#include "photometry/validation.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace gonio;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  static const std::string dir = fuzz::scratch_dir("ies");
  Result<io::IesFile> r = io::parse_ies(bytes, "fuzz.ies", dir);
  if (!r.ok()) return 0;
  const photometry::Distribution& d = r->distribution;
  // What the reader returns is a valid model: anything else is a finding.
  if (!photometry::validate(d).ok()) fuzz::finding("parse_ies returned an invalid distribution");
  (void)photometry::check(d);
  (void)photometry::total_flux_lm(d);
  const std::string text = io::write_ies(d, {}, nullptr);
  Result<io::IesFile> again = io::parse_ies(text, "fuzz-written.ies", dir);
  if (!again.ok()) fuzz::finding("write_ies wrote a file parse_ies refuses: " + to_string(again.error()));
  return 0;
}
