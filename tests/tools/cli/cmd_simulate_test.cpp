// gonio simulate, run as a user would, on a small glTF model written here.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "io/outputs/exr.h"
#include "io/photometric/tm33.h"
#include "photometry/colour.h"
#include "io/support/zip.h"
#include "sim/shapes.h"
#include "tests/support/test_support.h"

namespace gonio {
namespace {

test::ProcessResult gonio(std::vector<std::string> args) {
  args.insert(args.begin(), GONIO_EXECUTABLE);
  return test::run_process(args);
}

std::string base64(const std::string& bytes) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) |
                       (static_cast<unsigned char>(bytes[i + 1]) << 8) |
                       static_cast<unsigned char>(bytes[i + 2]);
    out += table[v >> 18];
    out += table[(v >> 12) & 63];
    out += table[(v >> 6) & 63];
    out += table[v & 63];
  }
  if (i + 1 == bytes.size()) {
    const unsigned v = static_cast<unsigned char>(bytes[i]) << 16;
    out += table[v >> 18];
    out += table[(v >> 12) & 63];
    out += "==";
  } else if (i + 2 == bytes.size()) {
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) |
                       (static_cast<unsigned char>(bytes[i + 1]) << 8);
    out += table[v >> 18];
    out += table[(v >> 12) & 63];
    out += table[(v >> 6) & 63];
    out += '=';
  }
  return out;
}

// A white box shade 0.2 m wide, open at the bottom, with a 1000 lm point
// light inside: written with nlohmann::json and a data-URI buffer.
// With `glass`, the open box is clear glass: an open refractive volume,
// which the model checks refuse.
// With `sealed`, the box is closed: no light leaves it. `size_x`, `size_z`:
// the box's extent along world X and Z (its opening's sides).
std::string shade_model(double lamp_x = 0.0, double lamp_z = 0.0, bool glass = false, bool sealed = false,
                        double size_x = 0.2, double size_z = 0.2) {
  sim::Mesh box = sim::box(size_x, 0.2, size_z);
  // Drop the two triangles of the −Y face (the box's quads come in the
  // order +X, −X, +Y, −Y, +Z, −Z): light leaves downwards.
  if (!sealed) box.indices.erase(box.indices.begin() + 18, box.indices.begin() + 24);
  std::string bin;
  bin.append(reinterpret_cast<const char*>(box.positions.data()), box.positions.size() * sizeof(sim::Vec3f));
  const std::size_t positions_bytes = bin.size();
  bin.append(reinterpret_cast<const char*>(box.indices.data()), box.indices.size() * sizeof(std::uint32_t));
  using nlohmann::json;
  json g;
  g["asset"] = {{"version", "2.0"}};
  g["extensionsUsed"] = json::array({"KHR_lights_punctual"});
  if (glass) g["extensionsUsed"].push_back("KHR_materials_transmission");

  json light = {{"type", "point"}, {"intensity", 1000.0 / (4.0 * 3.141592653589793)}};
  g["extensions"]["KHR_lights_punctual"]["lights"] = json::array({light});
  g["scene"] = 0;
  g["scenes"] = json::array({json{{"nodes", json::array({0, 1})}}});

  json shade_node = {{"name", "shade"}, {"mesh", 0}};
  json lamp_node = {{"name", "lamp"}};
  if (lamp_x != 0.0 || lamp_z != 0.0) lamp_node["translation"] = json::array({lamp_x, 0.0, lamp_z});
  lamp_node["extensions"]["KHR_lights_punctual"]["light"] = 0;
  g["nodes"] = json::array({shade_node, lamp_node});

  json primitive = {{"indices", 1}, {"material", 0}};
  primitive["attributes"]["POSITION"] = 0;
  json mesh = {{"name", "shade"}, {"primitives", json::array({primitive})}};
  g["meshes"] = json::array({mesh});

  json material = {{"name", "white"}};
  material["pbrMetallicRoughness"] = {{"baseColorFactor", json::array({0.8, 0.8, 0.8, 1.0})},
                                      {"metallicFactor", 0.0},
                                      {"roughnessFactor", 1.0}};
  if (glass) {
    material["pbrMetallicRoughness"]["roughnessFactor"] = 0.0;
    material["extensions"]["KHR_materials_transmission"] = {{"transmissionFactor", 1.0}};
  }
  g["materials"] = json::array({material});

  json buffer = {{"byteLength", bin.size()},
                 {"uri", "data:application/octet-stream;base64," + base64(bin)}};
  g["buffers"] = json::array({buffer});
  json view0 = {{"buffer", 0}, {"byteOffset", 0}, {"byteLength", positions_bytes}, {"target", 34962}};
  json view1 = {{"buffer", 0},
                {"byteOffset", positions_bytes},
                {"byteLength", bin.size() - positions_bytes},
                {"target", 34963}};
  g["bufferViews"] = json::array({view0, view1});
  json positions = {{"bufferView", 0}, {"componentType", 5126}, {"count", box.positions.size()},
                    {"type", "VEC3"}};
  positions["min"] = json::array({-size_x / 2, -0.1, -size_z / 2});
  positions["max"] = json::array({size_x / 2, 0.1, size_z / 2});
  json indices = {{"bufferView", 1}, {"componentType", 5125}, {"count", box.indices.size()},
                  {"type", "SCALAR"}};
  g["accessors"] = json::array({positions, indices});
  return g.dump();
}

