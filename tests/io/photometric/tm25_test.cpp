#include "io/photometric/tm25.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <string>

#include "io/photometric/photometric_file.h"
#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

// parse_tm25, each input also a seed for the TM-25 fuzzer (scripts/fuzz.sh).
Result<Tm25RaySet> parse(const std::string& bytes, const std::string& name = "t.tm25ray") {
  test::offer_fuzz_seed("tm25", bytes);
  return parse_tm25(bytes, name);
}

const Finding* find(const std::vector<Finding>& w, const std::string& code) {
  for (const Finding& f : w)
    if (f.code == code) return &f;
  return nullptr;
}

template <class T>
void poke(std::string& bytes, std::size_t offset, T value) {
  std::memcpy(bytes.data() + offset, &value, sizeof(T));
}
template <class T>
T peek(const std::string& bytes, std::size_t offset) {
  T v;
  std::memcpy(&v, bytes.data() + offset, sizeof(T));
  return v;
}

// Four rays with every kind of item Gonio keeps apart: radiant flux,
// wavelength, Tri_Y, one additional item; one spectral table of 3 pairs,
// texts with non-ASCII characters.
Tm25RaySet rich_set() {
  Tm25RaySet s;
  Tm25Header& h = s.header;
  h.creation_method = 1;
  h.radiant_flux_w = 0.01f;
  h.luminous_flux_lm = 3.0f;
  h.created = "2026-12-02T22:00:00+00:00";
  h.start_position = 5;  // not the spectral identifier's 2: a swap of the two is seen
  h.spectrum = Tm25Spectrum::PerRayWavelength;
  h.min_wavelength_nm = 400.0f;
  h.max_wavelength_nm = 700.0f;
  h.radiant_flux = true;
  h.wavelength = true;
  h.light_source = "Test LED µ";
  h.manufacturer = "Gonio — test";
  h.equipment = "none";
  h.spectral_tables.push_back({{400.0f, 550.0f, 700.0f}, {0.1f, 1.0f, 0.2f}});
  h.additional_items = {"etendue"};
  h.additional_text = "free text ✓";
  s.columns = tm25_columns(h);
  EXPECT_EQ(s.columns.count, 9);
  // x y z kx ky kz phi lambda extra
  s.items = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0025f, 450.0f, 1.0f,  //
             1.0f, 2.0f, 0.5f, 0.6f, 0.0f, 0.8f, 0.0025f, 550.0f, 2.0f,  //
             -1.0f, 0.0f, 0.0f, 0.0f, 0.6f, 0.8f, 0.0025f, 600.0f, 3.0f, //
             0.0f, -3.0f, 0.1f, 0.0f, 0.0f, -1.0f, 0.0025f, 650.0f, 4.0f};
  return s;
}

TEST(Tm25, LayoutOfTheWrittenFile) {
  const Tm25RaySet s = rich_set();
  auto bytes = write_tm25(s);
  ASSERT_TRUE(bytes.ok()) << to_string(bytes.error());
  // 256 + 32 + 9 × 4000, one table of 4 + 3 × 8 = 28 bytes padded to 32,
  // one 512-byte item name, the text's 11 characters × 4 = 44 bytes padded
  // to 64, 4 rays × 9 × 4.
  EXPECT_EQ(bytes->size(), 36288u + 32u + 512u + 64u + 144u);
  EXPECT_EQ(bytes->substr(0, 4), "TM25");
  EXPECT_EQ(peek<std::int32_t>(*bytes, 4), 2013);
  EXPECT_EQ(peek<std::uint64_t>(*bytes, 20), 4u);
  EXPECT_EQ(bytes->substr(28, 25), "2026-12-02T22:00:00+00:00");
  EXPECT_EQ(peek<std::int32_t>(*bytes, 56), 5);   // ray start position
  EXPECT_EQ(peek<std::int32_t>(*bytes, 60), 2);   // spectral identifier
  EXPECT_EQ(peek<std::int32_t>(*bytes, 76), 1);   // tables
  EXPECT_EQ(peek<std::int32_t>(*bytes, 80), 1);   // additional items
  EXPECT_EQ(peek<std::int32_t>(*bytes, 84), 64);  // text bytes, padded to 32
  for (int f = 0; f < 8; ++f)  // position, direction, radiant, wavelength, luminous, Stokes, tristimulus, index
    EXPECT_EQ(peek<std::int32_t>(*bytes, 256 + 4 * f), f < 4 ? 1 : 0) << f;
  EXPECT_EQ(peek<char32_t>(*bytes, 288), U'T');
  EXPECT_EQ(peek<char32_t>(*bytes, 288 + 4 * 9), U'µ');
  EXPECT_EQ(peek<std::int32_t>(*bytes, 36288), 3);
  EXPECT_EQ(peek<float>(*bytes, 36288 + 4 + 8), 550.0f);
}

