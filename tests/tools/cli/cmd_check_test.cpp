// gonio check, run as a user would.
#include <gtest/gtest.h>

#include <algorithm>

#include <nlohmann/json.hpp>

#include "io/photometric/ldt.h"
#include "io/support/text.h"
#include "tests/tools/cli/cli_fixtures.h"

namespace gonio {
namespace {

using nlohmann::json;
using test::contains;
using test::gonio;

constexpr int kClean = 0, kWarnings = 3, kErrors = 4;

// The files the tests check, written once per test into a fresh directory.
struct Files {
  test::TempDir dir;
  std::string clean_ies, clean_ldt, warned, zero, truncated, note;

  Files() {
    clean_ies = (dir / "clean.ies").string();
    clean_ldt = (dir / "clean.ldt").string();
    test::write_distribution(clean_ies, test::lambertian_downlight());
    test::write_distribution(clean_ldt, test::lambertian_downlight());

    // C-planes that disagree at the nadir (a model-level warning) and a
    // keyword LM-63-2002 does not define (a reader warning on line 6).
    warned = (dir / "warned.ies").string();
    test::write_file(warned,
                     "IESNA:LM-63-2002\r\n[TEST] 1\r\n[TESTLAB] L\r\n[ISSUEDATE] 2002\r\n"
                     "[MANUFAC] M\r\n[WEIRD] x\r\nTILT=NONE\r\n1 1000 1 3 2 1 2 0 0 0\r\n"
                     "1 1 10\r\n0 45 90\r\n0 180\r\n100 80 0\r\n150 80 0\r\n");

    // Every intensity 0: readable, but the luminaire emits nothing (an error).
    zero = (dir / "zero.ies").string();
    test::write_file(zero,
                     "IESNA:LM-63-2002\r\n[TEST] 1\r\n[TESTLAB] L\r\n[ISSUEDATE] 2002\r\n"
                     "[MANUFAC] M\r\nTILT=NONE\r\n1 1000 1 3 1 1 2 0 0 0\r\n1 1 10\r\n"
                     "0 45 90\r\n0\r\n0 0 0\r\n");

    const std::string text = test::read_file(clean_ldt);
    truncated = (dir / "truncated.ldt").string();
    test::write_file(truncated, text.substr(0, text.size() / 3));

    // An EULUMDAT conversion factor other than 1 is a note (info) only:
    // values halved, factor 2, the same luminaire.
    note = (dir / "note.ldt").string();
    std::vector<std::string> lines;
    for (const io::TextLine& l : io::split_lines(text)) lines.emplace_back(l.text);
    lines[23] = "2";                     // field 24, the conversion factor
    const std::size_t values = 37 * 73;  // planes × γ angles
    for (std::size_t i = lines.size() - values; i < lines.size(); ++i)
      lines[i] = std::to_string(std::stod(lines[i]) / 2.0);
    std::string halved;
    for (const std::string& l : lines) halved += l + "\r\n";
    test::write_file(note, halved);
  }
};

int count(const std::string& text, const std::string& part) {
  int n = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

TEST(CliCheck, ExitCodesSeparateCleanWarningsAndErrors) {
  Files f;
  auto clean = gonio({"check", f.clean_ies, f.clean_ldt});
  EXPECT_EQ(clean.exit_code, kClean) << clean.out << clean.err;
  EXPECT_TRUE(contains(clean.out, f.clean_ies + ": clean (IES LM-63-2019)\n")) << clean.out;
  EXPECT_TRUE(contains(clean.out, f.clean_ldt + ": clean (EULUMDAT)\n")) << clean.out;
  EXPECT_TRUE(contains(clean.out, "2 files: 2 clean, 0 with warnings, 0 with errors\n"));
  EXPECT_TRUE(clean.err.empty()) << clean.err;

  auto warned = gonio({"check", f.warned});
  EXPECT_EQ(warned.exit_code, kWarnings) << warned.out;
  EXPECT_TRUE(contains(warned.out, "gonio: " + f.warned + ":6: warning: ")) << warned.out;
  EXPECT_TRUE(contains(warned.out, "[unknown-keyword]\n")) << warned.out;
  // A model-level finding concerns no single line.
  EXPECT_TRUE(contains(warned.out, "gonio: " + f.warned + ": warning: ")) << warned.out;
  EXPECT_TRUE(contains(warned.out, "[nadir-mismatch]\n")) << warned.out;
  EXPECT_TRUE(contains(warned.out, f.warned + ": 2 warnings (IES LM-63-2002)\n")) << warned.out;
  EXPECT_FALSE(contains(warned.out, "files:"));  // no total for one file

  auto zero = gonio({"check", f.zero});
  EXPECT_EQ(zero.exit_code, kErrors) << zero.out;
  EXPECT_TRUE(contains(zero.out, "gonio: " + f.zero + ": error: ")) << zero.out;
  EXPECT_TRUE(contains(zero.out, "[all-zero]\n")) << zero.out;

  auto truncated = gonio({"check", f.truncated});
  EXPECT_EQ(truncated.exit_code, kErrors);
  EXPECT_TRUE(contains(truncated.out, "gonio: " + f.truncated + ":")) << truncated.out;
  EXPECT_TRUE(contains(truncated.out, ": error: ")) << truncated.out;
  EXPECT_TRUE(contains(truncated.out, "[unreadable]\n")) << truncated.out;
  EXPECT_TRUE(contains(truncated.out, f.truncated + ": 1 error, unreadable\n")) << truncated.out;

  // Notes (info) do not make a file unclean.
  auto note = gonio({"check", f.note});
  EXPECT_EQ(note.exit_code, kClean) << note.out;
  EXPECT_TRUE(contains(note.out, ": info: ")) << note.out;
  EXPECT_TRUE(contains(note.out, f.note + ": clean, 1 info (EULUMDAT)\n")) << note.out;
}

TEST(CliCheck, GoesOnAfterUnreadableFilesAndReportsTheWorst) {
  Files f;
  const std::string missing = (f.dir / "missing.ldt").string();
  const std::string folder = f.dir.path().string();
  auto r = gonio({"check", f.truncated, missing, folder, f.clean_ies, f.warned});
  EXPECT_EQ(r.exit_code, kErrors) << r.out;
  EXPECT_TRUE(contains(r.out, "gonio: " + missing + ": error: cannot open")) << r.out;
  EXPECT_TRUE(contains(r.out, "gonio: " + folder + ": error: is a directory")) << r.out;
  EXPECT_TRUE(contains(r.out, f.clean_ies + ": clean")) << r.out;
  EXPECT_TRUE(contains(r.out, f.warned + ": 2 warnings")) << r.out;
  EXPECT_EQ(count(r.out, ", unreadable\n"), 3) << r.out;
  EXPECT_TRUE(contains(r.out, "5 files: 1 clean, 1 with warnings, 3 with errors\n")) << r.out;
  // Unreadable files are part of the report, on stdout like the rest.
  EXPECT_TRUE(r.err.empty()) << r.err;
  // Warnings only, over several files: 3.
  EXPECT_EQ(gonio({"check", f.clean_ldt, f.warned, f.note}).exit_code, kWarnings);
}

TEST(CliCheck, JsonReportMatchesTheTextAndTheExitCode) {
  Files f;
  auto r = gonio({"check", "--json", f.clean_ldt, f.warned, f.zero, f.truncated});
  EXPECT_EQ(r.exit_code, kErrors);
  const json j = json::parse(r.out, nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << r.out;
  EXPECT_EQ(j["exit_code"], kErrors);
  EXPECT_EQ(j["clean"], 1);
  EXPECT_EQ(j["with_warnings"], 1);
  EXPECT_EQ(j["with_errors"], 2);
  ASSERT_EQ(j["files"].size(), 4u);
  EXPECT_EQ(j["files"][0]["status"], "clean");
  EXPECT_EQ(j["files"][0]["format"], "EULUMDAT");
  EXPECT_EQ(j["files"][1]["status"], "warnings");
  EXPECT_EQ(j["files"][1]["version"], "LM-63-2002");
  EXPECT_EQ(j["files"][1]["warnings"], 2);
  bool line6 = false, model = false;
  for (const auto& x : j["files"][1]["findings"]) {
    line6 =
        line6 || (x["code"] == "unknown-keyword" && x["line"] == 6 && x["severity"] == "warning");
    model = model || (x["code"] == "nadir-mismatch" && x["line"].is_null());
  }
  EXPECT_TRUE(line6 && model) << j["files"][1].dump();
  EXPECT_EQ(j["files"][2]["status"], "errors");
  EXPECT_EQ(j["files"][2]["readable"], true);
  EXPECT_EQ(j["files"][3]["readable"], false);
  EXPECT_TRUE(j["files"][3]["format"].is_null());
  EXPECT_EQ(j["files"][3]["findings"][0]["code"], "unreadable");
  EXPECT_GT(j["files"][3]["findings"][0]["line"].get<int>(), 0);
  EXPECT_FALSE(contains(r.out, "gonio: "));  // nothing but the JSON on stdout

  auto clean = gonio({"check", f.clean_ies, "--json"});
  EXPECT_EQ(clean.exit_code, kClean);
  EXPECT_EQ(json::parse(clean.out)["exit_code"], kClean);
}

// A negative intensity is read as 0 with one warning naming file and line,
// in both formats, and every command treats it the same way: check counts a
// warning, info and convert say it on stderr and go on.
TEST(CliCheck, NegativeIntensitiesAreOneWarningInEveryCommand) {
  Files f;
  const std::string ies = (f.dir / "negative.ies").string();
  test::write_file(ies,
                   "IESNA:LM-63-2002\r\n[TEST] 1\r\n[TESTLAB] L\r\n[ISSUEDATE] 2002\r\n"
                   "[MANUFAC] M\r\nTILT=NONE\r\n1 1000 1 3 1 1 2 0 0 0\r\n1 1 10\r\n"
                   "0 45 90\r\n0\r\n100 80 -0.5\r\n");
  // The clean LDT with C 0, gamma 180 (0 cd/klm there) made negative.
  const std::string clean = test::read_file(f.clean_ldt);
  std::vector<std::string> lines;
  for (const io::TextLine& l : io::split_lines(clean)) lines.emplace_back(l.text);
  const std::size_t at = lines.size() - 37 * 73 + 72;  // plane C 0, gamma 180
  ASSERT_EQ(lines[at], "0");
  lines[at] = "-0.5";
  std::string text;
  for (const std::string& l : lines) text += l + "\r\n";
  const std::string ldt = (f.dir / "negative.ldt").string();
  test::write_file(ldt, text);

  struct Case {
    std::string path, finding;
  };
  const Case cases[] = {
      {ies, "gonio: " + ies + ":11: warning: 1 negative candela value(s) read as 0"
            " [negative-intensity]\n"},
      {ldt, "gonio: " + ldt + ":" + std::to_string(at + 1) +
                ": warning: 1 negative intensity value(s) read as 0 (the first at C 0, gamma "
                "180) [ldt-negative-intensity]\n"}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.path);
    auto check = gonio({"check", c.path});
    EXPECT_EQ(check.exit_code, kWarnings) << check.out;
    EXPECT_TRUE(contains(check.out, c.finding)) << check.out;
    EXPECT_TRUE(contains(check.out, c.path + ": 1 warning (")) << check.out;
    EXPECT_TRUE(check.err.empty()) << check.err;

    auto info = gonio({"info", c.path});
    EXPECT_EQ(info.exit_code, 0) << info.err;
    EXPECT_TRUE(contains(info.err, c.finding)) << info.err;
    EXPECT_TRUE(contains(info.out, "Total flux")) << info.out;

    const bool from_ies = std::filesystem::path(c.path).extension() == ".ies";
    const std::string out = (f.dir / (from_ies ? "converted.ldt" : "converted.ies")).string();
    auto convert = gonio({"convert", c.path, out});
    EXPECT_EQ(convert.exit_code, 0) << convert.err;
    EXPECT_TRUE(contains(convert.err, c.finding)) << convert.err;
    // What was written holds the 0 and reads back without the warning.
    auto again = gonio({"check", out});
    EXPECT_FALSE(contains(again.out, "negative-intensity")) << again.out;
  }
}

// stderr carries only usage errors and a report that could not be written.
TEST(CliCheck, StderrHoldsUsageErrorsAndAReportThatCouldNotBeWritten) {
  Files f;
  auto usage = gonio({"check", f.warned, "--frob"});
  EXPECT_EQ(usage.exit_code, 2);
  EXPECT_TRUE(usage.out.empty()) << usage.out;
  EXPECT_TRUE(contains(usage.err, "gonio: check: unknown option '--frob'")) << usage.err;

  // Standard output on a full disk: the findings are lost, and said to be.
  auto full = test::run_process(
      {"/bin/sh", "-c", "exec \"$0\" check \"$1\" >/dev/full", GONIO_EXECUTABLE, f.warned});
  EXPECT_EQ(full.exit_code, 1) << full.err;
  EXPECT_EQ(full.err.rfind("gonio: cannot write the standard output", 0), 0u) << full.err;
  EXPECT_EQ(std::count(full.err.begin(), full.err.end(), '\n'), 1) << full.err;  // said once
}

TEST(CliCheck, Isym3OrderOptionIsAccepted) {
  Files f;
  auto r = gonio({"check", f.clean_ldt, "--ldt-isym3", "qlumedit"});
  EXPECT_EQ(r.exit_code, kClean) << r.out << r.err;
}

}  // namespace
}  // namespace gonio
