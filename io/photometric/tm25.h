// IES TM-25-13 ray files (".tm25ray"): near-field ray sets of a light source,
// read and written.
//
// Layout (TM-25-13 section 4.7; all numbers little-endian, int32, uint64 or
// IEEE float32; text UTF-32LE, NUL-padded):
// - 4.7.1 file header, 256 bytes: "TM25", version (2013), creation method
//   (0 simulation, 1 measurement), total luminous flux [lm] and radiant flux
//   [W] (float; NaN: not stated), ray count (uint64), creation date and time
//   (28 bytes ASCII, ISO 8601), ray start position (0 unknown … 7),
//   spectral data identifier (0 none, 1 one wavelength, 2 a wavelength per
//   ray, 3 one spectral table for all rays, 4 a spectral table per ray by
//   index), the single wavelength and the minimum and maximum wavelength
//   [nm], the number of spectral tables, of additional ray items and the size
//   of the additional text block [bytes] (a multiple of 32: the writer pads
//   the text with NULs; the reader warns of another size), then 168 reserved bytes.
// - 4.7.2 known data flags, 8 int32 (0 or 1): position and direction (always
//   1), radiant flux, wavelength, luminous flux (the Tri_Y column), Stokes
//   parameters, tristimulus (Tri_X and Tri_Z) and spectrum index.
// - 4.7.3 nine description texts of 1000 UTF-32 characters (4000 bytes):
//   light source, manufacturer, model creator, ray file creator, equipment,
//   camera, operation, additional information, data reference.
// - 4.7.4 the spectral tables: per table an int32 pair count and that many
//   (wavelength [nm], weight) float pairs; the block padded to 32 bytes.
// - 4.7.5 one 512-byte UTF-32 name per additional ray item.
// - 4.7.6 the additional text (UTF-32, NUL-padded to the size the header states).
// - 4.7.7 the rays: per ray, float32 items in this order, those the flags
//   declare: x y z [mm], kx ky kz (direction), radiant flux [W], wavelength
//   [nm], Tri_Y (luminous flux [lm]), S1 S2 S3 and the polarisation
//   ellipse's reference vector (3 items), Tri_X Tri_Z, spectrum index, then
//   the additional items.
//
// Reading (parse_tm25) checks what it reads and says where, by byte offset:
// a short file, a wrong signature or version, flags that are not 0 or 1 or
// contradict each other (the rules of 4.7.2), counts that do not fit the
// bytes that follow (checked before anything is allocated), NaN or infinite
// ray items, negative fluxes and zero directions are errors; directions that
// are not unit (|k| off 1 by more than 1e-3; every direction off by more than 1e-6 is normalised), header
// fluxes that disagree with the rays' sum by more than 1 %, trailing bytes
// and unusual header values are warnings ("tm25-..." codes, docs/formats.md).
//
// Luminous flux per ray: the Tri_Y column where the file has one; else the
// radiant flux times the header's efficacy Φv/Φe where the spectrum is the
// same for every ray (identifier 0, 1 or 3) and both header fluxes are
// stated; for per-ray spectra (2, 4) the same ratio as a mean, with a
// "tm25-luminous-from-header" note; with neither, luminous flux is unknown
// (has_luminous_flux() is false).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "photometry/diagnostics.h"
#include "photometry/vec3.h"