TEST(Tm25, RoundTripKeepsEverything) {
  const Tm25RaySet s = rich_set();
  auto bytes = write_tm25(s);
  ASSERT_TRUE(bytes.ok());
  auto r = parse(*bytes);
  ASSERT_TRUE(r.ok()) << to_string(r.error());
  ASSERT_EQ(r->findings.size(), 1u) << r->findings.back().message;
  const Tm25Header& h = r->header;
  EXPECT_EQ(h.creation_method, 1);
  EXPECT_EQ(h.radiant_flux_w, 0.01f);
  EXPECT_EQ(h.luminous_flux_lm, 3.0f);
  EXPECT_EQ(h.created, "2026-12-02T22:00:00+00:00");
  EXPECT_EQ(h.start_position, 5);
  EXPECT_EQ(h.spectrum, Tm25Spectrum::PerRayWavelength);
  EXPECT_EQ(h.light_source, "Test LED µ");
  EXPECT_EQ(h.manufacturer, "Gonio — test");
  EXPECT_EQ(h.additional_text, "free text ✓");
  ASSERT_EQ(h.additional_items.size(), 1u);
  EXPECT_EQ(h.additional_items[0], "etendue");
  ASSERT_EQ(h.spectral_tables.size(), 1u);
  EXPECT_EQ(h.spectral_tables[0].weight[2], 0.2f);
  EXPECT_EQ(r->items, s.items);
  EXPECT_EQ(r->ray_count(), 4u);
  EXPECT_NEAR(r->total_radiant_flux_w(), 0.01, 1e-9);
  // Per-ray spectra: luminous flux from the header's mean efficacy, said so.
  EXPECT_NEAR(r->efficacy_lm_per_w, 300.0, 1e-3);
  EXPECT_NEAR(r->total_luminous_flux_lm(), 3.0, 1e-6);
  ASSERT_NE(find(r->findings, "tm25-luminous-from-header"), nullptr);
  // Written again: the same bytes.
  auto again = write_tm25(*r);
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(*again, *bytes);
}

// Where the blocks of a TM-25 file lie by the reference reader's rules
// (Julius Muschaweck's TM25RaySetTools, TM25_impl.h ReadHeader, public
// domain), independent of Gonio's reader: the additional text block's size
// (4.7.1.15, byte 84) must be a non-negative multiple of 32, the spectral
// tables (4.7.4) are padded to 32 bytes, 512 bytes per additional item name
// (4.7.5), then the text, then the rays. `error` says what it refuses.
struct ReferenceLayout {
  std::string error;
  std::size_t text_at = 0, text_bytes = 0, rays_at = 0;
};
ReferenceLayout reference_layout(const std::string& b) {
  ReferenceLayout l;
  if (b.size() < kTm25FixedBytes) return {"short", 0, 0, 0};
  const auto tables = peek<std::int32_t>(b, 76), items = peek<std::int32_t>(b, 80), text = peek<std::int32_t>(b, 84);
  if (text < 0 || text % 32 != 0) return {"additional text block size must be nonnegative multiple of 32", 0, 0, 0};
  std::size_t pos = kTm25FixedBytes, used = 0;
  for (std::int32_t t = 0; t < tables; ++t) {
    const std::size_t bytes = 4 + 8 * static_cast<std::size_t>(peek<std::int32_t>(b, pos));
    pos += bytes;
    used += bytes;
  }
  if (used % 32 != 0) pos += 32 - used % 32;
  pos += 512 * static_cast<std::size_t>(items);
  l.text_at = pos;
  l.text_bytes = static_cast<std::size_t>(text);
  l.rays_at = pos + l.text_bytes;
  return l;
}

