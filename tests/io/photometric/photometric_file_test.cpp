#include "io/photometric/photometric_file.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "photometry/beam.h"
#include "photometry/flux.h"
#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

namespace fs = std::filesystem;
using photometry::Distribution;
using photometry::PhotometricType;
using photometry::Symmetry;

constexpr double kDeg = std::numbers::pi / 180.0;

bool has(const std::vector<Finding>& w, const std::string& code) {
  return std::any_of(w.begin(), w.end(), [&](const Finding& f) { return f.code == code; });
}

const Finding* find(const std::vector<Finding>& w, const std::string& code) {
  for (const Finding& f : w)
    if (f.code == code) return &f;
  return nullptr;
}

int entries(const fs::path& dir) {
  int n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++n;
  return n;
}

// I = I0 cosⁿ α about the beam axis on a `step` grid of H and V in
// −90…90°: Type B's axis is the nadir (photometric zero), Type A's the
// photometric horizontal +x. Either way the lobe lies in the grid's
// hemisphere and emits Φ = 2π I0 / (n + 1).
Distribution lobe(PhotometricType type, int n, double step, double i0_cd = 1000.0) {
  Distribution d;
  d.type = type;
  d.symmetry = Symmetry::None;
  for (double a = -90.0; a <= 90.0 + 1e-9; a += step) {
    d.horizontal_deg.push_back(a);
    d.vertical_deg.push_back(a);
  }
  for (double h : d.horizontal_deg)
    for (double v : d.vertical_deg)
      d.candela.push_back(i0_cd *
                          std::pow(std::max(0.0, std::cos(h * kDeg) * std::cos(v * kDeg)), n));
  d.absolute = true;
  d.lamps = {photometry::LampSet{}};
  return d;
}

double lobe_flux_lm(int n, double i0_cd = 1000.0) {
  return 2.0 * std::numbers::pi * i0_cd / (n + 1);
}

// A Type C downlight with relative photometry, C0-C180 symmetry.
Distribution downlight() {
  Distribution d;
  d.symmetry = Symmetry::C0_C180;
  for (double c = 0; c <= 180; c += 15) d.horizontal_deg.push_back(c);
  for (double g = 0; g <= 180; g += 5) d.vertical_deg.push_back(g);
  for (double c : d.horizontal_deg)
    for (double g : d.vertical_deg)
      d.candela.push_back(g < 90 ? 800.0 * std::cos(g * kDeg) * (1.0 + 0.2 * std::cos(c * kDeg))
                                 : 0.0);
  d.lamps = {photometry::LampSet{1, "LED", 3000.0, "", "", 25.0}};
  d.keywords = {{"MANUFAC", "Gonio tests"}, {"LUMCAT", "DL-1"}};
  return d;
}

TEST(PhotometricFile, ExtensionsNameAFormat) {
  EXPECT_EQ(format_for_path("a.ies"), PhotometricFormat::Ies);
  EXPECT_EQ(format_for_path("dir/A.IES"), PhotometricFormat::Ies);
  EXPECT_EQ(format_for_path("x.Ies"), PhotometricFormat::Ies);
  EXPECT_EQ(format_for_path("b.ldt"), PhotometricFormat::Ldt);
  EXPECT_EQ(format_for_path("/tmp/B.LDT"), PhotometricFormat::Ldt);
  EXPECT_EQ(format_for_path("lamp.txt"), std::nullopt);
  EXPECT_EQ(format_for_path("lamp"), std::nullopt);
  EXPECT_EQ(format_for_path("ies.d/lamp"), std::nullopt);
  EXPECT_EQ(format_for_path("lamp.ies.bak"), std::nullopt);
  EXPECT_STREQ(to_string(PhotometricFormat::Ies), "IES");
  EXPECT_STREQ(to_string(PhotometricFormat::Ldt), "EULUMDAT");
}