TEST(Simulate, WritesTheFarFieldAndAReportThatCloses) {
  test::TempDir dir;
  const auto model = dir / "shade.gltf";
  test::write_file(model, shade_model());
  const auto out = dir / "out";
  auto r = gonio({"simulate", model.string(), "--out", out.string(), "--photons", "20000", "--iterations", "3",
                  "--face-size", "16"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("iteration"), std::string::npos);  // no progress unless stderr is a terminal
  EXPECT_NE(r.out.find("60000 photons in 3 iterations"), std::string::npos) << r.out;

  const auto report = nlohmann::json::parse(test::read_file(out / "report.json"));
  EXPECT_EQ(report["photons_emitted"], 60000);
  EXPECT_EQ(report["photons_emitted"].get<std::uint64_t>(),
            report["photons_escaped"].get<std::uint64_t>() + report["photons_absorbed"].get<std::uint64_t>() +
                report["photons_cutoff"].get<std::uint64_t>());
  EXPECT_NEAR(report["emitted_lm"].get<double>(), 1000.0, 1e-9);
  EXPECT_TRUE(report["ledger"]["photons_close"].get<bool>());
  EXPECT_GT(report["photons_per_s"].get<double>(), 0.0);
  EXPECT_EQ(report["settings"]["face_size"], 16);
  EXPECT_EQ(report["program"]["name"], "gonio");

  auto image = io::read_exr((out / "farfield.exr").string());
  ASSERT_TRUE(image.ok()) << image.error().message;
  auto field = io::far_field_from_image(*image, "farfield.exr");
  ASSERT_TRUE(field.ok());
  EXPECT_EQ(field->total_photons(), report["photons_escaped"].get<std::uint64_t>());
  EXPECT_NEAR(field->total_flux_lm(), report["escaped_lm"].get<double>(), 1e-4 * 1000.0);
  // The box is open at the bottom only: more light goes down than up.
  double down = 0.0, up = 0.0;
  for (std::size_t t = 0; t < field->texel_count(); ++t) {
    const Vec3 d = field->grid().texel_direction(t);
    (d.y < 0 ? down : up) += field->flux_lm(t);
  }
  EXPECT_GT(down, 0.9 * field->total_flux_lm());
}

// --format gldf: STEM.gldf holds product.xml, the very LDT and IES files
// the run wrote, and the model as L3D; every command opens it.
// A spectral model (issue 24): a 2700 K lamp in a shade painted green by
// its spectral reflectance. report.json gains colour and colour over angle,
// farfield.exr X and Z, the LDT its colour temperature, the IES _CCT; light
// off the green walls pulls every direction above the Planckian locus
// (Duv > 0, where the bare lamp has 0); a grey model has none of it.
TEST(Simulate, SpectralModelsReportColourOverAngle) {
  test::TempDir dir;
  auto g = nlohmann::json::parse(shade_model());
  g["extensions"]["KHR_lights_punctual"]["lights"][0]["extras"]["gonio"]["spectrum"] = {{"blackbody_k", 2700.0}};
  g["materials"][0]["extras"]["gonio"]["spectral_reflectance"] = {
      {"wavelengths_nm", {380.0, 480.0, 530.0, 580.0, 780.0}}, {"values", {0.05, 0.2, 0.7, 0.2, 0.1}}};
  const auto model = dir / "green.gltf";
  test::write_file(model, g.dump());
  const auto out = dir / "out";
  auto r = gonio({"simulate", model.string(), "--out", out.string(), "--photons", "100000", "--iterations", "2",
                  "--gamma-step", "5", "--c-step", "15", "--format", "all,report,tm33"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = nlohmann::json::parse(test::read_file(out / "report.json"));
  ASSERT_TRUE(report.contains("colour")) << report.dump();
  // The radiant books close (the shade absorbs by wavelength).
  ASSERT_TRUE(report.contains("radiant"));
  const auto& w = report["radiant"];
  EXPECT_NEAR(report["ledger"]["radiant_imbalance_w"].get<double>(), 0.0, 1e-9 * w["emitted_w"].get<double>());
  EXPECT_GT(w["absorbed_w"].get<double>(), 0.0);
  EXPECT_EQ(w["escaped_spectrum"]["wavelengths_nm"].size(), 95u);
  // The datasheet shows the colour, Δu′v′ max with its chart, and the watts.
  const std::string sheet = test::read_file(out / "green.html");
  const auto fixed = [](double v, int decimals) {
    char b[32];
    std::snprintf(b, sizeof b, "%.*f", decimals, v);
    return std::string(b);
  };
  for (const std::string& part :
       {std::string("<h2>Colour</h2>"), fixed(report["colour"]["cct_k"].get<double>(), 0) + " K",
        fixed(report["colour"]["cie_x"].get<double>(), 4) + ", " + fixed(report["colour"]["cie_y"].get<double>(), 4),
        fixed(report["colour_over_angle"]["delta_uv_max"].get<double>(), 4), std::string("colour-chart"),
        fixed(w["emitted_w"].get<double>(), 4) + " W"})
    EXPECT_NE(sheet.find(part), std::string::npos) << part;
  const auto& c = report["colour"];
  EXPECT_GT(c["cct_k"].get<double>(), 1000.0);
  EXPECT_NEAR(c["cie_x"].get<double>() + c["cie_y"].get<double>(), 0.86, 0.1);
  const auto& coa = report["colour_over_angle"];
  ASSERT_EQ(coa["planes"].size(), 4u);
  EXPECT_EQ(coa["planes"][1]["c_deg"], 90.0);
  EXPECT_EQ(coa["threshold_fraction"], 0.1);
  EXPECT_GT(coa["planes"][0]["duv"][0].get<double>(), 0.003);
  EXPECT_GT(c["duv"].get<double>(), 0.003);
  EXPECT_GT(coa["delta_uv_max"].get<double>(), 0.0);
  EXPECT_EQ(coa["chart"], "green-colour.svg");
  EXPECT_NE(test::read_file(out / "green-colour.svg").find("<svg"), std::string::npos);
  auto image = io::read_exr((out / "farfield.exr").string());
  ASSERT_TRUE(image.ok());
  EXPECT_NE(image->find_float("X"), nullptr);
  EXPECT_NE(image->find_float("Z"), nullptr);
  EXPECT_NE(test::read_file(out / "green.ies").find("[_CCT] "), std::string::npos);
  EXPECT_NE(test::read_file(out / "green.ldt").find(" K\r\n"), std::string::npos);
  // TM-33 carries the luminaire's total spectrum (the escaped light's, from
  // the radiant books) and its CCT: read back by Gonio's reader, the
  // spectrum has the chromaticity the far field's X, Y, Z give. Two
  // estimators of the same light: the spectrum's, whose seldom drawn bands
  // pool with their neighbours, converges more slowly (here 1.3e-3 apart in
  // y at 2e5 photons; 1e-4 at 4e6, measured with gonio report on the file).
  auto tm33 = io::parse_tm33(test::read_file(out / "green.xml"), "green.xml");
  ASSERT_TRUE(tm33.ok()) << tm33.error().message;
  ASSERT_EQ(tm33->distribution.spectra.size(), 1u);
  const photometry::Spectrum& spectrum = tm33->distribution.spectra[0];
  EXPECT_EQ(spectrum.wavelength_nm.size(), 95u);
  EXPECT_TRUE(spectrum.normalized);
  const photometry::Chromaticity xy = photometry::chromaticity(photometry::tristimulus(photometry::sampled(spectrum)));
  EXPECT_NEAR(xy.x, c["cie_x"].get<double>(), 2e-3);
  EXPECT_NEAR(xy.y, c["cie_y"].get<double>(), 2e-3);
  std::printf("TM-33 spectrum x, y %.5f, %.5f; far field %.5f, %.5f\n", xy.x, xy.y, c["cie_x"].get<double>(),
              c["cie_y"].get<double>());
  // gonio report on that TM-33 file shows the colour of its spectrum.
  r = gonio({"report", (out / "green.xml").string(), "--out", (dir / "sheet.html").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string from_file = test::read_file(dir / "sheet.html");
  EXPECT_NE(from_file.find("<h2>Colour</h2>"), std::string::npos);
  EXPECT_NE(from_file.find("From the file's spectrum"), std::string::npos);
  ASSERT_FALSE(tm33->distribution.lamps.empty());
  EXPECT_EQ(tm33->distribution.lamps[0].color,
            std::to_string(std::lround(c["cct_k"].get<double>())) + " K");

  const auto grey = dir / "grey";
  test::write_file(dir / "shade.gltf", shade_model());
  r = gonio({"simulate", (dir / "shade.gltf").string(), "--out", grey.string(), "--photons", "20000",
             "--iterations", "1", "--face-size", "16"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(nlohmann::json::parse(test::read_file(grey / "report.json")).contains("colour"));
  EXPECT_EQ(io::read_exr((grey / "farfield.exr").string())->find_float("X"), nullptr);
}

TEST(Simulate, GldfHoldsTheLdtIesAndTheModel) {
  test::TempDir dir;
  const auto model = dir / "shade.gltf";
  test::write_file(model, shade_model());
  const auto out = dir / "out";
  auto r = gonio({"simulate", model.string(), "--out", out.string(), "--photons", "20000", "--iterations", "2",
                  "--face-size", "16", "--format", "ldt,ies,gldf"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("wrote " + (out / "shade.gldf").string()), std::string::npos) << r.out;
  auto entries = io::read_zip(test::read_file(out / "shade.gldf"), "shade.gldf");
  ASSERT_TRUE(entries.ok()) << to_string(entries.error());
  ASSERT_EQ(entries->size(), 4u);
  EXPECT_EQ((*entries)[0].name, "product.xml");
  EXPECT_EQ((*entries)[1].name, "ldc/shade.ldt");
  EXPECT_EQ((*entries)[1].bytes, test::read_file(out / "shade.ldt"));
  EXPECT_EQ((*entries)[2].name, "ldc/shade.ies");
  EXPECT_EQ((*entries)[2].bytes, test::read_file(out / "shade.ies"));
  EXPECT_EQ((*entries)[3].name, "geo/luminaire.l3d");
  auto l3d = io::read_zip((*entries)[3].bytes, "luminaire.l3d");
  ASSERT_TRUE(l3d.ok());
  ASSERT_EQ(l3d->size(), 2u);
  EXPECT_NE((*l3d)[0].bytes.find("<LightEmittingObject partName=\"lightEmittingObject\">"), std::string::npos);
  EXPECT_EQ((*l3d)[1].bytes.substr(0, 1), "#");  // the OBJ, with its header line
  const auto report = nlohmann::json::parse(test::read_file(out / "report.json"));
  bool listed = false;
  for (const auto& f : report["outputs"]["files"])
    if (f["format"] == "gldf") {
      listed = true;
      EXPECT_LT(std::abs(f["flux_difference"].get<double>()), 0.005);
    }
  EXPECT_TRUE(listed) << report["outputs"].dump();
  r = gonio({"check", (out / "shade.gldf").string()});
  EXPECT_NE(r.out.find("shade.gldf:ldc/shade.ldt: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("shade.gldf:ldc/shade.ies: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("2 files: "), std::string::npos) << r.out;
}

// The luminous opening of a simulated luminaire is where its light leaves:
// a shade 0.3 m along world X (C0) and 0.1 m along world Z (C90 is −Z),
// open at the bottom. The LDT carries it (EULUMDAT's length along
// C90–C270: field 16 = 100 mm, field 17 = 300 mm), the IES too (LM-63 width
// along 90–270), `info` gives a UGR table from it, and the GLDF's
// light-emitting object is that rectangle.
TEST(Simulate, FilesCarryTheOpeningTheLightLeavesThrough) {
  test::TempDir dir;
  const auto model = dir / "shade.gltf";
  test::write_file(model, shade_model(0.0, 0.0, false, false, 0.3, 0.1));
  const auto out = dir / "out";
  auto r = gonio({"simulate", model.string(), "--out", out.string(), "--photons", "20000", "--iterations", "2",
                  "--face-size", "16", "--format", "ldt,ies,gldf"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = gonio({"info", (out / "shade.ldt").string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["luminous_opening"]["shape"], "rectangular");
  // To the 0.1 mm the dimensions are rounded to (the exits lie on the walls).
  EXPECT_NEAR(j["luminous_opening"]["length_m"].get<double>(), 0.3, 2e-4);
  EXPECT_NEAR(j["luminous_opening"]["width_m"].get<double>(), 0.1, 2e-4);
  ASSERT_FALSE(j["ugr_table"].is_null()) << j["ugr_table_why"];
  EXPECT_EQ(j["ugr_table"]["rooms"].size(), 19u);
  const std::string ldt = test::read_file(out / "shade.ldt");
  std::vector<std::string> lines;
  for (std::size_t a = 0, b; a < ldt.size(); a = b + 1) {
    b = ldt.find('\n', a);
    if (b == std::string::npos) b = ldt.size();
    std::string line = ldt.substr(a, b - a);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    lines.push_back(line);
  }
  ASSERT_GT(lines.size(), 17u);
  EXPECT_NEAR(std::stod(lines[15]), 100.0, 0.2);  // EULUMDAT length: along C90–C270
  EXPECT_NEAR(std::stod(lines[16]), 300.0, 0.2);  // EULUMDAT width: along C0–C180
  r = gonio({"info", (out / "shade.ies").string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j["luminous_opening"]["length_m"].get<double>(), 0.3, 2e-4);
  EXPECT_NEAR(j["luminous_opening"]["width_m"].get<double>(), 0.1, 2e-4);
  auto entries = io::read_zip(test::read_file(out / "shade.gldf"), "shade.gldf");
  ASSERT_TRUE(entries.ok()) << to_string(entries.error());
  auto l3d = io::read_zip(entries->back().bytes, "luminaire.l3d");
  ASSERT_TRUE(l3d.ok());
  const std::string& structure = l3d->front().bytes;
  const auto at = structure.find("<Rectangle ");
  ASSERT_NE(at, std::string::npos) << structure;
  const std::string rect = structure.substr(at, structure.find("/>", at) - at);
  EXPECT_NE(rect.find("sizeX=\"0.3\""), std::string::npos) << rect;
  EXPECT_NE(rect.find("sizeY=\"0.1\""), std::string::npos) << rect;
}

TEST(Simulate, SameSeedSameBytesWithOneOrTwoThreads) {
  test::TempDir dir;
  const auto model = dir / "shade.gltf";
  test::write_file(model, shade_model());
  for (const char* t : {"1", "2"}) {
    auto r = gonio({"simulate", model.string(), "--out", (dir / t).string(), "--photons", "30000", "--iterations", "2",
                    "--threads", t, "--seed", "42", "--face-size", "16"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  EXPECT_EQ(test::read_file(dir / "1" / "farfield.exr"), test::read_file(dir / "2" / "farfield.exr"));
  auto a = nlohmann::json::parse(test::read_file(dir / "1" / "report.json"));
  auto b = nlohmann::json::parse(test::read_file(dir / "2" / "report.json"));
  EXPECT_EQ(a["meshes"], b["meshes"]);
  EXPECT_EQ(a["escaped_lm"], b["escaped_lm"]);
}

// --sampler sobol: photon i is Sobol' point i of the seed's scramble, so
// threads and iteration splits change no byte; it differs from random (the
// default), and report.json names it.
TEST(Simulate, SobolSamplerSameBytesWithOneOrTwoThreadsAndAnySplit) {
  test::TempDir dir;
  const auto model = dir / "shade.gltf";
  test::write_file(model, shade_model());
  struct Run {
    const char *name, *threads, *photons, *iterations, *sampler;
  };
  for (const Run& run : {Run{"1", "1", "30000", "2", "sobol"}, Run{"2", "2", "30000", "2", "sobol"},
                         Run{"whole", "2", "60000", "1", "sobol"}, Run{"random", "2", "60000", "1", "random"}}) {
    auto r = gonio({"simulate", model.string(), "--out", (dir / run.name).string(), "--photons", run.photons,
                    "--iterations", run.iterations, "--threads", run.threads, "--seed", "42", "--face-size", "16",
                    "--sampler", run.sampler, "--format", "exr,report"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  EXPECT_EQ(test::read_file(dir / "1" / "farfield.exr"), test::read_file(dir / "2" / "farfield.exr"));
  EXPECT_EQ(test::read_file(dir / "1" / "farfield.exr"), test::read_file(dir / "whole" / "farfield.exr"));
  EXPECT_NE(test::read_file(dir / "whole" / "farfield.exr"), test::read_file(dir / "random" / "farfield.exr"));
  auto a = nlohmann::json::parse(test::read_file(dir / "1" / "report.json"));
  auto b = nlohmann::json::parse(test::read_file(dir / "random" / "report.json"));
  EXPECT_EQ(a["settings"]["sampler"], "sobol");
  EXPECT_EQ(b["settings"]["sampler"], "random");
  EXPECT_EQ(gonio({"simulate", model.string(), "--out", (dir / "x").string(), "--sampler", "halton"}).exit_code, 2);
}

// --bvh-quality auto builds the quick tree for a run short for the model's
// size and the better one otherwise; the tree changes the speed, not the
// photons' paths: the same bytes either way.
TEST(Simulate, BvhQualityFollowsThePlannedWorkAndLeavesTheResultAlone) {
  test::TempDir dir;
  const auto model = dir / "shade.gltf";
  test::write_file(model, shade_model());  // 10 triangles
  struct Case {
    const char* name;
    std::vector<std::string> args;
    const char* quality;
    bool automatic;
  };
  const Case cases[] = {
      {"short", {"--photons", "2", "--iterations", "2"}, "low", true},  // 4 < 10 / 2
      {"long", {"--photons", "5", "--iterations", "1"}, "high", true},  // 5 = 10 / 2
      {"all", {"--photons", "3", "--iterations", "2"}, "high", true},   // every iteration's photons
      {"forced", {"--photons", "4", "--iterations", "1", "--bvh-quality", "high"}, "high", false},
      {"medium", {"--photons", "4", "--iterations", "1", "--bvh-quality", "medium"}, "medium", false},
  };
  for (const Case& c : cases) {
    // (Five photons cannot fill the IES grid: the flux check is waived.)
    std::vector<std::string> a = {"simulate", model.string(), "--out", (dir / c.name).string(), "--face-size", "16",
                                  "--format", "exr", "--flux-tolerance", "1"};
    a.insert(a.end(), c.args.begin(), c.args.end());
    auto r = gonio(a);
    ASSERT_EQ(r.exit_code, 0) << c.name << ": " << r.err;
    const auto report = nlohmann::json::parse(test::read_file(dir / c.name / "report.json"));
    EXPECT_EQ(report["setup"]["triangles_unique"], 10);
    EXPECT_EQ(report["settings"]["bvh_quality"], c.quality) << c.name;
    EXPECT_EQ(report["settings"]["bvh_quality_auto"], c.automatic) << c.name;
  }
  for (const char* q : {"low", "high"}) {
    auto r = gonio({"simulate", model.string(), "--out", (dir / q).string(), "--photons", "30000", "--iterations",
                    "1", "--face-size", "16", "--bvh-quality", q});
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  EXPECT_EQ(test::read_file(dir / "low" / "farfield.exr"), test::read_file(dir / "high" / "farfield.exr"));
}

// report.json times each setup phase and keeps the memory high-water mark;
// the phases are parts of the run, and the second run of an unchanged
// model takes the checks' result from the cache (--cache), --no-cache not.
TEST(Simulate, ReportsTheSetupPhasesAndCachesTheChecks) {
  test::TempDir dir;
  test::ScopedEnv epoch("SOURCE_DATE_EPOCH", "1764620000");  // the files' dates: the runs' bytes compare
  const auto model = dir / "shade.gltf";
  test::write_file(model, shade_model());
  const auto cache = dir / "cache";
  auto run = [&](const std::string& out, std::vector<std::string> extra) {
    std::vector<std::string> args = {"simulate", model.string(), "--out", (dir / out).string(),
                                     "--photons", "20000", "--iterations", "1", "--face-size", "16"};
    args.insert(args.end(), extra.begin(), extra.end());
    auto r = gonio(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nlohmann::json::parse(test::read_file(dir / out / "report.json"));
  };
  const auto cold = run("cold", {"--cache", cache.string()});
  const auto& setup = cold["setup"];
  double phases = 0.0;
  for (const char* key : {"load_s", "check_s", "validate_s", "emission_tables_s", "bvh_s", "shading_s"}) {
    ASSERT_TRUE(setup.contains(key)) << key;
    const double t = setup[key].get<double>();
    EXPECT_GE(t, 0.0) << key;
    phases += t;
  }
  EXPECT_GT(setup["load_s"].get<double>(), 0.0);
  EXPECT_GT(setup["bvh_s"].get<double>(), 0.0);
  // The phases and the tracing are disjoint parts of the command.
  EXPECT_LE(phases + cold["trace_s"].get<double>(), cold["wall_s"].get<double>());
  EXPECT_LE(setup["validate_s"].get<double>() + setup["emission_tables_s"].get<double>() +
                setup["bvh_s"].get<double>() + setup["shading_s"].get<double>(),
            cold["setup_s"].get<double>());
  EXPECT_EQ(setup["meshes"], 1);
  EXPECT_EQ(setup["meshes_from_cache"], 0);
  // At least what a process with Embree and TBB loaded holds.
  const auto peak = cold["max_rss_bytes"].get<std::uint64_t>();
  EXPECT_GT(peak, std::uint64_t{1} << 20);
  // A high-water mark only rises.
  EXPECT_LE(setup["max_rss_after_load_bytes"].get<std::uint64_t>(), setup["max_rss_after_checks_bytes"].get<std::uint64_t>());
  EXPECT_LE(setup["max_rss_after_checks_bytes"].get<std::uint64_t>(), peak);
  EXPECT_GT(setup["max_rss_after_load_bytes"].get<std::uint64_t>(), 0u);
  // One entry of checks, the resamplers of the files' grid and of the
  // latitude-longitude map (tools/run/resampler_cache.h), and the energy
  // table of the default material's glossy lobe (tools/run/glossy_energy_cache.h).
  ASSERT_TRUE(std::filesystem::is_directory(cache));
  const auto entries = [&] {
    std::vector<std::string> names;
    for (const auto& e : std::filesystem::directory_iterator(cache)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  };
  const std::vector<std::string> stored = entries();
  ASSERT_EQ(stored.size(), 4u);
  EXPECT_EQ(stored[0].rfind("glossy-energy-", 0), 0u);
  EXPECT_EQ(stored[1].rfind("mesh-check-", 0), 0u);
  EXPECT_EQ(stored[2].rfind("resampler-", 0), 0u);
  EXPECT_EQ(stored[3].rfind("resampler-", 0), 0u);

  const auto warm = run("warm", {"--cache", cache.string()});
  EXPECT_EQ(warm["setup"]["meshes_from_cache"], 1);
  EXPECT_EQ(warm["meshes"], cold["meshes"]);  // same seed, same ledger
  EXPECT_EQ(entries(), stored);
  // Resampled by stored rows: the same files.
  for (const char* file : {"shade.ies", "shade.ldt", "farfield-latlong.exr"})
    EXPECT_EQ(test::read_file(dir / "warm" / file), test::read_file(dir / "cold" / file)) << file;
  const auto none = run("none", {"--no-cache"});
  EXPECT_EQ(none["setup"]["meshes_from_cache"], 0);
  EXPECT_EQ(test::read_file(dir / "none" / "shade.ies"), test::read_file(dir / "cold" / "shade.ies"));
  EXPECT_EQ(gonio({"simulate", model.string(), "--out", (dir / "x").string(), "--cache", cache.string(),
                   "--no-cache"})
                .exit_code,
            2);
}

// The cache folder kept to --cache-limit after the run, least recently used
// entries first, this run's own entries (written or read: used now) last.
TEST(Simulate, KeepsTheCacheToItsLimitLeastRecentlyUsedFirst) {
  namespace fs = std::filesystem;
  test::TempDir dir;
  const auto model = dir / "shade.gltf";
  test::write_file(model, shade_model());
  const auto cache = dir / "cache";
  fs::create_directories(cache);
  const auto put_old = [&](const std::string& name, std::size_t bytes, int hours_ago) {
    test::write_file(cache / name, std::string(bytes, 'x'));
    fs::last_write_time(cache / name, fs::file_time_type::clock::now() - std::chrono::hours(hours_ago));
  };
  constexpr std::size_t kMiB = std::size_t{1} << 20;
  for (int i = 1; i <= 4; ++i) put_old("resampler-000000000000000" + std::to_string(i) + ".bin", kMiB, 50 - i);
  put_old("notes.txt", 3 * kMiB, 100);
  put_old(".mesh-check-0123456789abcdef.json.tmp42", 100, 2);  // an interrupted write's leftover
  auto run = [&](const std::string& out, const std::string& limit_mb) {
    auto r = gonio({"simulate", model.string(), "--out", (dir / out).string(), "--photons", "20000", "--iterations",
                    "1", "--face-size", "16", "--cache", cache.string(), "--cache-limit", limit_mb});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nlohmann::json::parse(test::read_file(dir / out / "report.json"));
  };
  const auto ours = [&] {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(cache)) {
      const std::string n = e.path().filename().string();
      if (n.rfind("mesh-check-", 0) == 0 || n.rfind("glossy-energy-", 0) == 0 ||
          (n.rfind("resampler-", 0) == 0 && n.find("00000000000000") == n.npos))
        names.push_back(n);
    }
    return names;
  };

  // 4 MiB of old entries and this run's four small ones (checks, two
  // resamplers, a glossy energy table) against 3 MiB: the two oldest go
  // (down to 2.7 MiB).
  const auto first = run("first", "3");
  EXPECT_EQ(first["cache"]["dir"], cache.string());
  EXPECT_EQ(first["cache"]["limit_bytes"], 3 * kMiB);
  EXPECT_EQ(first["cache"]["removed_entries"], 2);
  EXPECT_EQ(first["cache"]["removed_bytes"], 2 * kMiB);
  EXPECT_EQ(first["cache"]["entries"], 6);
  EXPECT_LE(first["cache"]["bytes"].get<std::uint64_t>(), 3 * kMiB - 3 * kMiB / 10);
  EXPECT_FALSE(fs::exists(cache / "resampler-0000000000000001.bin"));
  EXPECT_FALSE(fs::exists(cache / "resampler-0000000000000002.bin"));
  EXPECT_TRUE(fs::exists(cache / "resampler-0000000000000003.bin"));
  EXPECT_TRUE(fs::exists(cache / "resampler-0000000000000004.bin"));
  EXPECT_TRUE(fs::exists(cache / "notes.txt"));  // not Gonio's
  EXPECT_FALSE(fs::exists(cache / ".mesh-check-0123456789abcdef.json.tmp42"));
  const std::vector<std::string> stored = ours();
  ASSERT_EQ(stored.size(), 4u);

  // This run's entries made older than the rest: a run that reads them marks
  // them used, so the older of the others goes instead.
  for (const std::string& n : stored)
    fs::last_write_time(cache / n, fs::file_time_type::clock::now() - std::chrono::hours(200));
  const auto second = run("second", "2");
  EXPECT_EQ(second["setup"]["meshes_from_cache"], 1);
  EXPECT_EQ(second["cache"]["removed_entries"], 1);
  EXPECT_FALSE(fs::exists(cache / "resampler-0000000000000003.bin"));
  EXPECT_TRUE(fs::exists(cache / "resampler-0000000000000004.bin"));
  EXPECT_EQ(ours(), stored);

  // No limit: nothing goes; without a cache, the report says so.
  const auto third = run("third", "0");
  EXPECT_EQ(third["cache"]["removed_entries"], 0);
  EXPECT_EQ(third["cache"]["entries"], 5);
  auto r = gonio({"simulate", model.string(), "--out", (dir / "none").string(), "--photons", "20000",
                  "--iterations", "1", "--face-size", "16", "--no-cache"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(nlohmann::json::parse(test::read_file(dir / "none" / "report.json"))["cache"].is_null());
}

TEST(Simulate, BadInputsAndUsage) {
  test::TempDir dir;
  auto r = gonio({"simulate", (dir / "missing.gltf").string(), "--out", (dir / "o").string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("gonio: "), std::string::npos);
  EXPECT_NE(r.err.find("missing.gltf"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(dir / "o" / "report.json"));

  const auto model = dir / "shade.gltf";
  test::write_file(model, shade_model());
  EXPECT_EQ(gonio({"simulate", model.string()}).exit_code, 2);  // no --out
  EXPECT_EQ(gonio({"simulate", model.string(), "--out", "x", "--photons", "0"}).exit_code, 2);
  EXPECT_EQ(gonio({"simulate", model.string(), "--out", "x", "--threads", "-1"}).exit_code, 2);
  EXPECT_EQ(gonio({"simulate", model.string(), "--out", "x", "--bogus"}).exit_code, 2);

  // A model that loads but fails its checks: every problem printed, nothing written.
  test::write_file(dir / "open-glass.gltf", shade_model(0.0, 0.0, true));
  r = gonio({"simulate", (dir / "open-glass.gltf").string(), "--out", (dir / "g").string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("open-glass.gltf"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("nothing was simulated"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "g"));
  r = gonio({"bench", (dir / "open-glass.gltf").string(), "--out", (dir / "b").string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("nothing was benchmarked"), std::string::npos) << r.err;

  test::write_file(dir / "broken.gltf", "{ not json");
  r = gonio({"simulate", (dir / "broken.gltf").string(), "--out", (dir / "o").string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("broken.gltf"), std::string::npos);

  // An output directory that cannot be created.
  test::write_file(dir / "file", "x");
  r = gonio({"simulate", model.string(), "--out", (dir / "file" / "sub").string(), "--photons", "1000",
             "--iterations", "1"});
  EXPECT_EQ(r.exit_code, 1);
}

TEST(Simulate, PreviewFilesFollowEveryIteration) {
  test::TempDir dir;
  const auto model = dir / "shade.gltf";
  test::write_file(model, shade_model());
  const auto out = dir / "out";
  // Without filtering the preview is the raw far field, texel for texel.
  auto r = gonio({"simulate", model.string(), "--out", out.string(), "--photons", "20000", "--iterations", "2",
                  "--face-size", "16", "--preview", "--filter", "none"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto raw = io::read_exr((out / "farfield.exr").string());
  const auto preview = io::read_exr((out / "preview.exr").string());
  ASSERT_TRUE(raw.ok() && preview.ok());
  ASSERT_NE(raw->find_float("Y"), nullptr);
  ASSERT_NE(preview->find_float("Y"), nullptr);
  EXPECT_EQ(raw->find_float("Y")->values, preview->find_float("Y")->values);
  EXPECT_EQ(test::read_file(out / "preview.png").substr(1, 3), "PNG");
  const auto report = nlohmann::json::parse(test::read_file(out / "report.json"));
  EXPECT_NEAR(report["preview"]["flux_lm"].get<double>(), report["escaped_lm"].get<double>(),
              1e-6 * report["escaped_lm"].get<double>());

  // The default filter smooths but keeps the flux within a few percent.
  r = gonio({"simulate", model.string(), "--out", out.string(), "--photons", "20000", "--iterations", "1",
             "--face-size", "16", "--preview"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto filtered = nlohmann::json::parse(test::read_file(out / "report.json"));
  EXPECT_NEAR(filtered["preview"]["flux_lm"].get<double>(), filtered["escaped_lm"].get<double>(),
              0.05 * filtered["escaped_lm"].get<double>());

  EXPECT_EQ(gonio({"simulate", model.string(), "--out", out.string(), "--preview", "--adaptive", "--no-adaptive"})
                .exit_code,
            2);
  EXPECT_EQ(gonio({"simulate", model.string(), "--out", out.string(), "--preview", "--filter", "box"}).exit_code, 2);
}

TEST(Simulate, ThePreviewNeverFeedsBack) {
  // The same seed with and without the bilateral preview (filtered after
  // every iteration): the far field and the photometric files are the same
  // bytes, while the preview itself differs from the raw map.
  test::TempDir dir;
  const auto model = dir / "shade.gltf";
  test::write_file(model, shade_model());
  const std::vector<std::string> base = {"simulate", model.string(), "--photons", "20000", "--iterations", "3",
                                         "--face-size", "32", "--seed", "7", "--format", "ies,ldt,exr"};
  auto run = [&](const char* out, std::vector<std::string> extra) {
    std::vector<std::string> a = base;
    a.insert(a.end(), {"--out", (dir / out).string()});
    a.insert(a.end(), extra.begin(), extra.end());
    return gonio(a);
  };
  auto plain = run("plain", {});
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  auto previewed = run("previewed", {"--preview", "--filter", "bilateral"});
  ASSERT_EQ(previewed.exit_code, 0) << previewed.err;
  ASSERT_TRUE(std::filesystem::exists(dir / "previewed" / "preview.exr"));
  EXPECT_FALSE(std::filesystem::exists(dir / "plain" / "preview.exr"));
  for (const char* name : {"farfield.exr", "shade.ies", "shade.ldt"}) {
    const std::string a = test::read_file(dir / "plain" / name), b = test::read_file(dir / "previewed" / name);
    EXPECT_FALSE(a.empty()) << name;
    EXPECT_TRUE(a == b) << name << " differs with the preview on";
  }
  const auto raw = io::read_exr((dir / "previewed" / "farfield.exr").string());
  const auto preview = io::read_exr((dir / "previewed" / "preview.exr").string());
  ASSERT_TRUE(raw.ok() && preview.ok());
  ASSERT_NE(raw->find_float("Y"), nullptr);
  ASSERT_NE(preview->find_float("Y"), nullptr);
  EXPECT_NE(raw->find_float("Y")->values, preview->find_float("Y")->values);
}

nlohmann::json read_json(const std::filesystem::path& path) {
  return nlohmann::json::parse(test::read_file(path));
}

const nlohmann::json* file_entry(const nlohmann::json& report, const std::string& format) {
  for (const auto& f : report["outputs"]["files"])
    if (f["format"] == format) return &f;
  return nullptr;
}

TEST(SimulateOutputs, EveryFormatIsWrittenReadBackCleanAndCarriesTheEscapedFlux) {
  test::TempDir dir;
  const auto model = dir / "shade.gltf";
  test::write_file(model, shade_model());
  const auto out = dir / "out";
  auto r = gonio({"simulate", model.string(), "--out", out.string(), "--photons", "200000", "--iterations", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* name : {"shade.ies", "shade.ldt", "farfield.exr", "farfield-latlong.exr", "shade.svg", "report.json"})
    EXPECT_TRUE(std::filesystem::exists(out / name)) << name;
  EXPECT_NE(r.out.find("shade.ies"), std::string::npos) << r.out;

  const auto report = read_json(out / "report.json");
  const double escaped = report["escaped_lm"].get<double>();
  ASSERT_EQ(report["outputs"]["files"].size(), 5u);
  for (const auto& f : report["outputs"]["files"]) {
    EXPECT_TRUE(f["clean"].get<bool>()) << f.dump();
    EXPECT_TRUE(f["findings"].empty()) << f.dump();
    if (f["format"] == "plot") {
      EXPECT_TRUE(f["flux_lm"].is_null());
      continue;
    }
    EXPECT_NEAR(f["flux_lm"].get<double>(), escaped, 0.005 * escaped) << f.dump();
    EXPECT_NEAR(f["flux_difference"].get<double>(), f["flux_lm"].get<double>() / escaped - 1.0, 1e-12);
  }
  // The cube and the latlong map carry the flux exactly (float rounding).
  EXPECT_NEAR((*file_entry(report, "exr"))["flux_lm"].get<double>(), escaped, 1e-5 * escaped);
  EXPECT_NEAR((*file_entry(report, "latlong"))["flux_lm"].get<double>(), escaped, 1e-5 * escaped);
  EXPECT_TRUE(report["energy"]["passed"].get<bool>());
  EXPECT_NEAR(report["energy"]["lor"].get<double>(), escaped / report["emitted_lm"].get<double>(), 1e-12);
  // A square box around a centred lamp: both mirror planes, not rotational.
  EXPECT_EQ(report["outputs"]["symmetry"]["chosen"], "quadrant") << report["outputs"]["symmetry"].dump();
  EXPECT_NE(r.err.find("symmetry auto: quadrant"), std::string::npos) << r.err;

  // The IES file says what made it, and nothing invented.
  const std::string ies = test::read_file(out / "shade.ies");
  EXPECT_EQ(ies.rfind("IES:LM-63-2019\r\n", 0), 0u);
  EXPECT_NE(ies.find("[FILEGENINFO] Computer simulation by Gonio"), std::string::npos);
  EXPECT_NE(ies.find("[_GONIO_PHOTONS] 400000"), std::string::npos);
  EXPECT_NE(ies.find("[_GONIO_SEED] 1\r\n"), std::string::npos);
  EXPECT_NE(ies.find("\r\n1 1.00010 "), std::string::npos);  // file generation type: computer simulation
  EXPECT_NE(ies.find("[TESTLAB] none: computer simulation"), std::string::npos);

  // The LDT: cd/klm of the emitters' 1000 lm, LORL = escaped / emitted.
  const std::string ldt = test::read_file(out / "shade.ldt");
  std::vector<std::string> lines;
  for (std::size_t a = 0, b; (b = ldt.find("\r\n", a)) != std::string::npos; a = b + 2) lines.push_back(ldt.substr(a, b - a));
  ASSERT_GT(lines.size(), 30u);
  EXPECT_NEAR(std::stod(lines[22]), 100.0 * report["energy"]["lor"].get<double>(), 1e-6);  // field 23, LORL
  EXPECT_EQ(lines[2], "4");                                                                  // Isym 4: quadrant
  EXPECT_NEAR(std::stod(lines[28]), 1000.0, 1e-6);                                          // lamp set flux

  const auto latlong = io::read_exr((out / "farfield-latlong.exr").string());
  ASSERT_TRUE(latlong.ok());
  EXPECT_EQ(latlong->envmap, io::Envmap::LatLong);
  EXPECT_EQ(latlong->width, 2 * latlong->height - 1);
  EXPECT_NE(test::read_file(out / "shade.svg").find("<svg"), std::string::npos);
}

TEST(SimulateOutputs, FormatsNameAndIesVersionChooseTheFiles) {
  test::TempDir dir;
  const auto model = dir / "shade.gltf";
  test::write_file(model, shade_model());
  const auto out = dir / "out";
  auto r = gonio({"simulate", model.string(), "--out", out.string(), "--photons", "100000", "--iterations", "1",
                  "--format", "ies, plot", "--name", "lamp", "--ies-version", "2002", "--c-step", "10",
                  "--gamma-step", "5", "--symmetry", "C0-C180"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(out)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"lamp.ies", "lamp.svg", "report.json"}));
  const std::string ies = test::read_file(out / "lamp.ies");
  EXPECT_EQ(ies.rfind("IESNA:LM-63-2002\r\n", 0), 0u);
  // C0-C180 on a 10° × 5° grid: 19 planes 0…180, 37 angles.
  EXPECT_NE(ies.find(" 37 19 1 "), std::string::npos);
  const auto report = read_json(out / "report.json");
  EXPECT_EQ(report["outputs"]["symmetry"]["chosen"], "C0-C180");
  EXPECT_NE(report["outputs"]["symmetry"]["reason"].get<std::string>().find("as requested"), std::string::npos);
  EXPECT_EQ(report["outputs"]["grid"]["c_step_deg"], 10.0);
  EXPECT_EQ(report["settings"]["face_size"], 64);  // face_size_for(5°)
}

// --format ...,report: the datasheet beside the files, with the run's books.
TEST(SimulateOutputs, ReportWritesTheDatasheetWithTheLedger) {
  test::TempDir dir;
  const auto model = dir / "shade.gltf";
  test::write_file(model, shade_model());
  const auto out = dir / "out";
  auto r = gonio({"simulate", model.string(), "--out", out.string(), "--photons", "100000", "--iterations", "1",
                  "--format", "ies,report", "--name", "lamp", "--c-step", "10", "--gamma-step", "5"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(out / "lamp.html"));
  EXPECT_FALSE(std::filesystem::exists(out / "lamp.svg"));  // only what was asked for
  const std::string html = test::read_file(out / "lamp.html");
  EXPECT_NE(html.find("Energy ledger of the simulation"), std::string::npos);
  EXPECT_NE(html.find("UGR"), std::string::npos);
  const auto report = read_json(out / "report.json");
  char escaped[64];
  std::snprintf(escaped, sizeof escaped, "%.2f lm", report["escaped_lm"].get<double>());
  EXPECT_NE(html.find(escaped), std::string::npos) << escaped;
  bool listed = false;
  for (const auto& f : report["outputs"]["files"]) listed = listed || f["format"] == "report";
  EXPECT_TRUE(listed);
}

TEST(SimulateOutputs, AutoSymmetryDoesNotClaimWhatAnOffCentreLampBreaks) {
  test::TempDir dir;
  struct Case {
    double x, z;
    const char* expected;
  };
  // The lamp moved along +X (C0) keeps the mirror about the C0–C180 plane
  // only; moved along X and Z it keeps none.
  for (const Case& c : {Case{0.05, 0.0, "C0-C180"}, Case{0.05, 0.03, "none"}}) {
    const auto model = dir / "shade.gltf";
    test::write_file(model, shade_model(c.x, c.z));
    const auto out = dir / c.expected;
    auto r = gonio({"simulate", model.string(), "--out", out.string(), "--photons", "500000", "--iterations", "1",
                    "--format", "ies", "--c-step", "10", "--gamma-step", "5"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto report = read_json(out / "report.json");
    EXPECT_EQ(report["outputs"]["symmetry"]["chosen"], c.expected) << report["outputs"]["symmetry"].dump(1);
  }
}

TEST(SimulateOutputs, MinLorAndFluxToleranceFailTheRunWithAClearMessage) {
  test::TempDir dir;
  const auto model = dir / "shade.gltf";
  test::write_file(model, shade_model());
  const auto out = dir / "out";
  const std::vector<std::string> base = {"simulate", model.string(), "--out", out.string(), "--photons", "100000",
                                         "--iterations", "1", "--format", "ies,ldt"};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> a = base;
    a.insert(a.end(), extra.begin(), extra.end());
    return gonio(a);
  };
  auto r = with({});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const double lor = read_json(out / "report.json")["energy"]["lor"].get<double>();
  ASSERT_GT(lor, 0.3);
  ASSERT_LT(lor, 0.95);

  r = with({"--min-lor", std::to_string(lor - 0.01)});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  r = with({"--min-lor", std::to_string(lor + 0.01)});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("energy check failed: light output ratio"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--min-lor"), std::string::npos) << r.err;
  // Everything is still written, and the report says why the run failed.
  auto report = read_json(out / "report.json");
  EXPECT_FALSE(report["energy"]["passed"].get<bool>());
  EXPECT_EQ(report["energy"]["failures"].size(), 1u);
  EXPECT_TRUE(std::filesystem::exists(out / "shade.ies"));

  // No quadrature is exact: a zero tolerance fails on the IES and LDT files.
  r = with({"--flux-tolerance", "0"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("shade.ies: flux"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--flux-tolerance"), std::string::npos) << r.err;
}

TEST(SimulateOutputs, BadOptionValuesAreUsageErrorsThatSayWhy) {
  test::TempDir dir;
  const auto model = dir / "shade.gltf";
  test::write_file(model, shade_model());
  struct Case {
    std::vector<std::string> args;
    const char* says;
  };
  const Case cases[] = {
      {{"--c-step", "7"}, "7"},
      {{"--gamma-step", "0.05"}, "gamma-step"},  // 0.1 is the finest (issue 44)
      {{"--gamma-step", "abc"}, "gamma-step"},
      {{"--symmetry", "diagonal"}, "diagonal"},
      {{"--symmetry", "quadrant", "--c-step", "60"}, "quadrant"},
      {{"--format", "ies,gif"}, "gif"},
      {{"--format", ""}, "format"},
      {{"--ies-version", "1995"}, "ies-version"},
      {{"--min-lor", "1.5"}, "min-lor"},
      {{"--flux-tolerance", "-0.1"}, "flux-tolerance"},
      {{"--name", "a/b"}, "name"},
      {{"--bvh-quality", "fast"}, "bvh-quality"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> a = {"simulate", model.string(), "--out", (dir / "o").string()};
    a.insert(a.end(), c.args.begin(), c.args.end());
    auto r = gonio(a);
    EXPECT_EQ(r.exit_code, 2) << c.args[0] << " " << c.args[1];
    EXPECT_NE(r.err.find(c.says), std::string::npos) << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "o"));
}

TEST(Simulate, HelpNamesEveryOption) {
  auto r = gonio({"simulate", "--help"});
  EXPECT_EQ(r.exit_code, 0);
  for (const char* o : {"--photons", "--iterations", "--seed", "--threads", "--max-bounces", "--face-size", "--out",
                        "--c-step", "--gamma-step", "--symmetry", "--format", "--ies-version", "--name", "--min-lor",
                        "--flux-tolerance", "--bvh-quality", "--sampler", "--next-event", "--connections",
                        "--luminance-image"})
    EXPECT_NE(r.out.find(o), std::string::npos) << o;
}

// --luminance-image ugr: four images (γ 65° and 50° in C0 and C90) as EXR
// and PNG, listed in report.json with CIE 232's figures; the white shade
// (a diffuse box open at the bottom) glares from its inside. A view that
// sees only the box's top (from above) has no glare source.
TEST(Simulate, LuminanceImagesAndCie232FiguresFromTheUgrViews) {
  test::TempDir dir;
  const auto model = dir / "shade.gltf";
  test::write_file(model, shade_model());
  const auto out = dir / "o";
  auto r = gonio({"simulate", model.string(), "--out", out.string(), "--photons", "50000", "--iterations", "2",
                  "--face-size", "16", "--luminance-image", "ugr,0:170", "--format", "ies,report"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json report = nlohmann::json::parse(test::read_file(out / "report.json"));
  ASSERT_EQ(report["luminance_images"].size(), 5u);
  const std::set<std::string> names = [&] {
    std::set<std::string> n;
    for (const auto& p : report.at("written")) n.insert(std::filesystem::path(p.get<std::string>()).filename().string());
    return n;
  }();
  for (const char* f : {"shade.luminance-C0-G65.exr", "shade.luminance-C0-G50.exr", "shade.luminance-C90-G65.exr",
                        "shade.luminance-C90-G50.exr", "shade.luminance-C0-G170.exr", "shade.luminance-C0-G65.png"})
    EXPECT_TRUE(names.count(f)) << f;
  auto exr = io::read_exr((out / "shade.luminance-C0-G65.exr").string());
  ASSERT_TRUE(exr.ok()) << exr.error().message;
  ASSERT_NE(exr->find_float("L"), nullptr);
  // Each image carries the intensity towards its view; the views below see
  // the lit inside of the shade: CIE 232 defined there.
  for (int k = 0; k < 4; ++k) {
    const auto& img = report["luminance_images"][k];
    EXPECT_GT(img["intensity_cd"].get<double>(), 0.0);
    EXPECT_TRUE(img["cie232"]["defined"].get<bool>()) << img.dump();
    EXPECT_NEAR(img["cie232"]["delta_ugr"].get<double>(), 8.0 * std::log10(img["cie232"]["k2"].get<double>()), 1e-9);
  }
  // From above (γ 170°) only the closed top: no light, no glare source.
  EXPECT_EQ(report["luminance_images"][4]["intensity_cd"].get<double>(), 0.0);
  EXPECT_FALSE(report["luminance_images"][4]["cie232"]["defined"].get<bool>());
  EXPECT_TRUE(report["cie232"]["delta_ugr"].is_number());
  EXPECT_EQ(report["cie232"]["threshold_cd_m2"].get<double>(), 500.0);
  // The datasheet shows them.
  const std::string html = test::read_file(out / "shade.html");
  EXPECT_NE(html.find("CIE 232:2019"), std::string::npos);
  EXPECT_NE(html.find("shade.luminance-C90-G50.exr"), std::string::npos);
  EXPECT_NE(r.out.find("luminance image C0 G65"), std::string::npos) << r.out;
  // Bad views are usage errors that say why.
  for (const char* bad : {"0:200", "x", "0:65,", "400:10"}) {
    r = gonio({"simulate", model.string(), "--out", (dir / "bad").string(), "--luminance-image", bad});
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.err.find("--luminance-image"), std::string::npos) << r.err;
  }
}

// --next-event: the report says what was chosen and how the far field's
// total relates to the books; the written files carry the far field's flux.
TEST(Simulate, NextEventReportsItsChoiceAndItsBooks) {
  test::TempDir dir;
  const auto model = dir / "shade.gltf";
  test::write_file(model, shade_model());
  for (const char* mode : {"on", "off", "auto"}) {
    const auto out = dir / mode;
    auto r = gonio({"simulate", model.string(), "--out", out.string(), "--photons", "40000", "--iterations", "1",
                    "--face-size", "16", "--next-event", mode, "--format", "ies,exr"});
    ASSERT_EQ(r.exit_code, 0) << mode << r.err;
    const nlohmann::json report = nlohmann::json::parse(test::read_file(out / "report.json"));
    const nlohmann::json& n = report["next_event"];
    EXPECT_EQ(n["mode"].get<std::string>(), mode);
    if (std::string(mode) == "on") {
      ASSERT_TRUE(n["enabled"].get<bool>());
      EXPECT_GT(n["connections"].get<double>(), 0.0);
      // far field − escaped = booked − covered.
      EXPECT_NEAR(n["far_field_minus_escaped_lm"].get<double>(),
                  n["booked_lm"].get<double>() - n["covered_lm"].get<double>(), 1e-6);
      EXPECT_NEAR(report["far_field"]["flux_lm"].get<double>(),
                  report["escaped_lm"].get<double>() + n["far_field_minus_escaped_lm"].get<double>(),
                  1e-6);
    }
    if (std::string(mode) == "off") {
      EXPECT_FALSE(n["enabled"].get<bool>());
    }
    EXPECT_TRUE(report["energy"]["photons_close"].get<bool>());
  }
  auto r = gonio({"simulate", model.string(), "--out", (dir / "x").string(), "--next-event", "maybe"});
  EXPECT_EQ(r.exit_code, 2);
}


// --- failures after tracing lose nothing -----------------------------------

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// The file names of report.json's "written" list; each must exist.
std::set<std::string> written_names(const nlohmann::json& report) {
  std::set<std::string> names;
  for (const auto& p : report.at("written")) {
    const std::filesystem::path path = p.get<std::string>();
    EXPECT_TRUE(std::filesystem::is_regular_file(path)) << path;
    names.insert(path.filename().string());
  }
  return names;
}

std::vector<std::string> simulate_args(const std::filesystem::path& model, const std::filesystem::path& out,
                                       const std::string& face_size = "16") {
  return {"simulate", model.string(), "--out", out.string(), "--photons", "20000", "--iterations", "1",
          "--face-size", face_size};
}

TEST(SimulateFailures, AMissingPlotProgramStillLeavesEveryOtherFileAndTheReport) {
  test::TempDir dir;
  const auto model = dir / "shade.gltf";
  test::write_file(model, shade_model());
  const auto out = dir / "out";
  const test::ScopedEnv no_gnuplot("GONIO_GNUPLOT", "/nonexistent");
  const auto r = gonio(simulate_args(model, out));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(has(r.err, "gnuplot")) << r.err;
  EXPECT_TRUE(has(r.err, "1 output failed after tracing")) << r.err;
  EXPECT_TRUE(has(r.err, (out / "report.json").string())) << r.err;
  const auto report = read_json(out / "report.json");
  ASSERT_EQ(report["output_failures"].size(), 1u) << report["output_failures"].dump();
  EXPECT_TRUE(has(report["output_failures"][0].get<std::string>(), "shade.svg")) << report["output_failures"].dump();
  ASSERT_EQ(report["outputs"]["failed"].size(), 1u);
  EXPECT_EQ(report["outputs"]["failed"][0]["format"], "plot");
  EXPECT_EQ(written_names(report),
            (std::set<std::string>{"shade.ies", "shade.ldt", "farfield.exr", "farfield-latlong.exr"}));
  EXPECT_FALSE(std::filesystem::exists(out / "shade.svg"));
  // The run's books are all there.
  EXPECT_EQ(report["photons_emitted"], 20000);
  EXPECT_TRUE(report["energy"]["passed"].get<bool>());
  EXPECT_EQ(report["outputs"]["files"].size(), 4u);
}

TEST(SimulateFailures, AFileThatCannotBeWrittenIsNamedAndTheOthersAreWritten) {
  test::TempDir dir;
  const auto model = dir / "shade.gltf";
  test::write_file(model, shade_model());
  const auto out = dir / "out";
  std::filesystem::create_directories(out / "farfield.exr");  // in the way
  const auto r = gonio(simulate_args(model, out));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(has(r.err, (out / "farfield.exr").string())) << r.err;
  const auto report = read_json(out / "report.json");
  ASSERT_EQ(report["output_failures"].size(), 1u);
  EXPECT_TRUE(has(report["output_failures"][0].get<std::string>(), "farfield.exr"));
  EXPECT_EQ(report["outputs"]["failed"][0]["format"], "exr");
  EXPECT_EQ(written_names(report),
            (std::set<std::string>{"shade.ies", "shade.ldt", "farfield-latlong.exr", "shade.svg"}));
}

TEST(SimulateFailures, AFullDiskLeavesTheReportWithWhatFitted) {
  // A file size limit (ulimit -f, with SIGXFSZ ignored) makes every write
  // past it fail with EFBIG, as a full disk fails with ENOSPC: the large
  // far-field images do not fit, the tables and the report do.
  test::TempDir dir;
  const auto model = dir / "shade.gltf";
  test::write_file(model, shade_model());
  const auto out = dir / "out";
  std::string command = std::string("trap '' XFSZ; ulimit -f 48; exec '") + GONIO_EXECUTABLE + "'";
  for (const std::string& a : simulate_args(model, out, "128")) command += " '" + a + "'";
  const auto r = test::run_process({"/bin/bash", "-c", command});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  const auto report = read_json(out / "report.json");
  const std::set<std::string> written = written_names(report);
  EXPECT_TRUE(written.count("shade.ies") && written.count("shade.ldt")) << report["written"].dump();
  ASSERT_GE(report["output_failures"].size(), 1u);
  for (const auto& f : report["outputs"]["failed"]) {
    const std::string path = f["path"].get<std::string>();
    EXPECT_FALSE(std::filesystem::exists(path)) << path;  // nothing half written
    EXPECT_TRUE(has(r.err, path)) << r.err;
  }
  // Nothing else is left in the folder: no temporary file of a failed write.
  for (const auto& e : std::filesystem::directory_iterator(out))
    EXPECT_TRUE(e.path().filename() == "report.json" || written.count(e.path().filename().string())) << e.path();
}

TEST(SimulateFailures, APreviewThatCannotBeWrittenLosesNothingElse) {
  test::TempDir dir;
  const auto model = dir / "shade.gltf";
  test::write_file(model, shade_model());
  const auto out = dir / "out";
  std::filesystem::create_directories(out / "preview.png");  // in the way
  auto args = simulate_args(model, out);
  args.push_back("--preview");
  const auto r = gonio(args);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(has(r.err, "preview.png")) << r.err;
  const auto report = read_json(out / "report.json");
  ASSERT_EQ(report["output_failures"].size(), 1u);
  EXPECT_TRUE(has(report["output_failures"][0].get<std::string>(), "preview.png"));
  const std::set<std::string> written = written_names(report);
  for (const char* name : {"shade.ies", "shade.ldt", "farfield.exr", "farfield-latlong.exr", "shade.svg"})
    EXPECT_TRUE(written.count(name)) << name;
  EXPECT_FALSE(written.count("preview.png"));
}

TEST(SimulateFailures, AReportThatCannotBeWrittenNamesWhatWasWritten) {
  test::TempDir dir;
  const auto model = dir / "shade.gltf";
  test::write_file(model, shade_model());
  const auto out = dir / "out";
  std::filesystem::create_directories(out / "report.json");  // in the way
  const auto r = gonio(simulate_args(model, out));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.err, (out / "report.json").string())) << r.err;
  for (const char* name : {"shade.ies", "shade.ldt", "farfield.exr", "farfield-latlong.exr", "shade.svg"})
    EXPECT_TRUE(has(r.err, "written before the report failed: " + (out / name).string())) << r.err;
}

// A model that lets no light out: the run says so in words, and no number
// it prints is "nan".
TEST(Simulate, AModelThatLetsNoLightOutSaysSoPlainly) {
  test::TempDir dir;
  const auto model = dir / "sealed.gltf";
  test::write_file(model, shade_model(0.0, 0.0, false, true));
  const auto out = dir / "out";
  const auto r = gonio({"simulate", model.string(), "--out", out.string(), "--photons", "20000", "--iterations",
                        "1", "--face-size", "16", "--format", "ies,ldt,exr"});
  EXPECT_TRUE(has(r.err, "no light leaves the model")) << r.err;
  EXPECT_FALSE(has(r.out + r.err, "nan")) << r.out << r.err;
  EXPECT_FALSE(has(r.out + r.err, "inf ")) << r.out << r.err;
  const auto report = read_json(out / "report.json");
  EXPECT_EQ(report["photons_escaped"], 0);
  EXPECT_EQ(report["photons_emitted"], 20000);
}

// A model whose image uri leaves its folder: refused by every command that
// loads models, naming model and uri, unless --allow-outside-paths
// (io/model/gltf.h; each kind of uri and escape is tested in tests/io/model/gltf_test.cpp).
TEST(Simulate, UrisOutsideTheModelsFolderNeedAllowOutsidePaths) {
  test::TempDir dir;
  std::filesystem::create_directories(dir / "model");
  std::filesystem::create_directories(dir / "outside");
  test::write_file(dir / "outside" / "tex.png", "not decoded");
  nlohmann::json g = nlohmann::json::parse(shade_model());
  g["images"] = nlohmann::json::array({nlohmann::json{{"uri", "../outside/tex.png"}}});
  const auto model = dir / "model" / "shade.gltf";
  test::write_file(model, g.dump());
  const auto out = dir / "out";
  for (const char* command : {"simulate", "bench"}) {
    const auto r = gonio({command, model.string(), "--out", out.string(), "--photons", "20000"});
    EXPECT_EQ(r.exit_code, 1) << command;
    EXPECT_TRUE(has(r.err, model.string() + ": uri '../outside/tex.png' climbs out with '..', outside the "
                           "model's folder")) << r.err;
    EXPECT_TRUE(has(r.err, "--allow-outside-paths")) << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(out / "report.json"));
  auto args = simulate_args(model, out);
  args.push_back("--allow-outside-paths");
  const auto r = gonio(args);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(out / "report.json"));
}

}  // namespace
}  // namespace gonio
