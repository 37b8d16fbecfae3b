// IES LM-63 photometric files: a reader for every version real files use and
// a writer for LM-63-2019 (default) and LM-63-2002.
//
// Reading
// - Versions: LM-63-1986 (no version line), 1991 ("IESNA91"), 1995
//   ("IESNA:LM-63-1995"), 2002 ("IESNA:LM-63-2002"), 2019 ("IES:LM-63-2019").
//   Other lines starting with "IESNA" or "IES:" are read by the year they
//   name (e.g. "IESNA95" as 1995) with a "nonstandard-version" warning, or as
//   2002 with an "unknown-version" warning when they name none.
// - Tolerated and kept: a UTF-8 byte-order mark, blank and indented lines,
//   lower-case keywords and TILT, label lines without brackets (1986 files;
//   kept as [OTHER]), [MORE] continuations (joined into the previous
//   keyword's value with '\n'), user keywords [_...], spaces, tabs and commas
//   between values, values wrapped across lines anywhere, LF, CRLF and CR line
//   ends, lines longer than 256 characters (warning), Latin-1 text (decoded
//   to UTF-8), a DOS end-of-file byte (0x1A).
// - Keywords: every one in `Distribution::keywords` in file order, keys upper
//   case without brackets. [LAMP] is also copied to `lamps[0].type`.
// - Numbers: the candela multiplier is applied (the model holds candela);
//   the ballast factor and the 1986–1995 ballast-lamp photometric factor are
//   kept, not applied. Lumens per lamp −1 (any negative value, with a warning
//   if not −1) means absolute photometry: `absolute = true`, lamp flux NaN.
//   One LampSet: count = number of lamps, flux = count × lumens per lamp.
//   Negative intensities are read as 0 with a "negative-intensity" warning.
// - TILT=NONE, TILT=INCLUDE and TILT=<file> (resolved relative to the
//   directory given; its data kept like INCLUDE with `tilt.kind = File`).
// - Type C horizontal ranges: one angle → rotational; 0–90 → quadrant;
//   0–180 → C0-C180; 0 to (180, 360] → none; 90–270 → C90-C270 (an
//   LM-63-1995 range: a "horizontal-range" warning in 2002/2019 files);
//   anything else is an error. Types A and B: H 0…90 → lateral symmetry,
//   from below 0 up to at most 90 → none (warning unless −90…90).
// - Luminous opening: units type 1 (feet) or 2 (metres), kept in
//   `opening.file_unit`, dimensions converted to metres. Signs encode the
//   shape. LM-63-2002 and -2019 use the 15-row table of LM-63-2019 §5.11
//   (W, L, H; D a diameter): point 0 0 0; rectangular W L 0; rectangular
//   with luminous sides W L H; circular −D −D 0; ellipse −W −L 0; vertical
//   cylinder −D −D H; vertical elliptical cylinder −W −L H; sphere −D −D −D;
//   ellipsoid −W −L −H; horizontal cylinder along the photometric horizontal
//   (C0, the length) −D L −D, elliptical −W L −H; horizontal cylinder
//   perpendicular to it (along the width) W −D −D, elliptical W −L −H;
//   vertical circle facing the photometric horizontal −D 0 −D; vertical
//   ellipse −W 0 −H. LM-63-1986…1995 files use the LM-63-1995 table:
//   circular −D 0 0; sphere −D 0 −D; vertical cylinder −D 0 H; horizontal
//   cylinder along the length 0 L −D, along the width W 0 −D; ellipse −W L H
//   or W −L H (a vertical elliptical cylinder when H > 0); ellipsoid −W L −H
//   or W −L −H. A pattern the version's table lacks is read by the other
//   table, else as a circle (one negative horizontal dimension, the other 0)
//   or a rectangle of the absolute values, with an "opening-shape" warning.
// - LM-63-2019 file generation type → `file_generation` (an unknown code:
//   warning, Undefined). 2002's "future use" value is expected to be 1.
// - Findings (warnings, with file:line): long-line, missing-keyword (2019
//   and 2002: TEST, TESTLAB, ISSUEDATE, MANUFAC; 1991/1995: TEST, MANUFAC),
//   unknown-keyword, label-line, more-without-keyword, trailing-data,
//   nonstandard-version, unknown-version, horizontal-range, vertical-range,
//   negative-intensity, absolute-flux, opening-shape, file-generation-type,
//   future-use.
//
// Bad input: an Error naming the file and line and what was expected there —
// empty files, binary data, missing TILT lines, missing TILT files (naming
// both files), non-numeric, NaN or infinite tokens, truncated data, counts
// that are negative, non-integral or larger than the rest of the file could
// hold (checked before anything is allocated), unsorted angles, angles out
// of range. Files larger than kMaxIesFileBytes are refused.
//
// Writing (LM-63-2019 by default, LM-63-2002 on request)
// - Lines end with CR LF (the standard's delimiter). Data lines hold at most
//   128 characters, 130 with CR LF: inside the 132 of LM-63-1991/1995 as
//   well as the 256 of later versions, so that old readers with fixed line
//   buffers cope. Keyword lines hold at most 254 (256 with CR LF); longer
//   values continue on [MORE] lines. Each list (vertical angles, horizontal
//   angles, each plane's candela values) starts on a new line.
// - Text is written as Latin-1; characters outside it become '?' (warning).
// - Numbers: at most 15 significant digits, fixed notation (scientific only
//   below 1e-10 or from 1e16), trailing zeros dropped. Any number that itself
//   has at most 15 significant digits is written exactly as read, so
//   IES → IES round trips are exact and repeated round trips are stable;
//   any other double changes by at most 5 parts in 10^15. The file
//   generation type is written with five decimals (1.00010).
// - Required keywords [TEST], [TESTLAB], [ISSUEDATE], [MANUFAC]: the
//   model's values, else [ISSUEDATE] from the options or a 1991/1995 [DATE],
//   else "not stated" (warning "default-keyword"). 2019 adds [FILEGENINFO]
//   (the model's, else the options', else "Written by Gonio <version>").
//   Other keywords follow in model order; those not defined by the target
//   version become user keywords "[_KEY]" (warning "keyword-renamed"),
//   except [FILEGENINFO] in 2002, written as [OTHER].
// - Type C is written with the smallest horizontal range its symmetry
//   allows: rotational → 0; quadrant → 0–90; C0-C180 → 0–180; none → as
//   stored (expanded to 0–360 with a warning if it does not start at 0 or
//   ends at or below 180, which LM-63 would read as a symmetry).
//   C90-C270 (valid only in LM-63-1995's 90–270 range) is expanded to the
//   full 0–360 (warning "symmetry-expanded"): a 0–180 range would mean the
//   other mirror plane, and rotating the frame would move C0.
// - What IES cannot carry becomes a warning, never a silent loss: several
//   lamp sets (merged into one: total count, total flux), EULUMDAT's
//   alternative lamp sets ("alternative-lamps"), lamp colour and colour
//   rendering, EULUMDAT-only fields ("ldt-only-field": declared LOR and DFF,
//   direct ratios, non-zero luminaire body dimensions, luminous-area side
//   heights other than the opening's height, a non-zero measurement tilt, a
//   type indicator Ityp other than the one an LDT writer derives: 1 for
//   rotational symmetry, else 3), a ballast-lamp photometric factor other than 1,
//   TILT=<file> (written as TILT=INCLUDE), unknown input watts (written as
//   0; the sum of the lamp sets' powers is used where known), Types A/B
//   without symmetry on H ≥ 0 only (read back as lateral symmetry).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "photometry/diagnostics.h"
#include "photometry/distribution.h"

