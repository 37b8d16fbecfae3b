// Helpers of the TM-33 reader's two test files (tm33_test.cpp,
// tm33_dialects_test.cpp).
#pragma once

#include <string>
#include <vector>

#include "io/photometric/tm33.h"
#include "tests/support/test_support.h"

namespace gonio::io::tm33_test {

// parse_tm33, each document also a seed for the TM-33 fuzzer (scripts/fuzz.sh).
inline Result<Tm33File> parse(const std::string& document, const std::string& name) {
  test::offer_fuzz_seed("tm33", document);
  return parse_tm33(document, name);
}

// The first finding with this code, or null.
inline const Finding* find(const std::vector<Finding>& w, const std::string& code) {
  for (const Finding& f : w)
    if (f.code == code) return &f;
  return nullptr;
}

// A keyword's value, "<none>" where the distribution has none.
inline std::string keyword(const photometry::Distribution& d, const std::string& key) {
  const photometry::Keyword* k = d.find_keyword(key);
  return k ? k->value : "<none>";
}

}  // namespace gonio::io::tm33_test
