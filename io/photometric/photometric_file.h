// Photometric files of any format Gonio reads: the one way every subcommand
// (info, check, convert, plot, compare) opens a file when it does not care
// which format it is.
//
// - Reading: by extension first, case-insensitive: ".ies" is IES LM-63
//   (io/photometric/ies.h), ".ldt" EULUMDAT (io/photometric/ldt.h), ".xml" IES TM-33 (io/photometric/tm33.h,
//   whose reader then requires TM-33's root element), ".gldf" a GLDF
//   container (io/photometric/gldf.h) whose photometries are read by their content type, ".tm25ray" an
//   IES TM-25 ray file (io/photometric/tm25.h) whose far field the caller's
//   PhotometricReadOptions::ray_set_far_field computes. Where the extension
//   names no format (".txt", ".dat", none) the content decides
//   (photometric_format_for_content): "TM25" at the start a ray file, an IES version line or a TILT= line
//   makes it IES, TM-33's root element TM-33, the numeric header of EULUMDAT
//   makes it EULUMDAT; anything else is refused with an error naming the
//   file and the formats accepted.
// - Writing: by the output's extension alone (format_for_path).
// - Writing converts what the target cannot hold as it is, and says so:
//   EULUMDAT holds Type C photometry only, so a Type A or B distribution
//   written as .ldt is resampled onto a regular Type C grid
//   (photometry::to_type_c, bilinear in the input's own angles) with a
//   "type-c-resampled" warning that states the grid and the flux before and
//   after. Everything else the target format cannot carry is reported by the
//   writers themselves (see io/photometric/ies.h and io/photometric/ldt.h), never dropped silently.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "io/photometric/ies.h"
#include "io/photometric/ldt.h"
#include "io/photometric/tm25.h"
#include "io/photometric/tm33.h"
#include "photometry/diagnostics.h"
#include "photometry/distribution.h"
#include "photometry/resample.h"

