// libFuzzer harness: the IES TM-33 reader (io::parse_tm33, XML through
// io/support/xml.cpp) on arbitrary bytes, and, for what it accepts, the plausibility
// checks, the flux integral and the TM-33 writer, whose output must parse
// again and, written once more, give the same bytes (a second round trip
// loses nothing). A crash, a sanitizer report or a broken round trip is a
// finding (scripts/fuzz.sh).
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "io/photometric/tm33.h"
#include "photometry/distribution.h"
#include "photometry/flux.h"
#include "photometry/validation.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace gonio;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  Result<io::Tm33File> r = io::parse_tm33(bytes, "fuzz.xml");
  if (!r.ok()) return 0;
  const photometry::Distribution& d = r->distribution;
  if (!photometry::validate(d).ok()) fuzz::finding("parse_tm33 returned an invalid distribution");
  (void)photometry::check(d);
  (void)photometry::total_flux_lm(d);
  const std::string text = io::write_tm33(d, nullptr);
  Result<io::Tm33File> again = io::parse_tm33(text, "fuzz-written.xml");
  if (!again.ok()) fuzz::finding("write_tm33 wrote a document parse_tm33 refuses: " + to_string(again.error()));
  if (io::write_tm33(again->distribution, nullptr) != text)
    fuzz::finding("write_tm33 -> parse_tm33 -> write_tm33 changed the document");
  return 0;
}