TEST(PhotometricFile, ReadsEitherFormatAndNamesTheFileOnErrors) {
  test::TempDir dir;
  const Distribution d = downlight();
  for (const char* name : {"a.ies", "b.LDT"}) {
    SCOPED_TRACE(name);
    const std::string path = (dir / name).string();
    ASSERT_TRUE(write_photometric_file(path, d, {}, nullptr).ok());
    auto r = read_photometric_file(path);
    ASSERT_TRUE(r.ok()) << to_string(r.error());
    const bool ies = std::string(name) == "a.ies";
    EXPECT_EQ(r->format, ies ? PhotometricFormat::Ies : PhotometricFormat::Ldt);
    EXPECT_EQ(r->ies_version.has_value(), ies);
    if (ies) {
      EXPECT_EQ(*r->ies_version, IesVersion::LM63_2019);
    }
    EXPECT_EQ(r->distribution.symmetry, Symmetry::C0_C180);
    EXPECT_NEAR(photometry::total_flux_lm(r->distribution), photometry::total_flux_lm(d),
                1e-9 * photometry::total_flux_lm(d));
    for (const Finding& f : r->findings) EXPECT_EQ(f.where.file, path);
  }

  test::write_file(dir / "c.txt", "IESNA:LM-63-2002\n");
  auto truncated = read_photometric_file((dir / "c.txt").string());  // IES by content
  ASSERT_FALSE(truncated.ok());
  EXPECT_EQ(truncated.error().where.file, (dir / "c.txt").string());
  test::write_file(dir / "notes.txt", "a shopping list\n");
  auto unknown = read_photometric_file((dir / "notes.txt").string());
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(unknown.error().where.file, (dir / "notes.txt").string());
  EXPECT_NE(unknown.error().message.find("'.txt'"), std::string::npos);
  EXPECT_NE(unknown.error().message.find(".ies"), std::string::npos);

  auto missing = read_photometric_file((dir / "missing.ldt").string());
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().where.file, (dir / "missing.ldt").string());

  test::write_file(dir / "junk.ies", std::string("\x7f"
                                                 "ELF\x02\x01\x01\0\0\0\0",
                                                 12));
  auto junk = read_photometric_file((dir / "junk.ies").string());
  ASSERT_FALSE(junk.ok());
  EXPECT_EQ(junk.error().where.file, (dir / "junk.ies").string());
}