namespace gonio::io {

// Tm25: an IES TM-25 ray file, read as its far field (never written from
// a distribution: encode_photometric_file refuses it).
enum class PhotometricFormat { Ies, Ldt, Tm33, Gldf, Tm25 };

// "IES", "EULUMDAT", "TM-33", "GLDF" or "TM-25".
const char* to_string(PhotometricFormat format);

// The format an extension names (".ies", ".IES", ".ldt", ".Ldt", ".xml", ...);
// nullopt for any other name.
std::optional<PhotometricFormat> format_for_path(std::string_view path);

// The format the first bytes of a file show, for files whose extension names
// none: GLDF when it is a ZIP archive ("PK\3\4"); TM-33 when it is XML with
// TM-33's root element (looks_like_tm33);
// IES when a line among the first 40 starts with "IESNA", "IES:" or
// "TILT=" (any case, after blanks and a UTF-8 BOM); EULUMDAT when lines 2 to
// 6 hold its header (Ityp 0-3, Isym 0-4, Mc 0-1440, Dc, Ng 0-1801 as
// numbers); nullopt otherwise.
std::optional<PhotometricFormat> photometric_format_for_content(std::string_view bytes);

// By extension, then by content where the extension names no format. Errors
// name the file: missing, a directory, unreadable, or not a format Gonio
// knows (with the extensions and contents accepted).
Result<PhotometricFormat> detect_photometric_format(const std::string& path);

struct PhotometricFile {
  // The format of the photometry itself: for a photometry inside a GLDF
  // container its own (IES, EULUMDAT or TM-33), with `container` set.
  PhotometricFormat format = PhotometricFormat::Ies;
  // GLDF only: the container's path and the photometry's id and entry.
  std::string container;         // "" unless read from a .gldf
  std::string container_entry;   // "ldc/lamp.ldt"
  std::string container_id;      // the Photometry id in product.xml
  // IES only: the LM-63 version the file declared (or was read as).
  std::optional<IesVersion> ies_version;
  // TM-33 only: TM-33-23 or ATLA S001 / TM-33-18.
  std::optional<Tm33Version> tm33_version;
  photometry::Distribution distribution;
  // TM-25 only: the ray set whose far field `distribution` is.
  std::shared_ptr<const Tm25RaySet> ray_set;
  // Format-level warnings and notes of the reader, with file and line.
  std::vector<Finding> findings;
};

// "IES LM-63-2019", "EULUMDAT", "TM-33-23": the format and version as messages and
// reports name them.
std::string format_label(const PhotometricFile& file);

struct PhotometricReadOptions {
  LdtReadOptions ldt;  // the Isym 3 plane order of EULUMDAT input
  // GLDF: the Photometry id (or archive entry, "ldc/x.ldt") that
  // read_photometric_file() reads; empty: the first. read_photometric_files()
  // then reads that one only.
  std::string gldf_photometry;
  // TM-25 ray files: their far field as a distribution. The binning lives in
  // sim/ (tools/run/ray_file_far_field.h gives it); where this is empty a ray
  // file is refused with an error saying so.
  std::function<Result<photometry::Distribution>(const Tm25RaySet&, const std::string& path)> ray_set_far_field;
};

// Every photometry a file holds: one for IES, EULUMDAT and TM-33, one per
// readable photometry of a GLDF container (in product.xml's order; each
// one's findings name "CONTAINER:ENTRY"). Errors as read_photometric_file's.
Result<std::vector<PhotometricFile>> read_photometric_files(const std::string& path,
                                                            const PhotometricReadOptions& options = {});

// The one photometry of a file; of a GLDF container the one
// `options.gldf_photometry` names (an error listing the ids where none
// matches), else its first, with an info finding "gldf-first-photometry"
// where it holds more.
// Reads a photometric file of any format (detect_photometric_format). Errors
// name the file (and the line where the reader found the problem): an
// unknown format, anything the readers refuse (missing, a directory, too
// large, binary, truncated, malformed).
Result<PhotometricFile> read_photometric_file(const std::string& path,
                                              const PhotometricReadOptions& options = {});

struct PhotometricWriteOptions {
  IesWriteOptions ies;  // LM-63 version and defaults of IES output
  LdtWriteOptions ldt;  // digits, Isym 3 order and Ityp of EULUMDAT output
  // The Type C grid a distribution is resampled onto when the target needs
  // it (Types A and B into EULUMDAT). The default, C every 5° and γ every 1°,
  // keeps the flux of cosⁿ beams from Lambertian down to 8° wide (n ≤ 300)
  // on a 2.5° Type B grid within 0.1 % (measured at most 3.1e-4,
  // tests/io/photometric/photometric_file_test.cpp); photometry's own default γ step of
  // 2.5° loses 0.8 % on the 8° beam. The bilinear interpolation in the
  // input's own grid dominates what is left: on a 5° Type B grid a
  // Lambertian lobe loses 0.12 % whatever the output grid.
  photometry::TypeCGrid type_c_grid = {5.0, 1.0, std::nullopt, false};
  // Resample onto type_c_grid whatever the input and target (a regular
  // Type C grid on request), not only where the target needs it.
  bool always_resample = false;
  // GLDF output: the format of the photometry inside (IES, EULUMDAT or
  // TM-33), its file name without extension (empty: the output's name, else
  // "luminaire"), and the creation time written (seconds since 1970; 0: now).
  PhotometricFormat gldf_photometry = PhotometricFormat::Ldt;
  std::string gldf_stem;
  std::int64_t gldf_created_unix = 0;
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
// atomically (io/support/file_io.h): on any error nothing is left at `path` that was
// not there before. Errors name `path`.
Status write_photometric_file(const std::string& path, const photometry::Distribution& d,
                              const PhotometricWriteOptions& options,
                              std::vector<Finding>* warnings);

}  // namespace gonio::io
