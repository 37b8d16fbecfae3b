// libFuzzer harness: the EULUMDAT reader (io::parse_ldt) on arbitrary bytes,
// with both Isym 3 orders (the first byte chooses), and, for what it accepts,
// the plausibility checks, the flux integral and the writer, whose output
// must parse again. A crash, a sanitizer report or a broken round trip is a
// finding (scripts/fuzz.sh).
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "io/photometric/ldt.h"
#include "photometry/distribution.h"
#include "photometry/flux.h"
#include "photometry/validation.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace gonio;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  io::LdtReadOptions options;
  // Seeds are whole files, whose first byte is text: the common order. A
  // mutated first byte with its high bit set tries QLumEdit's order.
  if (size > 0 && (data[0] & 0x80) != 0) options.isym3_order = io::LdtIsym3Order::C90_C180_C270;
  Result<io::LdtFile> r = io::parse_ldt(bytes, "fuzz.ldt", options);
  if (!r.ok()) return 0;
  const photometry::Distribution& d = r->distribution;
  if (!photometry::validate(d).ok()) fuzz::finding("parse_ldt returned an invalid distribution");
  (void)photometry::check(d);
  (void)photometry::total_flux_lm(d);
  Result<std::string> text = io::write_ldt(d, {}, nullptr);
  if (!text.ok()) return 0;  // e.g. relative photometry without lamp flux: an error, not a crash
  Result<io::LdtFile> again = io::parse_ldt(*text, "fuzz-written.ldt");
  if (!again.ok()) fuzz::finding("write_ldt wrote a file parse_ldt refuses: " + to_string(again.error()));
  return 0;
}