TEST(PhotometricFile, ContentDecidesWhereTheExtensionNamesNoFormat) {
  EXPECT_EQ(photometric_format_for_content("IESNA:LM-63-2002\r\n[TEST] 1\r\n"), PhotometricFormat::Ies);
  EXPECT_EQ(photometric_format_for_content("\xEF\xBB\xBF  iesna91\n"), PhotometricFormat::Ies);
  EXPECT_EQ(photometric_format_for_content("IES:LM-63-2019\n"), PhotometricFormat::Ies);
  // LM-63-1986: no version line, labels, then TILT=.
  EXPECT_EQ(photometric_format_for_content("LUMINAIRE X\nLAMP Y\ntilt=NONE\n"), PhotometricFormat::Ies);
  EXPECT_EQ(photometric_format_for_content("Company\r\n1\r\n2\r\n24\r\n15\r\n19\r\n5\r\n"),
            PhotometricFormat::Ldt);
  EXPECT_EQ(photometric_format_for_content("Company\n 3 \n4\n0\n0,0\n37\n2.5\n"), PhotometricFormat::Ldt);
  // Numbers out of EULUMDAT's ranges, too few lines, prose, XML: nothing.
  EXPECT_EQ(photometric_format_for_content("Company\n4\n2\n24\n15\n19\n5\n"), std::nullopt);
  EXPECT_EQ(photometric_format_for_content("Company\n1\n5\n24\n15\n19\n5\n"), std::nullopt);
  EXPECT_EQ(photometric_format_for_content("Company\n1\n2\n24.5\n15\n19\n5\n"), std::nullopt);
  EXPECT_EQ(photometric_format_for_content("Company\n1\n2\n24\n"), std::nullopt);
  EXPECT_EQ(photometric_format_for_content("Dear reader,\nthis is not photometry.\n"), std::nullopt);
  EXPECT_EQ(photometric_format_for_content(""), std::nullopt);

  // The same bytes read under a name that says nothing give what the named
  // file gives; a decisive extension is never overruled by the content.
  test::TempDir dir;
  const Distribution d = downlight();
  ASSERT_TRUE(write_photometric_file((dir / "a.ies").string(), d, {}, nullptr).ok());
  ASSERT_TRUE(write_photometric_file((dir / "b.ldt").string(), d, {}, nullptr).ok());
  test::write_file(dir / "a.txt", test::read_file(dir / "a.ies"));
  test::write_file(dir / "b", test::read_file(dir / "b.ldt"));
  for (const auto& [named, unnamed] :
       {std::pair{"a.ies", "a.txt"}, std::pair{"b.ldt", "b"}}) {
    SCOPED_TRACE(unnamed);
    auto x = read_photometric_file((dir / named).string());
    auto y = read_photometric_file((dir / unnamed).string());
    ASSERT_TRUE(x.ok()) << to_string(x.error());
    ASSERT_TRUE(y.ok()) << to_string(y.error());
    EXPECT_EQ(y->format, x->format);
    EXPECT_EQ(format_label(*y), format_label(*x));
    EXPECT_EQ(y->distribution.candela, x->distribution.candela);
    EXPECT_EQ(y->distribution.horizontal_deg, x->distribution.horizontal_deg);
    EXPECT_EQ(detect_photometric_format((dir / unnamed).string()).value(), x->format);
  }
  EXPECT_EQ(format_label(*read_photometric_file((dir / "a.txt").string())), "IES LM-63-2019");
  EXPECT_EQ(format_label(*read_photometric_file((dir / "b").string())), "EULUMDAT");
  test::write_file(dir / "ldt-inside.ies", test::read_file(dir / "b.ldt"));
  auto as_ies = read_photometric_file((dir / "ldt-inside.ies").string());
  EXPECT_FALSE(as_ies.ok());  // read as IES, which it is not
  std::filesystem::create_directory(dir / "folder");
  auto folder = detect_photometric_format((dir / "folder").string());
  ASSERT_FALSE(folder.ok());
  EXPECT_NE(folder.error().message.find("directory"), std::string::npos);
}

TEST(PhotometricFile, TypeBIntoLdtIsResampledOntoTheStatedGrid) {
  // A 30° floodlight beam (cos²⁰) on a 2.5° Type B grid.
  const int n = 20;
  const Distribution b = lobe(PhotometricType::B, n, 2.5);
  const double flux_b = photometry::total_flux_lm(b);
  ASSERT_NEAR(flux_b, lobe_flux_lm(n), 1e-6 * lobe_flux_lm(n));

  std::vector<Finding> w;
  auto ldt = encode_photometric_file(b, PhotometricFormat::Ldt, {}, &w);
  ASSERT_TRUE(ldt.ok()) << ldt.error().message;
  const Finding* resampled = find(w, "type-c-resampled");
  ASSERT_NE(resampled, nullptr);
  EXPECT_EQ(resampled->severity, Severity::Warning);
  EXPECT_NE(resampled->message.find("C 0 to 360 every 5 deg"), std::string::npos)
      << resampled->message;
  EXPECT_NE(resampled->message.find("gamma 0 to 90 every 1 deg"), std::string::npos)
      << resampled->message;

  auto back = parse_ldt(*ldt, "b.ldt");
  ASSERT_TRUE(back.ok()) << to_string(back.error());
  const Distribution& c = back->distribution;
  EXPECT_EQ(c.type, PhotometricType::C);
  EXPECT_EQ(c.horizontal_count(), 72u);  // EULUMDAT lists C 0 … 355 (360 is C 0)
  EXPECT_EQ(c.vertical_count(), 91u);
  // The default grid keeps this beam's flux within 0.1 % (photometric_file.h).
  EXPECT_NEAR(photometry::total_flux_lm(c), flux_b, 1e-3 * flux_b);
  // The axis is a grid point of both: the peak stays where and what it was.
  EXPECT_NEAR(*std::max_element(c.candela.begin(), c.candela.end()), 1000.0, 1e-6);
  EXPECT_NEAR(c.at(0, 0), 1000.0, 1e-6);
  // Beam angle of cos²⁰: 2 acos(0.5^(1/20)) = 30.04°.
  const double beam = 2.0 * std::acos(std::pow(0.5, 1.0 / n)) / kDeg;
  EXPECT_NEAR(photometry::beam_angle(c, 0.0).angle_deg, beam, 0.2);
  EXPECT_NEAR(photometry::beam_angle(c, 90.0).angle_deg, beam, 0.2);

  // IES holds Type B as it is: no resampling, no warning about it.
  w.clear();
  auto ies = encode_photometric_file(b, PhotometricFormat::Ies, {}, &w);
  ASSERT_TRUE(ies.ok());
  EXPECT_FALSE(has(w, "type-c-resampled"));
  auto ies_back = parse_ies(*ies, "b.ies", "");
  ASSERT_TRUE(ies_back.ok());
  EXPECT_EQ(ies_back->distribution.type, PhotometricType::B);
  EXPECT_EQ(ies_back->distribution.candela.size(), b.candela.size());
}