// Issue 44: the additional text block is NUL-padded to a multiple of 32
// bytes, as the reference reader requires, for texts of every length about
// a boundary (0, 1, 7, 8, 9 and 11 characters, non-ASCII among them); the
// text reads back, the rays lie where the reference reader looks for them.
// A writer that wrote the text unpadded (as before) is refused by the
// reference rules for any length that is not a multiple of 8 characters.
TEST(Tm25, TheAdditionalTextIsPaddedAsTheReferenceReaderRequires) {
  for (const std::string text : {"", "a", "µ-text", "12345678", "123456789", "free text ✓"}) {
    Tm25RaySet s = rich_set();
    s.header.additional_text = text;
    auto bytes = write_tm25(s);
    ASSERT_TRUE(bytes.ok()) << text;
    const ReferenceLayout l = reference_layout(*bytes);
    ASSERT_EQ(l.error, "") << text;
    std::u32string chars;
    for (std::size_t i = 0; i < l.text_bytes / 4 && peek<char32_t>(*bytes, l.text_at + 4 * i) != 0; ++i)
      chars += peek<char32_t>(*bytes, l.text_at + 4 * i);
    EXPECT_EQ(l.text_bytes, (chars.size() * 4 + 31) / 32 * 32) << text;  // the least padding
    for (std::size_t i = l.text_at + 4 * chars.size(); i < l.rays_at; ++i) EXPECT_EQ((*bytes)[i], '\0') << text;
    ASSERT_EQ(l.rays_at + s.items.size() * 4, bytes->size()) << text;
    EXPECT_EQ(peek<float>(*bytes, l.rays_at + 4 * 9 + 7 * 4), 550.0f) << text;  // ray 2's wavelength
    auto r = parse(*bytes);
    ASSERT_TRUE(r.ok()) << to_string(r.error());
    EXPECT_EQ(r->header.additional_text, text);
    EXPECT_EQ(find(r->findings, "tm25-header-value"), nullptr) << text;
  }
  // A file from a writer that left the text unpadded (44 bytes): read as
  // stated, with a warning; written again, padded.
  Tm25RaySet s = rich_set();
  std::string padded = write_tm25(s).value();
  const ReferenceLayout l = reference_layout(padded);
  std::string unpadded = padded;
  unpadded.erase(l.text_at + 44, 20);
  poke<std::int32_t>(unpadded, 84, 44);
  EXPECT_NE(reference_layout(unpadded).error, "");
  auto r = parse(unpadded);
  ASSERT_TRUE(r.ok()) << to_string(r.error());
  EXPECT_EQ(r->header.additional_text, "free text ✓");
  EXPECT_EQ(r->items, s.items);
  const Finding* warned = find(r->findings, "tm25-header-value");
  ASSERT_NE(warned, nullptr);
  EXPECT_NE(warned->message.find("multiple of 32"), std::string::npos) << warned->message;
  EXPECT_EQ(write_tm25(*r).value(), padded);
}

