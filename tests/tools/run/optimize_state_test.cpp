// DIR/state.json of a running gonio optimize (tools/run/optimize_state.h):
// the best's candela and figures are the best evaluation's, whatever the
// size of the generation traced before its evaluations are recorded.
#include "tools/run/optimize_state.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "tests/support/test_support.h"

namespace gonio::app {
namespace {

// A CMA-ES generation of 260 points (--population allows up to 100000) is
// traced before any of its evaluations is recorded: each point's candela
// must wait for its record. The first point is the best; the state must
// show its candela and its candela RMS, not keep the nulls of the start
// (a cap that dropped every waiting row beyond 256 lost it).
TEST(OptimizeState, ALargeGenerationKeepsEveryPointsCandelaUntilItsRecord) {
  test::TempDir dir;
  design::MeritSpec spec;
  spec.absolute = true;  // the candela as traced, unscaled
  design::MeritGrid grid;
  grid.c_deg = {0.0};
  grid.gamma_deg = {0.0, 45.0, 90.0};
  grid.solid_angle_sr = {1.0, 1.0, 1.0};
  design::MeritTarget target;
  target.candela = {1.0, 1.0, 1.0};
  const std::vector<design::OptimizeVariable> variables = {{"x", 0.5, 0.0, 1.0}};
  OptimizeProgress progress((dir / "state.json").string(), "d.design.toml", "t.ies", "cmaes", 1000, 0.0, variables,
                            spec, grid, target);
  constexpr int kPoints = 260;
  const auto merit_of = [](int k) { return 1.0 + k; };
  for (int k = 0; k < kPoints; ++k) {
    design::MeritValue m;
    m.merit = merit_of(k);
    m.candela_rms_pct = merit_of(k);
    m.lor = 0.5;
    progress.traced({k / 1000.0}, 500, 7, {10.0 + k, 20.0 + k, 30.0 + k}, m);
  }
  for (int k = 0; k < kPoints; ++k) {
    design::EvaluationRecord r;
    r.index = k + 1;
    r.values = {k / 1000.0};
    r.merit = merit_of(k);
    r.best = merit_of(0);
    r.photons = 500;
    r.seed = 7;
    progress.evaluation(r);
  }
  const nlohmann::json state = nlohmann::json::parse(test::read_file(dir / "state.json"));
  EXPECT_EQ(state.at("optimize").at("best_index").get<int>(), 1);
  ASSERT_FALSE(state.at("optimize").at("candela_rms_pct").is_null()) << "the best's candela was dropped";
  EXPECT_EQ(state.at("optimize").at("candela_rms_pct").get<double>(), merit_of(0));
  EXPECT_EQ(state.at("curves").at("c0"), nlohmann::json({10.0, 20.0, 30.0}));
  EXPECT_EQ(state.at("max_cd").get<double>(), 30.0);
}

}  // namespace
}  // namespace gonio::app
