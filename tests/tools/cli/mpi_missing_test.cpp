// Stands in for the MPI suites (gonio_mpi_tests, gonio_sim_mpi_tests) in a
// build configured without MPI, so that they do not vanish unseen: a skip
// naming what is missing, and under CI=true a failure (GONIO_MISSING).
#include <gtest/gtest.h>

#include <string>

#include "tests/support/test_support.h"

namespace {

TEST(Mpi, SuitesAreBuiltOnlyWithMpi) {
  GONIO_MISSING(std::string(GONIO_MPI_MISSING) +
                ": the MPI suites gonio_mpi_tests and gonio_sim_mpi_tests were not built");
}

}  // namespace