// Issue 34, cases 3 and 8 (the header layout and a ray's direction), a check
// independent of Gonio's writer and of the corpus file: a file put together
// byte by byte in the field order of another reader, Julius Muschaweck's
// TM25RaySetTools (TM25Library/TM25_impl.h, ReadHeader: 4.7.1.1 … 4.7.1.16,
// 4.7.2.1 … 4.7.2.8, 4.7.3.1 … 4.7.3.9; public domain), every field a value
// no other field has, so a reader that swaps or shifts two fields is seen.
// Its one ray points at C 30°, γ 40° of the ray file's frame (+x C0, −y
// C90, +z the nadir): direction (kx, ky, kz) = (sin 40° cos 30°,
// −sin 40° sin 30°, cos 40°); read as (ky, kx, kz) it would be C 300°-ish.
TEST(Tm25, HandBuiltFileReadsFieldByFieldInAnotherReadersOrder) {
  std::string b;
  const auto i32 = [&b](std::int32_t v) { b.append(reinterpret_cast<const char*>(&v), 4); };
  const auto u64 = [&b](std::uint64_t v) { b.append(reinterpret_cast<const char*>(&v), 8); };
  const auto f32 = [&b](float v) { b.append(reinterpret_cast<const char*>(&v), 4); };
  const auto utf32 = [&b](const std::u32string& text, std::size_t bytes) {
    const std::size_t start = b.size();
    for (char32_t c : text) b.append(reinterpret_cast<const char*>(&c), 4);
    b.resize(start + bytes, '\0');
  };
  b += "TM25";                 // 4.7.1.1 file type
  i32(2013);                   // 4.7.1.2 version
  i32(1);                      // 4.7.1.3 creation method: measurement
  f32(12.5f);                  // 4.7.1.4 luminous flux [lm]
  f32(0.04f);                  // 4.7.1.5 radiant flux [W]
  u64(2);                      // 4.7.1.6 rays
  b += "2024-05-06T07:08:09+02:00";
  b.resize(28 + 28, '\0');     // 4.7.1.7 date, 28 bytes
  i32(3);                      // 4.7.1.8 ray start position
  i32(1);                      // 4.7.1.9 spectral identifier: one wavelength
  f32(555.0f);                 // 4.7.1.10 the wavelength [nm]
  f32(501.0f);                 // 4.7.1.11 minimum
  f32(602.0f);                 // 4.7.1.12 maximum
  i32(0);                      // 4.7.1.13 spectral tables
  i32(0);                      // 4.7.1.14 additional ray items
  i32(0);                      // 4.7.1.15 additional text bytes
  b.resize(256, '\0');         // 4.7.1.16 reserved
  for (std::int32_t flag : {1, 1, 1, 0, 1, 0, 0, 0}) i32(flag);  // 4.7.2.1-8: radiant and luminous flux
  const std::u32string texts[9] = {U"source µ", U"maker", U"modeller", U"ray filer", U"goniometer",
                                   U"camera", U"350 mA", U"more", U"ref"};
  for (const std::u32string& t : texts) utf32(t, 4000);  // 4.7.3.1-9
  ASSERT_EQ(b.size(), kTm25FixedBytes);
  const double g = 40.0 * std::numbers::pi / 180.0, c = 30.0 * std::numbers::pi / 180.0;
  const float k[3] = {static_cast<float>(std::sin(g) * std::cos(c)), static_cast<float>(-std::sin(g) * std::sin(c)),
                      static_cast<float>(std::cos(g))};
  for (float v : {1.0f, 2.0f, 3.0f, k[0], k[1], k[2], 0.03f, 9.0f}) f32(v);         // x y z kx ky kz Φe Tri_Y
  for (float v : {-4.0f, -5.0f, -6.0f, 0.0f, 0.0f, 1.0f, 0.01f, 3.5f}) f32(v);

  auto r = parse(b);
  ASSERT_TRUE(r.ok()) << to_string(r.error());
  for (const Finding& f : r->findings) ADD_FAILURE() << f.code << ": " << f.message;
  const Tm25Header& h = r->header;
  EXPECT_EQ(h.creation_method, 1);
  EXPECT_EQ(h.luminous_flux_lm, 12.5f);
  EXPECT_EQ(h.radiant_flux_w, 0.04f);
  EXPECT_EQ(h.created, "2024-05-06T07:08:09+02:00");
  EXPECT_EQ(h.start_position, 3);
  EXPECT_EQ(h.spectrum, Tm25Spectrum::SingleWavelength);
  EXPECT_EQ(h.wavelength_nm, 555.0f);
  EXPECT_EQ(h.min_wavelength_nm, 501.0f);
  EXPECT_EQ(h.max_wavelength_nm, 602.0f);
  EXPECT_TRUE(h.radiant_flux);
  EXPECT_FALSE(h.wavelength);
  EXPECT_TRUE(h.luminous_flux);
  EXPECT_EQ(h.light_source, "source µ");
  EXPECT_EQ(h.manufacturer, "maker");
  EXPECT_EQ(h.model_creator, "modeller");
  EXPECT_EQ(h.ray_file_creator, "ray filer");
  EXPECT_EQ(h.equipment, "goniometer");
  EXPECT_EQ(h.camera, "camera");
  EXPECT_EQ(h.operation, "350 mA");
  EXPECT_EQ(h.additional_info, "more");
  EXPECT_EQ(h.data_reference, "ref");
  ASSERT_EQ(r->ray_count(), 2u);
  EXPECT_EQ(r->columns.count, 8);
  const Vec3 p = r->position_mm(0), d = r->direction(0);
  EXPECT_EQ(p.x, 1.0);
  EXPECT_EQ(p.y, 2.0);
  EXPECT_EQ(p.z, 3.0);
  EXPECT_EQ(d.x, static_cast<double>(k[0])) << "kx";
  EXPECT_EQ(d.y, static_cast<double>(k[1])) << "ky";
  EXPECT_EQ(d.z, static_cast<double>(k[2])) << "kz";
  // Back to C and γ in the ray file's frame.
  EXPECT_NEAR(std::acos(d.z) * 180.0 / std::numbers::pi, 40.0, 1e-4);
  EXPECT_NEAR(std::atan2(-d.y, d.x) * 180.0 / std::numbers::pi, 30.0, 1e-4);
  EXPECT_EQ(r->position_mm(1).z, -6.0);
  EXPECT_DOUBLE_EQ(r->radiant_flux_w(0), static_cast<double>(0.03f));
  EXPECT_DOUBLE_EQ(r->luminous_flux_lm(0), 9.0);
  EXPECT_DOUBLE_EQ(r->luminous_flux_lm(1), 3.5);
  // Written again by Gonio: the same bytes.
  auto again = write_tm25(*r);
  ASSERT_TRUE(again.ok());
  EXPECT_TRUE(*again == b);
}

