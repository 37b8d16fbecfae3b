// EULUMDAT (.ldt) files: reader and writer.
//
// The format (Stockmar 1990, EULUMDAT/2 1998) is one field per line:
//   1 company  2 Ityp  3 Isym  4 Mc  5 Dc  6 Ng  7 Dg  8 measurement report
//   9 luminaire name  10 luminaire number  11 file name  12 date/user
//   13–15 luminaire length (or diameter), width (0: round), height [mm]
//   16–17 luminous area length (or diameter), width (0: round) [mm]
//   18–21 luminous area heights in the C0, C90, C180, C270 planes [mm]
//   22 DFF [%]  23 LORL [%]  24 conversion factor  25 measurement tilt [deg]
//   26 number n of lamp sets (1–20), then per set: 26a number of lamps,
//   26b type, 26c total flux [lm], 26d colour, 26e colour rendering,
//   26f wattage including ballast [W]
//   27 ten direct ratios (room index k = 0.6 … 5)
//   28 Mc C angles  29 Ng γ angles  30 intensities [cd/klm], plane by plane.
//
// How the file maps onto photometry::Distribution, and the choices made where
// implementations disagree:
//
// - Stored planes (field 30 holds planes Mc1…Mc2 of the C list, 1-based):
//     Isym 0: 1…Mc          all planes              Symmetry::None
//     Isym 1: 1…1           one plane               Symmetry::Rotational
//     Isym 2: 1…Mc/2+1      C0 … C180               Symmetry::C0_C180
//     Isym 3: 3Mc/4+1 … 3Mc/4+1+Mc/2, indices taken modulo Mc:
//                           C270 … C360=C0 … C90    Symmetry::C90_C270
//     Isym 4: 1…Mc/4+1      C0 … C90                Symmetry::Quadrant
//   Isym 3 follows the standard's Mc1/Mc2 definition literally, as
//   photometric-viewer and pyldt do: the first stored plane is C270, the
//   last C90. QLumEdit stores C90 … C180 … C270 instead, which read the
//   standard way turns the luminaire by 180°; LdtIsym3Order selects it for
//   files known to come from such a tool. No field tells the two apart. The
//   one real Isym 3 file at hand (a road luminaire among QLumEdit's
//   templates) read the standard way sends twice as much flux to the C270
//   half as to the C90 half, its peak at C190/C350, γ 65°: plausible only if
//   its maker put the street side at C270, so that file probably follows
//   QLumEdit's order. The model keeps the planes it defines for C90_C270,
//   C 90…270 ascending: each stored plane C is the mirror image 180° − C of
//   the plane the model holds.
//   Isym 2 needs Mc even, Isym 3 and 4 Mc divisible by 4, and the C list must
//   hold 0°, 90°, 180° and 270° at the indices these ranges imply.
//   Isym 0 with a single C-plane (Mc = 1) is read as rotationally symmetric,
//   with a warning: one plane says nothing about the others.
// - Ityp 0 ("point source without symmetry", EULUMDAT/2; the 1990 list has
//   1–3 only) is accepted and kept in `ldt_type_indicator`, so a round trip
//   keeps any Ityp 0–3. A mismatch between Ityp 1 and Isym 1 is a warning.
//   Writing a model without an Ityp (one read from IES) derives 1 for
//   rotational symmetry and 3 otherwise; 0 is never derived because several
//   readers reject it, 2 is never guessed.
// - Lamp sets are alternative equipments of one luminaire ("standard sets";
//   photometric-viewer's examples: single lamp, double lamp, alternative
//   lamp). The intensities refer to the first set: cd = cd/klm × Φ₁ / 1000 ×
//   conversion factor. The first set becomes `lamps[0]`, the others
//   `alternative_lamps`. Counts are stored positive. Field 26 holds 1–20
//   sets: a file that declares more is an error on that line, and the writer
//   writes the first 20 of a model that has more ("ldt-too-many-lamp-sets").
// - Absolute photometry: a negative lamp count in the first set. Its flux
//   field then holds the luminaire's measured flux Φ_lum and the intensities
//   are cd per 1000 lm of it (cd = value × Φ_lum / 1000 × conversion
//   factor), as photometric-viewer reads it and the Aardvark photometry
//   library documents it; the model gets absolute = true, lamps[0].flux_lm =
//   NaN. The writer recomputes Φ_lum
//   by integrating the distribution (photometry::total_flux_lm) and states it
//   to 6 significant digits, dividing by exactly that value, so only the
//   candela are kept exactly and rewriting a file gives the same bytes.
// - Conversion factor (field 24, "depending on measurement"): read as the
//   factor that turns the tabulated values into cd/klm, so it multiplies the
//   intensities; values other than 1 are reported as a note. A factor of 0,
//   which would erase the data, is read as 1 with a warning; a negative one
//   is an error. The writer always writes 1 and the intensities with the
//   factor applied, so readers that ignore the field still get them right.
// - Header strings become keywords (Distribution::keywords) so IES ⇄ LDT
//   conversion carries them: company → MANUFAC, measurement report → TEST,
//   luminaire name → LUMINAIRE, luminaire number → LUMCAT, date/user →
//   ISSUEDATE (LM-63-2019's date of the file; the LDT field dates the data
//   set, not the test), file name → _LDT_FILENAME (a user keyword, so it
//   survives a trip through IES). Empty fields give no keyword. Lamp types
//   go to lamps[i].type. The writer fills date/user from ISSUEDATE, else
//   from DATE; every other keyword is reported as a warning, never dropped
//   silently.
// - Dimensions are millimetres in the file and metres in the model.
//   EULUMDAT's lengths (luminaire, field 13; luminous area, field 16) lie
//   along C90–C270 and its widths along C0–C180, the model's length along
//   C0–C180 (LM-63's axes): the reader puts the file's length into width_m
//   and its width into length_m, the writer back (IES ⇄ LDT conversion keeps
//   each axis's extent on its axis). A
//   luminous area width of 0 means circular (width_m = length_m); non-zero
//   side heights make it RectangularWithSides or VerticalCylinder with
//   height_m the largest of the four, which are kept in side_height_m.
//   DFF, LORL, tilt and the direct ratios go to their model fields as read.
// - Text is Latin-1 (UTF-8 files are accepted too); lines end in CRLF, LF or
//   CR; numbers may use a decimal comma and carry surrounding blanks. A
//   numeric field that is empty is an error, never a silent 0.
// - Negative intensities (field 30) are read as 0 with one
//   "ldt-negative-intensity" warning that counts them and names the first
//   one's line, C and γ, as the IES reader does ("negative-intensity"): one
//   stray value does not cost the whole file.
//
// LM-63 fields without an EULUMDAT counterpart are reported, not written:
// TILT data ("ldt-tilt-dropped"), a ballast factor or ballast-lamp factor
// other than 1 ("ldt-ballast-factor"), the LM-63-2019 file generation type
// ("ldt-file-generation"), input watts that differ from the first lamp set's
// wattage ("ldt-input-watts"; input watts fill a wattage that is unknown).
// Direct ratios the model lacks (IES input) are computed with
// photometry::direct_ratios() (Gonio's stated room model, not CIE 52's
// tables) and said so in an "ldt-direct-ratios" note.
//
// Writer: one field per line, CRLF, Latin-1. Text longer than the standard's
// field lengths (78 characters; lamp type 24, colour 16, colour rendering 6;
// file name 8, read as a DOS 8.3 name, so 12 with the extension, because
// files give it as "BD0150.ldt") is truncated with a warning. Numbers are
// printed in plain decimal notation rounded to `significant_digits` (default
// 12), trailing zeros dropped: intensities read back differ from the model's
// by less than 1e-11 relative, and numbers read from a file with up to 12
// significant digits are written back digit for digit, so writing what was
// read gives the same bytes again. Negative intensities are refused. Isym, Mc, Dc
// (0 unless the C list is equidistant), Ng and Dg (likewise) are derived from
// the model. DFF and LORL come from the declared values, or are computed by
// integrating the distribution (photometry/flux.h) when the model has none
// (IES input).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "photometry/diagnostics.h"
#include "photometry/distribution.h"