TEST(PhotometricFile, ResamplingFluxErrorOnNarrowerBeamsAndCoarserGrids) {
  // The default grid against closed forms, beams from Lambertian (n = 1) to
  // 8° (n = 300), Type B on 2.5°: within 0.1 % (measured at most 3.1e-4).
  for (int n : {1, 5, 50, 300}) {
    SCOPED_TRACE(n);
    const Distribution b = lobe(PhotometricType::B, n, 2.5);
    auto ldt = encode_photometric_file(b, PhotometricFormat::Ldt, {}, nullptr);
    ASSERT_TRUE(ldt.ok());
    auto back = parse_ldt(*ldt, "b.ldt");
    ASSERT_TRUE(back.ok());
    EXPECT_NEAR(photometry::total_flux_lm(back->distribution), lobe_flux_lm(n),
                1e-3 * lobe_flux_lm(n));
  }
  // A γ step of 2.5° (photometry's own default) loses a narrow beam's shape
  // (γ is sampled, not averaged; measured 0.28 %): the reason the default
  // here is 1°.
  PhotometricWriteOptions coarse;
  coarse.type_c_grid.gamma_step_deg = 2.5;
  const Distribution narrow = lobe(PhotometricType::B, 300, 2.5);
  auto ldt = encode_photometric_file(narrow, PhotometricFormat::Ldt, coarse, nullptr);
  ASSERT_TRUE(ldt.ok());
  auto back = parse_ldt(*ldt, "b.ldt");
  ASSERT_TRUE(back.ok());
  EXPECT_GT(std::abs(photometry::total_flux_lm(back->distribution) / lobe_flux_lm(300) - 1.0),
            2e-3);
}

TEST(PhotometricFile, TypeAIntoLdtIsResampled) {
  // Type A's beam axis is the photometric horizontal: C 0, γ 90°.
  const int n = 10;
  const Distribution a = lobe(PhotometricType::A, n, 2.5);
  std::vector<Finding> w;
  auto ldt = encode_photometric_file(a, PhotometricFormat::Ldt, {}, &w);
  ASSERT_TRUE(ldt.ok()) << ldt.error().message;
  ASSERT_TRUE(has(w, "type-c-resampled"));
  auto back = parse_ldt(*ldt, "a.ldt");
  ASSERT_TRUE(back.ok());
  const Distribution& c = back->distribution;
  EXPECT_EQ(c.vertical_deg.front(), 0.0);
  EXPECT_EQ(c.vertical_deg.back(), 180.0);
  EXPECT_NEAR(photometry::total_flux_lm(c), lobe_flux_lm(n), 1e-3 * lobe_flux_lm(n));
  const auto peak = std::max_element(c.candela.begin(), c.candela.end()) - c.candela.begin();
  EXPECT_EQ(c.horizontal_deg[static_cast<std::size_t>(peak) / c.vertical_count()], 0.0);
  EXPECT_EQ(c.vertical_deg[static_cast<std::size_t>(peak) % c.vertical_count()], 90.0);
}