TEST(Tm25, LuminousFluxPerRayFromTriY) {
  // Other makers' files: Tri_Y (luminous flux) per ray, no radiant flux.
  std::vector<float> rays = {0, 0, 0, 0, 0, 1, 2.0f, 1, 1, 0, 0, 1, 0, 3.0f};
  Tm25RaySet s = make_luminous_ray_set(rays);
  EXPECT_EQ(s.columns.tri_y, 6);
  EXPECT_EQ(s.header.luminous_flux_lm, 5.0f);
  EXPECT_TRUE(std::isnan(s.header.radiant_flux_w));
  auto bytes = write_tm25(s);
  ASSERT_TRUE(bytes.ok());
  EXPECT_EQ(peek<std::int32_t>(*bytes, 256 + 8), 0);   // radiant flag
  EXPECT_EQ(peek<std::int32_t>(*bytes, 256 + 16), 1);  // luminous flag
  auto r = parse(*bytes);
  ASSERT_TRUE(r.ok()) << to_string(r.error());
  EXPECT_TRUE(r->has_luminous_flux());
  EXPECT_DOUBLE_EQ(r->luminous_flux_lm(1), 3.0);
  EXPECT_DOUBLE_EQ(r->total_luminous_flux_lm(), 5.0);
  EXPECT_TRUE(std::isnan(r->total_radiant_flux_w()));
  EXPECT_EQ(find(r->findings, "tm25-flux-mismatch"), nullptr);
}

std::string valid_bytes() {
  auto b = write_tm25(rich_set());
  EXPECT_TRUE(b.ok());
  return b.ok() ? *b : std::string();
}

// The error message of parsing `bytes`, "" if it parses.
std::string error_of(const std::string& bytes) {
  auto r = parse(bytes);
  return r.ok() ? std::string() : to_string(r.error());
}

