// Photometric files of either format, chosen by file extension: what the
// command line reads, checks and converts when it does not care whether a
// file is IES LM-63 or EULUMDAT.
//
// - The format follows the extension alone, case-insensitive: ".ies" is IES
//   LM-63 (io/ies.h), ".ldt" EULUMDAT (io/ldt.h). Nothing else is guessed.
// - Writing converts what the target cannot hold as it is, and says so:
//   EULUMDAT holds Type C photometry only, so a Type A or B distribution
//   written as .ldt is resampled onto a regular Type C grid
//   (photometry::to_type_c, bilinear in the input's own angles) with a
//   "type-c-resampled" warning that states the grid and the flux before and
//   after. Everything else the target format cannot carry is reported by the
//   writers themselves (see io/ies.h and io/ldt.h), never dropped silently.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "io/ies.h"
#include "io/ldt.h"
#include "photometry/diagnostics.h"
#include "photometry/distribution.h"
#include "photometry/resample.h"

namespace gonio::io {

enum class PhotometricFormat { Ies, Ldt };

// "IES" or "EULUMDAT".
const char* to_string(PhotometricFormat format);

// The format an extension names (".ies", ".IES", ".ldt", ".Ldt", ...);
// nullopt for any other name.
std::optional<PhotometricFormat> format_for_path(std::string_view path);

struct PhotometricFile {
  PhotometricFormat format = PhotometricFormat::Ies;
  // IES only: the LM-63 version the file declared (or was read as).
  std::optional<IesVersion> ies_version;
  photometry::Distribution distribution;
  // Format-level warnings and notes of the reader, with file and line.
  std::vector<Finding> findings;
};

struct PhotometricReadOptions {
  LdtReadOptions ldt;  // the Isym 3 plane order of EULUMDAT input
};

// Reads an .ies or .ldt file. Errors name the file (and the line where the
// reader found the problem): an unknown extension, anything the readers
// refuse (missing, a directory, too large, binary, truncated, malformed).
Result<PhotometricFile> read_photometric_file(const std::string& path,
                                              const PhotometricReadOptions& options = {});

struct PhotometricWriteOptions {
  IesWriteOptions ies;  // LM-63 version and defaults of IES output
  LdtWriteOptions ldt;  // digits, Isym 3 order and Ityp of EULUMDAT output
  // The Type C grid a distribution is resampled onto when the target needs
  // it (Types A and B into EULUMDAT). The default, C every 5° and γ every 1°,
  // keeps the flux of cosⁿ beams from Lambertian down to 8° wide (n ≤ 300)
  // on a 2.5° Type B grid within 0.1 % (measured at most 3.1e-4,
  // tests/io/photometric_file_test.cpp); photometry's own default γ step of
  // 2.5° loses 0.8 % on the 8° beam. The bilinear interpolation in the
  // input's own grid dominates what is left: on a 5° Type B grid a
  // Lambertian lobe loses 0.12 % whatever the output grid.
  photometry::TypeCGrid type_c_grid = {5.0, 1.0, std::nullopt, false};
  // Resample onto type_c_grid whatever the input and target (a regular
  // Type C grid on request), not only where the target needs it.
  bool always_resample = false;
};

// The bytes of `d` in `format`. Warnings (what was converted, resampled, filled in or not carried)
// are appended to `warnings` if not null. Errors: an invalid distribution (photometry::validate), a
// resampling grid that to_type_c refuses, a distribution the LDT writer refuses (e.g. relative
// photometry without a lamp set of positive flux).
Result<std::string> encode_photometric_file(const photometry::Distribution& d,
                                            PhotometricFormat format,
                                            const PhotometricWriteOptions& options,
                                            std::vector<Finding>* warnings);

// encode_photometric_file() in the format of `path`'s extension, written
// atomically (io/file_io.h): on any error nothing is left at `path` that was
// not there before. Errors name `path`.
Status write_photometric_file(const std::string& path, const photometry::Distribution& d,
                              const PhotometricWriteOptions& options,
                              std::vector<Finding>* warnings);

}  // namespace gonio::io