TEST(PhotometricFile, LateralTypeBBecomesC0C180) {
  Distribution b = lobe(PhotometricType::B, 8, 5.0);
  // Keep H ≥ 0 only: lateral symmetry.
  Distribution half = b;
  half.symmetry = Symmetry::Lateral;
  half.horizontal_deg.clear();
  half.candela.clear();
  for (std::size_t h = 0; h < b.horizontal_count(); ++h) {
    if (b.horizontal_deg[h] < 0) continue;
    half.horizontal_deg.push_back(b.horizontal_deg[h]);
    for (std::size_t v = 0; v < b.vertical_count(); ++v) half.candela.push_back(b.at(h, v));
  }
  auto ldt = encode_photometric_file(half, PhotometricFormat::Ldt, {}, nullptr);
  ASSERT_TRUE(ldt.ok());
  auto back = parse_ldt(*ldt, "lateral.ldt");
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back->distribution.symmetry, Symmetry::C0_C180);
  EXPECT_NEAR(photometry::total_flux_lm(back->distribution), photometry::total_flux_lm(b),
              2e-3 * photometry::total_flux_lm(b));
}

TEST(PhotometricFile, ResamplingOnRequestAndBadGrids) {
  const Distribution d = downlight();
  PhotometricWriteOptions options;
  options.always_resample = true;
  options.type_c_grid.c_step_deg = 30.0;
  options.type_c_grid.gamma_step_deg = 2.5;
  std::vector<Finding> w;
  auto ies = encode_photometric_file(d, PhotometricFormat::Ies, options, &w);
  ASSERT_TRUE(ies.ok());
  ASSERT_TRUE(has(w, "type-c-resampled"));
  auto back = parse_ies(*ies, "r.ies", "");
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back->distribution.horizontal_deg, (std::vector<double>{0, 30, 60, 90, 120, 150, 180}));
  EXPECT_EQ(back->distribution.vertical_count(), 73u);
  // Planes every 30° hold the input's values exactly (they are input planes),
  // γ every 2.5° interpolates linearly between 5° samples of a cosine.
  EXPECT_NEAR(photometry::total_flux_lm(back->distribution), photometry::total_flux_lm(d),
              1e-3 * photometry::total_flux_lm(d));

  // A step that does not divide the range: an error naming the grid, and
  // write_photometric_file leaves nothing behind.
  options.type_c_grid.c_step_deg = 7.0;
  auto bad = encode_photometric_file(d, PhotometricFormat::Ldt, options, nullptr);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("resample"), std::string::npos);
  test::TempDir dir;
  const Status s = write_photometric_file((dir / "bad.ldt").string(), d, options, nullptr);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().where.file, (dir / "bad.ldt").string());
  EXPECT_EQ(entries(dir.path()), 0);
}

TEST(PhotometricFile, FailedWritesLeaveNothingAndKeepWhatWasThere) {
  test::TempDir dir;
  Distribution no_lamps = downlight();
  no_lamps.lamps.clear();  // relative photometry without lamp flux: LDT refuses it
  const auto target = dir / "out.ldt";
  test::write_file(target, "previous contents");
  const Status refused = write_photometric_file(target.string(), no_lamps, {}, nullptr);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().where.file, target.string());
  EXPECT_EQ(test::read_file(target), "previous contents");
  EXPECT_EQ(entries(dir.path()), 1);

  EXPECT_FALSE(
      write_photometric_file((dir / "no-dir" / "x.ies").string(), downlight(), {}, nullptr).ok());
  EXPECT_FALSE(fs::exists(dir / "no-dir"));
  const Status unknown = write_photometric_file((dir / "x.csv").string(), downlight(), {}, nullptr);
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(entries(dir.path()), 1);

  // An invalid model is an error, not a stop.
  Distribution broken = downlight();
  broken.candela.pop_back();
  auto e = encode_photometric_file(broken, PhotometricFormat::Ies, {}, nullptr);
  ASSERT_FALSE(e.ok());
  EXPECT_NE(e.error().message.find("invalid"), std::string::npos);
}

}  // namespace
}  // namespace gonio::io