namespace gonio::io {

enum class IesVersion { LM63_1986, LM63_1991, LM63_1995, LM63_2002, LM63_2019 };

// "LM-63-2019" etc.
const char* to_string(IesVersion version);

struct IesFile {
  photometry::Distribution distribution;
  IesVersion version = IesVersion::LM63_2019;
  std::vector<Finding> findings;  // format-level warnings, in file order
};

// Largest IES (or TILT) file accepted [bytes].
inline constexpr std::size_t kMaxIesFileBytes = std::size_t{64} << 20;

// Reads an IES file from disk; TILT=<file> is resolved relative to its
// directory. Errors name `path` (or the tilt file) and the line.
Result<IesFile> read_ies(const std::string& path);

// Parses IES bytes. `name` is used in errors and findings;
// TILT=<file> is resolved in `directory_for_tilt_files` (an error if empty).
Result<IesFile> parse_ies(std::string_view bytes, const std::string& name,
                          const std::string& directory_for_tilt_files);

struct IesWriteOptions {
  IesVersion version = IesVersion::LM63_2019;  // LM63_2019 or LM63_2002
  std::string issue_date;                      // [ISSUEDATE] when the model has none
  std::string file_generation_info;            // [FILEGENINFO] (2019) when the model has none
};

// The file text (Latin-1, CR LF). Requires photometry::validate(d).ok() and
// options.version LM63_2019 or LM63_2002. What IES cannot carry, and every
// default filled in, is appended to `warnings` (if not null); the caller
// writes the text atomically (io/support/file_io.h).
std::string write_ies(const photometry::Distribution& d, const IesWriteOptions& options,
                      std::vector<Finding>* warnings);

// LM-63-2019 file generation type codes (Table 2) and back; nullopt for a
// code the table lacks (compared at five decimals).
double file_generation_code(photometry::FileGenerationType type);
std::optional<photometry::FileGenerationType> file_generation_from_code(double code);

// A number as the writer prints it (see "Numbers" above).
std::string format_ies_number(double value);

}  // namespace gonio::io
