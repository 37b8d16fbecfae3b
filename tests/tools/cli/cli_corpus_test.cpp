// The gonio executable on every real file of the shared corpus.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "io/photometric/photometric_file.h"
#include "photometry/summary.h"
#include "tests/tools/cli/cli_fixtures.h"

namespace gonio {
namespace {

using nlohmann::json;

TEST(CliCorpus, InfoJsonAgreesWithTheLibraryOnEveryFile) {
  GONIO_REQUIRE_CORPUS();
  const auto files = test::corpus_files({".ies", ".ldt"});
  ASSERT_EQ(files.size(), 111u);
  for (const auto& p : files) {
    SCOPED_TRACE(p.string());
    const auto r = test::gonio({"info", "--json", p.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json j = json::parse(r.out, nullptr, false);
    ASSERT_FALSE(j.is_discarded()) << r.out;
    auto file = io::read_photometric_file(p.string());
    ASSERT_TRUE(file.ok());
    const auto s = photometry::summarize(file->distribution);
    EXPECT_EQ(j["flux_lm"].get<double>(), s.flux_lm);
    EXPECT_EQ(j["max_cd"].get<double>(), s.max_intensity_cd);
    EXPECT_EQ(j["lor"].is_null(), !s.lor_defined);
    EXPECT_EQ(j["absolute_photometry"].get<bool>(), file->distribution.absolute);
    // The planning figures: finite wherever defined, and a reason wherever not.
    if (j["ugr_table"].is_null()) {
      EXPECT_FALSE(j["ugr_table_why"].get<std::string>().empty());
    } else {
      ASSERT_EQ(j["ugr_table"]["rooms"].size(), 19u);
      for (const auto& room : j["ugr_table"]["rooms"])
        for (const char* side : {"crosswise", "endwise"})
          for (const auto& v : room[side]) EXPECT_TRUE(v.is_number()) << room.dump();
    }
    if (j["cu_table"].is_null()) {
      EXPECT_FALSE(j["cu_table_why"].get<std::string>().empty());
    } else {
      // Bounded by what the brightest room (ceiling 80 %, floor 20 %) can
      // return of the luminaire's share of the reference flux (a file with
      // a too-small lamp flux has LOR > 1, and CU follows it).
      const double share = j["flux_lm"].get<double>() / j["cu_table"]["reference_flux_lm"].get<double>();
      for (const auto& row : j["cu_table"]["values"])
        for (const auto& v : row) {
          ASSERT_TRUE(v.is_number());
          EXPECT_GE(v.get<double>(), 0.0);
          EXPECT_LE(v.get<double>(), share / (1 - 0.8 * 0.2) + 1e-9);
        }
    }
    for (const char* k : {"c0_c180", "c90_c270", "diagonal"})
      EXPECT_TRUE(j["spacing_criterion"][k].is_number() || j["spacing_criterion"].contains(std::string(k) + "_why"))
          << k;
    for (const char* k : {"b", "u", "g"}) {
      EXPECT_GE(j["bug"][k].get<int>(), 0);
      EXPECT_LE(j["bug"][k].get<int>(), 5);
    }
    if (!j["luminance_table"].is_null()) {
      EXPECT_TRUE(j["luminance_table"]["max_cd_m2"].is_number());
    }
    // Every reader warning is on stderr too, in the documented form.
    for (const Finding& f : file->findings)
      EXPECT_NE(r.err.find("gonio: " + to_string(f.where) + ": " + to_string(f.severity) + ": "),
                std::string::npos)
          << f.code;
  }
}

TEST(CliCorpus, CheckFindsWarningsButNoErrorsInRealFiles) {
  GONIO_REQUIRE_CORPUS();
  std::vector<std::string> args = {"check", "--json"};
  for (const auto& p : test::corpus_files({".ies", ".ldt"})) args.push_back(p.string());
  const auto r = test::gonio(args);
  EXPECT_EQ(r.exit_code, 3);  // warnings (e.g. declared LOR against integrated), no errors
  const json j = json::parse(r.out, nullptr, false);
  ASSERT_FALSE(j.is_discarded());
  EXPECT_EQ(j["with_errors"], 0);
  EXPECT_EQ(j["files"].size(), 111u);
  EXPECT_GT(j["clean"].get<int>(), 0);
  EXPECT_GT(j["with_warnings"].get<int>(), 0);
}

}  // namespace
}  // namespace gonio