namespace gonio::io {

// The fixed parts: file header and flags, then the nine 4000-byte texts.
inline constexpr std::size_t kTm25FileHeaderBytes = 256;
inline constexpr std::size_t kTm25FlagsBytes = 32;
inline constexpr std::size_t kTm25TextBytes = 4000;
inline constexpr std::size_t kTm25FixedBytes = kTm25FileHeaderBytes + kTm25FlagsBytes + 9 * kTm25TextBytes;
// The largest file read: 16 GiB (about 600 million rays of 7 items).
inline constexpr std::size_t kMaxTm25Bytes = std::size_t{16} << 30;

// 4.7.1.9, the spectral data identifier.
enum class Tm25Spectrum : std::int32_t {
  None = 0,
  SingleWavelength = 1,
  PerRayWavelength = 2,
  OneTable = 3,
  TablePerRay = 4,
};

struct Tm25SpectralTable {
  std::vector<float> wavelength_nm;
  std::vector<float> weight;
};

struct Tm25Header {
  std::int32_t version = 2013;
  std::int32_t creation_method = 0;  // 0 simulation, 1 measurement
  float luminous_flux_lm = std::numeric_limits<float>::quiet_NaN();
  float radiant_flux_w = std::numeric_limits<float>::quiet_NaN();
  std::string created;  // ISO 8601, at most 28 bytes
  std::int32_t start_position = 0;
  Tm25Spectrum spectrum = Tm25Spectrum::None;
  float wavelength_nm = std::numeric_limits<float>::quiet_NaN();
  float min_wavelength_nm = std::numeric_limits<float>::quiet_NaN();
  float max_wavelength_nm = std::numeric_limits<float>::quiet_NaN();
  // 4.7.2.3-8: the optional ray items.
  bool radiant_flux = false;
  bool wavelength = false;
  bool luminous_flux = false;
  bool stokes = false;
  bool tristimulus = false;
  bool spectrum_index = false;
  // 4.7.3 (UTF-8 here).
  std::string light_source, manufacturer, model_creator, ray_file_creator, equipment, camera,
      operation, additional_info, data_reference;
  std::vector<Tm25SpectralTable> spectral_tables;
  std::vector<std::string> additional_items;  // names of the additional ray items
  std::string additional_text;
};

// Column of each ray item in a ray's floats; -1 where absent.
struct Tm25Columns {
  int radiant_flux = -1, wavelength = -1, tri_y = -1, stokes = -1, tri_x = -1, tri_z = -1,
      spectrum_index = -1, additional = -1;
  int count = 6;  // floats per ray
};
// The columns the flags declare, in 4.7.7's order.
Tm25Columns tm25_columns(const Tm25Header& header);

struct Tm25RaySet {
  Tm25Header header;
  Tm25Columns columns;
  std::vector<float> items;  // ray-major: ray i's items at [i * columns.count, (i + 1) * columns.count)
  // Lumens per watt of radiant flux where the luminous flux comes from the
  // header's ratio (see above); NaN where it does not.
  double efficacy_lm_per_w = std::numeric_limits<double>::quiet_NaN();
  std::vector<Finding> findings;  // warnings and notes of the reader

  std::size_t ray_count() const {
    return columns.count > 0 ? items.size() / static_cast<std::size_t>(columns.count) : 0;
  }
  const float* ray(std::size_t i) const { return items.data() + i * static_cast<std::size_t>(columns.count); }
  Vec3 position_mm(std::size_t i) const { return item_vec(i, 0); }
  Vec3 direction(std::size_t i) const { return item_vec(i, 3); }
  // Items first, first + 1 and first + 2 of ray i, widened to double.
  Vec3 item_vec(std::size_t i, std::size_t first) const {
    const float* r = ray(i) + first;
    return {static_cast<double>(r[0]), static_cast<double>(r[1]), static_cast<double>(r[2])};
  }
  bool has_luminous_flux() const { return columns.tri_y >= 0 || std::isfinite(efficacy_lm_per_w); }
  // [lm]; requires has_luminous_flux().
  double luminous_flux_lm(std::size_t i) const {
    return columns.tri_y >= 0 ? static_cast<double>(ray(i)[columns.tri_y])
                              : static_cast<double>(ray(i)[columns.radiant_flux]) * efficacy_lm_per_w;
  }
  // [W]; NaN without a radiant flux column.
  double radiant_flux_w(std::size_t i) const {
    return columns.radiant_flux >= 0 ? static_cast<double>(ray(i)[columns.radiant_flux])
                                     : std::numeric_limits<double>::quiet_NaN();
  }
  // Sums over the rays (double accumulation).
  double total_luminous_flux_lm() const;
  double total_radiant_flux_w() const;
};

// Whether the bytes start with the TM-25 signature "TM25".
bool looks_like_tm25(std::string_view bytes);

// Reads a TM-25-13 ray file's bytes; `name` is the file named in errors and
// findings ("NAME: byte OFFSET: message").
Result<Tm25RaySet> parse_tm25(std::string_view bytes, const std::string& name);

// Reads a file (at most kMaxTm25Bytes).
Result<Tm25RaySet> read_tm25_file(const std::string& path);

// The bytes of a ray set: the header as given with the ray count and the
// flags taken from `columns` (which must match items' layout); texts longer
// than the fields are cut at a character boundary. Errors: items not a whole
// number of rays, columns inconsistent with the header's flags.
Result<std::string> write_tm25(const Tm25RaySet& set);

// write_tm25 written atomically to `path`.
Status write_tm25_file(const std::string& path, const Tm25RaySet& set);

// A ray set of position, direction and luminous flux per ray (7 items,
// Tri_Y as the flux; spectrum None), the header's luminous flux the rays'
// sum and its radiant flux NaN: what Gonio writes for a simulated
// luminaire. `rays` holds x y z [mm], kx ky kz, flux [lm] per ray.
Tm25RaySet make_luminous_ray_set(std::vector<float> rays);

}  // namespace gonio::io
