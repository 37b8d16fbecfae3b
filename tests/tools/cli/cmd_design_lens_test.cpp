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
                                 "0,60", "--out", out.string(), "--photons", "1000000"});
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
        {"--target", "linear:0.5,10"}, {"--ior", "0.9"}}) {
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