TEST(Tm25, TruncatedAnywhereIsAClearError) {
  const std::string bytes = valid_bytes();
  for (std::size_t cut : {std::size_t{0}, std::size_t{3}, std::size_t{100}, std::size_t{300}, std::size_t{36287},
                          std::size_t{36290}, std::size_t{36330}, std::size_t{36900}, bytes.size() - 1}) {
    const std::string e = error_of(bytes.substr(0, cut));
    EXPECT_NE(e.find("t.tm25ray: byte "), std::string::npos) << cut << ": " << e;
    EXPECT_TRUE(e.find("truncated") != std::string::npos || e.find("ends inside") != std::string::npos ||
                e.find("left") != std::string::npos)
        << cut << ": " << e;
  }
}

TEST(Tm25, RayCountBeyondTheFileIsRefusedBeforeAllocating) {
  std::string bytes = valid_bytes();
  poke<std::uint64_t>(bytes, 20, std::uint64_t{1} << 62);
  const std::string e = error_of(bytes);
  EXPECT_NE(e.find("declares 4611686018427387904 rays of 36 bytes, but only 144 bytes follow"), std::string::npos)
      << e;
  poke<std::uint64_t>(bytes, 20, std::numeric_limits<std::uint64_t>::max());
  EXPECT_NE(error_of(bytes).find("declares"), std::string::npos);
  // Fewer rays than bytes: the rest is a warning.
  poke<std::uint64_t>(bytes, 20, 3);
  auto r = parse(bytes);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->ray_count(), 3u);
  ASSERT_NE(find(r->findings, "tm25-trailing-bytes"), nullptr);
}

TEST(Tm25, HostileHeaderFields) {
  const std::string good = valid_bytes();
  struct Case {
    std::size_t offset;
    std::int32_t value;
    const char* expected;
  };
  for (const Case& c : {Case{4, 2019, "byte 4: file version 2019"},
                        Case{60, 7, "byte 60: spectral data identifier 7"},
                        Case{76, -1, "byte 76: the number of spectral tables is -1"},
                        Case{76, 1 << 30, "spectral table 2"},
                        Case{80, -3, "byte 80: the number of additional ray items is -3"},
                        Case{80, 1 << 30, "additional ray items' names need"},
                        Case{84, 6, "byte 84: the additional text block's size is 6"},
                        Case{84, 1 << 30, "the additional text block"},
                        Case{256, 0, "byte 256: the position flag is 0"},
                        Case{264, 2, "byte 264: the radiant flux flag is 2"},
                        Case{264, 0, "byte 256: neither radiant nor luminous flux per ray"},
                        Case{268, 0, "spectral identifier 2 (a wavelength per ray) without the wavelength flag"},
                        Case{272, 1, "requires radiant flux and no luminous flux"},
                        Case{280, 1, "tristimulus values require"},
                        Case{284, 1, "spectrum index flag"},
                        Case{36288, 1 << 29, "spectral table 1 claims 536870912 pairs"},
                        Case{36288, 0, "spectral table 1 has 0 pairs"}}) {
    std::string bytes = good;
    poke<std::int32_t>(bytes, c.offset, c.value);
    const std::string e = error_of(bytes);
    EXPECT_NE(e.find(c.expected), std::string::npos) << c.offset << "=" << c.value << ": " << e;
  }
  std::string bytes = good;
  bytes[0] = 'X';
  EXPECT_NE(error_of(bytes).find("not a TM-25 ray file"), std::string::npos);
  bytes = good;
  poke<float>(bytes, 16, -1.0f);
  EXPECT_NE(error_of(bytes).find("byte 16: the total radiant flux is -1"), std::string::npos);
}

