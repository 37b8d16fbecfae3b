// A real client: IES files Gonio writes, loaded by three.js's IESLoader
// (npm package `three`, pinned below) under plain node, give the same
// normalised distribution as Gonio's own reader and interpolation.
//
// How IESLoader (three 0.187.0) reads a file: it scales the candela by the
// multiplier, ballast factor and ballast-lamp factor, divides by the largest
// stored value, and samples the file's grid bilinearly (in C and γ, like
// photometry::interpolate) at every whole degree of C (0…359, one row for
// rotational symmetry; C beyond the last plane mirrored back into the stored
// range) and at γ_k = k·180/179° (k = 0…179). Earlier releases differed: r170
// squared the candela values before normalising, which is why the version is
// pinned.
//
// Needs node and npm (found at configure time) and the npm registry once:
// three is installed with `npm install --no-save` into the build tree. Where
// either is missing the test skips and says why, or fails under CI=true
// (GONIO_MISSING). ctest label `client`.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "io/support/file_io.h"
#include "io/photometric/ies.h"
#include "photometry/distribution.h"
#include "tests/support/photometry_fixtures.h"
#include "tests/support/test_support.h"

namespace gonio {
namespace {

constexpr const char* kThreeVersion = "0.187.0";

std::filesystem::path three_dir() { return std::filesystem::path(GONIO_CLIENT_DIR) / "node_modules" / "three"; }

// Holds an exclusive lock on a file while it lives: ctest runs the tests of
// this suite in parallel, and two npm installs into one folder collide.
class FileLock {
 public:
  explicit FileLock(const std::filesystem::path& path) : fd_(::open(path.c_str(), O_CREAT | O_RDWR, 0644)) {
    if (fd_ >= 0) ::flock(fd_, LOCK_EX);
  }
  ~FileLock() {
    if (fd_ >= 0) ::close(fd_);  // releases the lock
  }
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  int fd_;
};

// Installs three once into the build tree; an empty string when it is there.
std::string ensure_three() {
  if (std::string(GONIO_NODE).empty() || std::string(GONIO_NPM).empty())
    return "node and npm were not found when the build was configured";
  std::filesystem::create_directories(GONIO_CLIENT_DIR);
  const FileLock lock(std::filesystem::path(GONIO_CLIENT_DIR) / "install.lock");
  if (std::filesystem::exists(three_dir() / "package.json")) {
    const auto pkg = nlohmann::json::parse(test::read_file(three_dir() / "package.json"));
    if (pkg.value("version", "") == kThreeVersion) return {};
  }
  const auto r = test::run_process({GONIO_NPM, "install", "--no-save", "--no-audit", "--no-fund", "--prefix",
                                    GONIO_CLIENT_DIR, std::string("three@") + kThreeVersion});
  if (r.exit_code != 0 || !std::filesystem::exists(three_dir() / "package.json"))
    return "npm could not install three@" + std::string(kThreeVersion) + ": " + r.err;
  return {};
}

struct LoaderTexture {
  int rows = 0, columns = 0;
  std::vector<double> values;
};

LoaderTexture load_with_three(const std::filesystem::path& ies, const std::filesystem::path& json_out) {
  const auto r = test::run_process({GONIO_NODE, std::string(GONIO_SOURCE_DIR) + "/tests/client/ies_loader_dump.mjs",
                                    three_dir().string(), ies.string(), json_out.string()});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  LoaderTexture t;
  if (r.exit_code != 0) return t;
  const auto j = nlohmann::json::parse(test::read_file(json_out));
  t.rows = j["rows"];
  t.columns = j["columns"];
  t.values = j["values"].get<std::vector<double>>();
  return t;
}

// Largest |three − Gonio| over the texture, both normalised to the peak.
double largest_difference(const std::filesystem::path& path, const LoaderTexture& t) {
  auto ies = io::read_ies(path.string());
  EXPECT_TRUE(ies.ok());
  if (!ies.ok()) return 1.0;
  const photometry::Distribution& d = ies->distribution;
  double peak = 0.0;
  for (double v : d.candela) peak = std::max(peak, v);
  const photometry::Distribution expanded = photometry::expand_symmetry(d);
  EXPECT_EQ(t.columns, 180);
  EXPECT_EQ(t.rows, d.symmetry == photometry::Symmetry::Rotational ? 1 : 360);
  double worst = 0.0;
  for (int row = 0; row < t.rows; ++row) {
    for (int k = 0; k < t.columns; ++k) {
      const double gamma = k * 180.0 / 179.0;
      const double ours = photometry::interpolate(expanded, row, gamma) / peak;
      worst = std::max(worst, std::abs(t.values[static_cast<std::size_t>(row * t.columns + k)] - ours));
    }
  }
  return worst;
}

TEST(ThreeIesLoader, ReadsGoniosIesFilesAsTheSameNormalisedDistribution) {
  if (const std::string why = ensure_three(); !why.empty()) GONIO_MISSING("three.js for the client test: " + why);
  test::TempDir dir;
  struct Case {
    const char* name;
    photometry::Symmetry symmetry;
    std::vector<double> c;
  };
  const Case cases[] = {
      {"rotational", photometry::Symmetry::Rotational, {0.0}},
      {"quadrant", photometry::Symmetry::Quadrant, test::angles(0, 90, 5)},
      {"c0-c180", photometry::Symmetry::C0_C180, test::angles(0, 180, 5)},
      {"none", photometry::Symmetry::None, test::angles(0, 360, 5)},
      {"c90-c270", photometry::Symmetry::C90_C270, test::angles(90, 270, 5)},
  };
  for (const Case& c : cases) {
    // A lobe with every asymmetry the symmetry allows (mirror images of
    // cos C and sin C terms are what each symmetry keeps).
    photometry::Distribution d =
        test::sample_c(c.symmetry, c.c, test::angles(0, 180, 2.5), [&](double cdeg, double g) {
          const double cr = cdeg * M_PI / 180.0, s = std::sin(g * M_PI / 180.0);
          double a = 1.0;
          if (c.symmetry == photometry::Symmetry::None) a += 0.4 * s * std::cos(cr) + 0.2 * s * std::sin(cr);
          if (c.symmetry == photometry::Symmetry::C0_C180) a += 0.4 * s * std::cos(cr);
          if (c.symmetry == photometry::Symmetry::C90_C270) a += 0.4 * s * std::sin(cr);
          if (c.symmetry == photometry::Symmetry::Quadrant) a += 0.4 * s * std::cos(2 * cr);
          return 500.0 * (1.2 + std::cos(g * M_PI / 180.0)) * a;
        });
    d.lamps = {photometry::LampSet{1, "LED", 3000.0, "", "", photometry::kNaN}};
    const auto path = dir / (std::string(c.name) + ".ies");
    ASSERT_TRUE(io::write_file_atomic(path.string(), io::write_ies(d, {}, nullptr)).ok());
    const LoaderTexture t = load_with_three(path, dir / (std::string(c.name) + ".json"));
    ASSERT_FALSE(t.values.empty());
    const double worst = largest_difference(path, t);
    std::printf("three.js IESLoader %s on %s.ies: largest difference %.2e of the peak\n", kThreeVersion, c.name, worst);
    EXPECT_LT(worst, 1e-6) << c.name;  // float32 texture
  }
}

TEST(ThreeIesLoader, ReadsASimulatedFileAsGonioDoes) {
  if (const std::string why = ensure_three(); !why.empty()) GONIO_MISSING("three.js for the client test: " + why);
  test::TempDir dir;
  const std::string model = std::string(GONIO_SAMPLES_DIR) + "/spotlight/spotlight.gltf";
  for (const char* version : {"2019", "2002"}) {
    const auto out = dir / version;
    const auto r = test::run_process({GONIO_EXECUTABLE, "simulate", model, "--out", out.string(), "--photons",
                                      "300000", "--iterations", "1", "--format", "ies", "--ies-version", version});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const LoaderTexture t = load_with_three(out / "spotlight.ies", out / "three.json");
    ASSERT_FALSE(t.values.empty());
    const double worst = largest_difference(out / "spotlight.ies", t);
    std::printf("three.js IESLoader %s on a simulated LM-63-%s file: largest difference %.2e of the peak\n",
                kThreeVersion, version, worst);
    EXPECT_LT(worst, 1e-6);
  }
}

}  // namespace
}  // namespace gonio
