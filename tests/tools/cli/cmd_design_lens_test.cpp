// gonio design lens, run as a user would: the exact case φ = kθ of a point
// source whose intensity falls smoothly to zero at the lens's rim (so that
// neither target nor trace has a step), the designed profile against the
// closed form r(θ) = r₀·((n − cos((k − 1)θ))/(n − 1))^(1/(k − 1)), the lens
// traced against its target (flux-normalised: the Fresnel reflections at
// both faces are real), and the targets no lens can give.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "design/lens_design.h"
#include "design/reflector_design.h"
#include "io/photometric/photometric_file.h"
#include "tests/support/test_support.h"

namespace gonio {
namespace {

namespace fs = std::filesystem;
constexpr double kPi = std::numbers::pi;

test::ProcessResult gonio(std::vector<std::string> args) {
  args.insert(args.begin(), GONIO_EXECUTABLE);
  return test::run_process(args);
}

// 100 cd · cos²(90° · γ/to) below `to`, 0 beyond, every 0.5°.
void write_emitter(const fs::path& path, double to_deg) {
  std::vector<double> g, c;
  for (int i = 0; i <= 360; ++i) {
    const double gamma = 0.5 * i;
    g.push_back(gamma);
    c.push_back(gamma < to_deg ? 100.0 * std::pow(std::cos(kPi / 2 * gamma / to_deg), 2) : 0.0);
  }
  ASSERT_TRUE(io::write_photometric_file(path.string(), design::rotational_distribution(g, c), {}, nullptr).ok());
}

TEST(DesignLensCli, ExactCaseGivesTheClosedFormProfileAndTheTargetTraced) {
  test::TempDir dir;
  const fs::path emitter = dir / "e.ies";
  write_emitter(emitter, 60.0);
  const fs::path out = dir / "d";
  test::ProcessResult r = gonio({"design", "lens", "--emitter", emitter.string(), "--target", "linear:0.5,0", "--cone",
                                 "0,60", "--out", out.string(), "--photons", "1000000", "--feedback", "0"});
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  for (const char* f : {"lens.design.toml", "emitter.ies", "lens.gltf", "lens.bin", "target.ies", "lens.ies",
                        "lens.ldt", "report.json"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
#ifdef GONIO_TEST_WITH_OCCT
  EXPECT_TRUE(fs::exists(out / "lens.step"));
  EXPECT_TRUE(fs::exists(out / "lens.gonio.toml"));
#endif
  const nlohmann::json d = nlohmann::json::parse(test::read_file(out / "report.json")).at("design");
  EXPECT_EQ(d.at("kind"), "lens");
  const auto& theta = d.at("outer_profile").at("theta_deg");
  const auto& r_mm = d.at("outer_profile").at("r_mm");
  double worst = 0.0;
  for (std::size_t i = 0; i < theta.size(); ++i) {
    const double exact = 1e3 * design::linear_lens_r(0.5, 1.491, theta[i].get<double>() * kPi / 180.0, 0.010);
    worst = std::max(worst, std::abs(r_mm[i].get<double>() / exact - 1.0));
  }
  EXPECT_LT(worst, 1e-4);
  const nlohmann::json& a = d.at("against_target");
  const double rms_pct = 100.0 * a.at("rms_relative").get<double>();
  std::printf("lens k = 0.5: profile %.3g, traced RMS %.4f %% of peak, largest %.3f %%, beam %.2f° (target %.2f°)\n",
              worst, rms_pct, 100.0 * a.at("max_relative").get<double>(), a.at("beam_angle_traced_deg").get<double>(),
              a.at("beam_angle_target_deg").get<double>());
  EXPECT_LT(rms_pct, 1.5);  // measured 0.89 % at 10⁶ photons (docs/design.md: Fresnel's stray light and noise)
  EXPECT_NEAR(a.at("beam_angle_traced_deg").get<double>(), a.at("beam_angle_target_deg").get<double>(), 0.5);
}

// A point source's lens with the default feedback (one iteration): the
// Fresnel losses depend on the angle of incidence at the outer surface, and
// the feedback corrects the beam's shape for them. Measured (docs/design.md,
// "Feedback for a lens"): the RMS in the target's beam falls from 0.084 % to
// 0.019 % of the peak (two seeds differ by 0.02 %); the flux-normalised RMS
// stays at 0.89–0.94 %: the 7 % of the flux that the inner sphere reflects
// back above 90° is stray light no design of the surfaces sends into the beam.
TEST(DesignLensCli, FeedbackCorrectsTheBeamForTheFresnelLosses) {
  test::TempDir dir;
  const fs::path emitter = dir / "e.ies";
  write_emitter(emitter, 60.0);
  const fs::path out = dir / "d";
  test::ProcessResult r = gonio({"design", "lens", "--emitter", emitter.string(), "--target", "linear:0.5,0", "--cone",
                                 "0,60", "--out", out.string(), "--photons", "1000000"});
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const nlohmann::json f = nlohmann::json::parse(test::read_file(out / "report.json")).at("design").at("feedback");
  const nlohmann::json& it = f.at("per_iteration");
  ASSERT_EQ(it.size(), 2u) << f.dump();  // the default: one iteration for a point source
  const double first = it[0].at("rms_relative_beam").get<double>(), last = it[1].at("rms_relative_beam").get<double>();
  std::printf("lens point source: beam RMS %.4f %% -> %.4f %%, flux-normalised %.3f %% -> %.3f %%\n", 100 * first,
              100 * last, 100 * it[0].at("rms_relative").get<double>(), 100 * it[1].at("rms_relative").get<double>());
  EXPECT_LT(last, 0.5 * first) << f.dump();
  EXPECT_EQ(f.at("kept").get<int>(), 1);
  EXPECT_EQ(f.at("kept_by"), "rms_relative_beam");
  EXPECT_EQ(f.at("method"), "part");  // --correction auto: a lens's stray light rules out the cumulative
  // The stray light's floor under flux normalisation: ~7 % of the flux off the beam.
  EXPECT_GT(it[1].at("rms_relative").get<double>(), 0.008);
  EXPECT_FALSE(it[1].contains("profile_change_next"));  // the last iteration designs nothing after it
  EXPECT_LT(it[0].at("profile_change_next").get<double>(), 5e-3);  // a correction, not a new lens
}

// A die of 2 × 2 mm in the lens's cavity: the design file names its rays,
// the feedback brings the beam nearer the target (measured 1.02 % → 0.40 %
// → 0.30 % of the peak with 10⁶ rays); a die that does not fit inside the
// inner sphere is refused with the reason, nothing written.
TEST(DesignLensCli, ADiesBeamComesNearerTheTargetWithFeedback) {
  test::TempDir dir;
  const fs::path emitter = dir / "e.ies";
  write_emitter(emitter, 60.0);
  const fs::path out = dir / "die";
  test::ProcessResult r = gonio({"design", "lens", "--emitter", emitter.string(), "--target", "linear:0.5,0", "--cone",
                                 "0,60", "--out", out.string(), "--photons", "1000000", "--die", "2x2", "--die-rays",
                                 "500000", "--feedback", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(test::read_file(out / "lens.design.toml").find("ray_file = \"emitter.tm25ray\""), std::string::npos);
  EXPECT_TRUE(fs::exists(out / "emitter.tm25ray"));
  const nlohmann::json d = nlohmann::json::parse(test::read_file(out / "report.json")).at("design");
  EXPECT_TRUE(d.at("extended").get<bool>());
  const nlohmann::json& it = d.at("feedback").at("per_iteration");
  ASSERT_EQ(it.size(), 3u) << d.at("feedback").dump();
  const double first = it[0].at("rms_relative_beam").get<double>(), last = it[2].at("rms_relative_beam").get<double>();
  std::printf("lens die 2x2: beam RMS %.3f %% -> %.3f %% -> %.3f %%\n", 100 * first,
              100 * it[1].at("rms_relative_beam").get<double>(), 100 * last);
  EXPECT_LT(it[1].at("rms_relative_beam").get<double>(), 0.6 * first);
  EXPECT_LT(last, 0.5 * first);
  EXPECT_EQ(it[1].at("seed").get<int>(), 2);
  // A die whose corners (5.7 mm away) lie outside the 5 mm inner sphere.
  r = gonio({"design", "lens", "--emitter", emitter.string(), "--target", "linear:0.5,0", "--out",
             (dir / "big").string(), "--die", "8x8"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("not inside the lens's inner sphere (--inner, 5 mm)"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "big"));
}

// A measured LED's ray file (5.9 × 6.4 mm of rays) in a cavity of 3 mm:
// its rays would start inside the glass. An error naming the file and the
// reason, nothing written.
TEST(DesignLensCli, ARayFileMustFitInsideTheCavity) {
  GONIO_REQUIRE_CORPUS();
  const fs::path rays = test::corpus_dir() / "rayfiles" / "rayfile_LERTDUW_S2WP_blue_100k_20161013_IES_TM25.TM25RAY";
  test::TempDir dir;
  test::ProcessResult r = gonio({"design", "lens", "--emitter", rays.string(), "--target", "linear:0.5,0", "--cone",
                                 "0,80", "--inner", "3", "--distance", "12", "--out", (dir / "d").string()});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find(rays.filename().string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("not inside the lens's inner sphere (--inner, 3 mm)"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "d"));
}

TEST(DesignLensCli, TargetsNoLensCanGiveAndBadOptions) {
  test::TempDir dir;
  const fs::path emitter = dir / "e.ies";
  write_emitter(emitter, 80.0);
  // All of 0…80° into 5°: the rim's ray would turn by 75°.
  test::ProcessResult r = gonio({"design", "lens", "--emitter", emitter.string(), "--target", "uniform:0,5", "--cone",
                                 "0,80", "--out", (dir / "a").string()});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("no lens gives this target"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("total internal reflection at the outer surface"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "a" / "lens.design.toml"));
  for (const std::vector<std::string>& bad :
       {std::vector<std::string>{"--cone", "10,60"}, {"--cone", "0,95"}, {"--map", "sideways"},
        {"--target", "linear:0.5,10"}, {"--ior", "0.9"}, {"--correction", "sideways"}, {"--die", "2x"}}) {
    std::vector<std::string> args = {"design", "lens", "--emitter", emitter.string(), "--target", "uniform:0,30",
                                     "--out", (dir / "b").string()};
    for (std::size_t i = 0; i < bad.size(); i += 2) {
      const auto at = std::find(args.begin(), args.end(), bad[i]);
      if (at != args.end()) *(at + 1) = bad[i + 1];
      else args.insert(args.end(), {bad[i], bad[i + 1]});
    }
    r = gonio(args);
    EXPECT_EQ(r.exit_code, 2) << bad[0] << " " << bad[1] << "\n" << r.err;
  }
}

}  // namespace
}  // namespace gonio