TEST(Tm25, HostileRays) {
  const std::string good = valid_bytes();
  const std::size_t rays_at = good.size() - 144;
  std::string bytes = good;
  poke<float>(bytes, rays_at + 36 + 4, std::numeric_limits<float>::quiet_NaN());  // ray 2, y
  std::string e = error_of(bytes);
  EXPECT_NE(e.find("byte " + std::to_string(rays_at + 40) + ": ray 2, item 2 is nan"), std::string::npos) << e;
  bytes = good;
  poke<float>(bytes, rays_at + 72 + 24, -0.5f);  // ray 3, radiant flux
  EXPECT_NE(error_of(bytes).find("ray 3 has a negative flux"), std::string::npos);
  bytes = good;
  for (int k = 3; k < 6; ++k) poke<float>(bytes, rays_at + 4 * static_cast<std::size_t>(k), 0.0f);
  EXPECT_NE(error_of(bytes).find("ray 1 has a zero direction vector"), std::string::npos);
  bytes = good;
  poke<float>(bytes, rays_at + 36 + 12, 1.2f);  // ray 2: (1.2, 0, 0.8), length 1.44
  auto r = parse(bytes);
  ASSERT_TRUE(r.ok());
  const Finding* f = find(r->findings, "tm25-direction-not-unit");
  ASSERT_NE(f, nullptr);
  EXPECT_NE(f->message.find("byte " + std::to_string(rays_at + 48) + ": 1 ray direction is not"), std::string::npos)
      << f->message;
  EXPECT_NEAR(length(r->direction(1)), 1.0, 1e-6);
  // Radiant flux that disagrees with the header.
  bytes = good;
  poke<float>(bytes, 16, 0.02f);
  r = parse(bytes);
  ASSERT_TRUE(r.ok());
  ASSERT_NE(find(r->findings, "tm25-flux-mismatch"), nullptr);
  EXPECT_NE(find(r->findings, "tm25-flux-mismatch")->message.find("-50.00 %"), std::string::npos);
}

TEST(Tm25, WriterRefusesInconsistentSets) {
  Tm25RaySet s = rich_set();
  s.items.pop_back();
  EXPECT_FALSE(write_tm25(s).ok());
  s = rich_set();
  s.header.luminous_flux = true;  // columns no longer match
  EXPECT_FALSE(write_tm25(s).ok());
}

TEST(Tm25, FileRoundTripIsAtomic) {
  test::TempDir dir;
  const std::string path = (dir / "a.tm25ray").string();
  ASSERT_TRUE(write_tm25_file(path, rich_set()).ok());
  auto r = read_tm25_file(path);
  ASSERT_TRUE(r.ok()) << to_string(r.error());
  EXPECT_EQ(r->items, rich_set().items);
  auto missing = read_tm25_file((dir / "none.tm25ray").string());
  ASSERT_FALSE(missing.ok());
}

TEST(Tm25, TheOpenerKnowsRayFilesAndNeedsTheFarFieldHook) {
  EXPECT_EQ(format_for_path("a/LED.TM25RAY"), PhotometricFormat::Tm25);
  const std::string bytes = valid_bytes();
  EXPECT_EQ(photometric_format_for_content(bytes), PhotometricFormat::Tm25);
  test::TempDir dir;
  const std::string path = (dir / "led.dat").string();
  test::write_file(path, bytes);
  // Without the caller's far-field hook (tools/run/ray_file_far_field.h) a ray
  // file is refused, saying why.
  auto r = read_photometric_file(path);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("a TM-25 ray file: its far field is not computed here"), std::string::npos);
  // With one, the file is its far field and keeps its rays.
  PhotometricReadOptions options;
  options.ray_set_far_field = [](const Tm25RaySet& set, const std::string&) -> Result<photometry::Distribution> {
    photometry::Distribution d;
    d.type = photometry::PhotometricType::C;
    d.symmetry = photometry::Symmetry::Rotational;
    d.absolute = true;
    d.horizontal_deg = {0.0};
    d.vertical_deg = {0.0, 90.0, 180.0};
    d.candela = {static_cast<double>(set.ray_count()), 0.0, 0.0};
    return d;
  };
  r = read_photometric_file(path, options);
  ASSERT_TRUE(r.ok()) << to_string(r.error());
  EXPECT_EQ(r->format, PhotometricFormat::Tm25);
  ASSERT_NE(r->ray_set, nullptr);
  EXPECT_EQ(r->ray_set->ray_count(), 4u);
  EXPECT_EQ(r->distribution.candela[0], 4.0);
  // Never written from a distribution.
  std::vector<Finding> warnings;
  EXPECT_FALSE(encode_photometric_file(r->distribution, PhotometricFormat::Tm25, {}, &warnings).ok());
}

}  // namespace
}  // namespace gonio::io