namespace gonio::io {

// Largest counts accepted: C-planes every 0.25°, γ every 0.1°.
inline constexpr int kMaxLdtCPlanes = 1440;
inline constexpr int kMaxLdtGammaAngles = 1801;
// Most lines an EULUMDAT file can need (header with 20 lamp sets, both angle
// lists, every intensity), plus room for trailing notes. Longer input is
// refused before its lines are indexed, so hostile input cannot make the
// reader's memory grow beyond what the largest real file would need.
inline constexpr std::size_t kMaxLdtLines =
    std::size_t{kMaxLdtCPlanes} * kMaxLdtGammaAngles + kMaxLdtCPlanes + kMaxLdtGammaAngles + 1000;
// Largest .ldt file read_ldt() accepts [bytes]: every value of the largest
// file at 24 characters.
inline constexpr std::size_t kMaxLdtBytes = kMaxLdtLines * 24;
inline constexpr int kMaxLdtLampSets = 20;

// The keyword that carries the LDT file name field (11).
inline constexpr const char* kLdtFileNameKeyword = "_LDT_FILENAME";

// Which half circle an Isym 3 file stores, in file order (see above).
enum class LdtIsym3Order {
  C270_C0_C90,    // the standard's Mc1 = 3·Mc/4 + 1, Mc2 = Mc1 + Mc/2 (default)
  C90_C180_C270,  // QLumEdit
};

struct LdtFile {
  photometry::Distribution distribution;
  std::vector<Finding> findings;  // warnings and notes, with file and line
};

struct LdtReadOptions {
  LdtIsym3Order isym3_order = LdtIsym3Order::C270_C0_C90;
};

// Reads and parses a file (at most kMaxLdtBytes). Errors name the file, the
// line and what was expected there.
Result<LdtFile> read_ldt(const std::string& path, const LdtReadOptions& options = {});

// Parses the bytes of an .ldt file; `name` is used in messages.
Result<LdtFile> parse_ldt(std::string_view bytes, const std::string& name,
                          const LdtReadOptions& options = {});

struct LdtWriteOptions {
  int significant_digits = 12;  // 1…17; with 17 every number in the file reads back bit for bit
  LdtIsym3Order isym3_order = LdtIsym3Order::C270_C0_C90;
  int type_indicator = -1;  // Ityp 0–3 to write; −1: the model's, else derived
};

// The .ldt bytes for a Type C distribution (Types A and B must be resampled to
// Type C first: an error until that function exists). Errors: invalid model,
// relative photometry without a lamp set of positive flux, bad options.
// Everything the format cannot hold exactly (truncated text, keywords without
// an LDT field, lamp sets beyond 20, a symmetric grid Isym cannot express,
// values computed because the model lacks them) is appended to `warnings`
// (may be null). Write the result with io::write_file_atomic().
Result<std::string> write_ldt(const photometry::Distribution& distribution,
                              const LdtWriteOptions& options, std::vector<Finding>* warnings);

}  // namespace gonio::io
