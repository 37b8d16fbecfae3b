// The MPI seam's parts that need no launcher: how chunks are shared among
// ranks, when a process counts as launched by MPI, and a job of one.
#include "sim/distributed.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

namespace gonio::sim {
namespace {

TEST(RankShare, SharesCoverTheRangeInRankOrderAndDifferByAtMostOne) {
  for (std::uint64_t count : {0ull, 1ull, 2ull, 7ull, 8ull, 63ull, 1000ull, 4294967295ull})
    for (int ranks : {1, 2, 3, 4, 7, 64, 1000}) {
      std::uint64_t next = 0, smallest = ~0ull, largest = 0;
      for (int r = 0; r < ranks; ++r) {
        const IndexRange s = rank_share(count, r, ranks);
        ASSERT_EQ(s.begin, next) << count << " items, rank " << r << " of " << ranks;
        ASSERT_LE(s.begin, s.end);
        next = s.end;
        smallest = std::min(smallest, s.size());
        largest = std::max(largest, s.size());
      }
      EXPECT_EQ(next, count) << count << " items over " << ranks << " ranks";
      EXPECT_LE(largest - smallest, 1u) << count << " items over " << ranks << " ranks";
    }
  // The longer shares come first: 8 chunks over 3 ranks are 3, 3, 2.
  EXPECT_EQ(rank_share(8, 0, 3).size(), 3u);
  EXPECT_EQ(rank_share(8, 1, 3).size(), 3u);
  EXPECT_EQ(rank_share(8, 2, 3).size(), 2u);
  // More ranks than items: the last ranks get none.
  EXPECT_EQ(rank_share(2, 5, 7).size(), 0u);
}

// Restores an environment variable when it goes.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    if (value) setenv(name, value, 1); else unsetenv(name);
  }
  ~ScopedEnv() {
    if (old_) setenv(name_, old_->c_str(), 1); else unsetenv(name_);
  }
 private:
  const char* name_;
  std::optional<std::string> old_;
};

TEST(Ranks, ALauncherIsRecognisedByTheEnvironmentItSets) {
  ScopedEnv a("OMPI_COMM_WORLD_SIZE", nullptr), b("PMIX_RANK", nullptr), c("PMI_RANK", nullptr),
      d("PMI_SIZE", nullptr);
  EXPECT_FALSE(launched_by_mpi());
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"}) {
    ScopedEnv set(name, "3");
    EXPECT_TRUE(launched_by_mpi()) << name;
  }
  EXPECT_FALSE(launched_by_mpi());
}

TEST(Ranks, WithoutALauncherAProcessIsAJobOfOne) {
  ScopedEnv a("OMPI_COMM_WORLD_SIZE", nullptr), b("PMIX_RANK", nullptr), c("PMI_RANK", nullptr),
      d("PMI_SIZE", nullptr);
  auto ranks = Ranks::join_job();
  ASSERT_TRUE(ranks.ok()) << ranks.error().message;
  EXPECT_EQ(ranks->rank(), 0);
  EXPECT_EQ(ranks->size(), 1);
  EXPECT_FALSE(ranks->distributed());
  EXPECT_EQ(ranks->name(), "rank 0 of 1");
  // The collectives of a job of one leave values as they are.
  std::vector<std::uint64_t> v = {1, 2, 0xffffffffffffffffull};
  ranks->sum(v);
  EXPECT_EQ(v, (std::vector<std::uint64_t>{1, 2, 0xffffffffffffffffull}));
  EXPECT_EQ(ranks->gather(std::uint64_t{42}), std::vector<std::uint64_t>{42});
  EXPECT_EQ(ranks->gather(2.5), std::vector<double>{2.5});
  ranks->barrier();
}

TEST(Ranks, TheBuildSaysWhetherItHasMpi) {
  EXPECT_EQ(mpi_built_in(), GONIO_TEST_WITH_MPI != 0);
}

#if !GONIO_TEST_WITH_MPI
// (A build with MPI joins the job instead: tests/tools/cli/distributed_run_test.cpp.)
TEST(Ranks, ABuildWithoutMpiRefusesToRunUnderALauncher) {
  ScopedEnv set("OMPI_COMM_WORLD_SIZE", "3");
  auto ranks = Ranks::join_job();
  ASSERT_FALSE(ranks.ok());
  EXPECT_NE(ranks.error().message.find("without MPI"), std::string::npos) << ranks.error().message;
}
#endif

}  // namespace
}  // namespace gonio::sim
