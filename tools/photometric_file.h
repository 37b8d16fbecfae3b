// Reading a photometric file whatever its format, for the subcommands that
// take IES or EULUMDAT alike (plot, compare).
#pragma once

#include <string>
#include <vector>

#include "photometry/diagnostics.h"
#include "photometry/distribution.h"

namespace gonio::cli {

struct PhotometricFile {
  std::string path;
  std::string format;  // "IES LM-63-2019", "EULUMDAT", …
  photometry::Distribution distribution;
  std::vector<Finding> findings;  // the reader's
};

// By extension: .ies, .ldt (any case); otherwise by content (an IES version
// line or TILT= among the first lines means IES). Errors: unreadable files,
// an unknown format (named, with the extensions accepted), the reader's own
// (file and line).
Result<PhotometricFile> read_photometric_file(const std::string& path);

}  // namespace gonio::cli
