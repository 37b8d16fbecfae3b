#include "sim/distributed.h"
#include "sim/distributed_gather.h"

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <utility>

#ifdef GONIO_WITH_MPI
#include <mpi.h>
#endif

namespace gonio::sim {

IndexRange rank_share(std::uint64_t count, int rank, int ranks) {
  GONIO_CHECK(ranks >= 1 && rank >= 0 && rank < ranks);
  const auto n = static_cast<std::uint64_t>(ranks);
  const auto r = static_cast<std::uint64_t>(rank);
  const std::uint64_t base = count / n, extra = count % n;
  const std::uint64_t begin = r * base + std::min(r, extra);
  return {begin, begin + base + (r < extra ? 1 : 0)};
}

bool mpi_built_in() {
#ifdef GONIO_WITH_MPI
  return true;
#else
  return false;
#endif
}

bool launched_by_mpi() {
  // Open MPI's mpirun, PMIx launchers (srun --mpi=pmix, prterun), PMI-1/2
  // launchers (srun --mpi=pmi2, MPICH's hydra).
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    if (std::getenv(name) != nullptr) return true;
  return false;
}

Ranks::~Ranks() {
#ifdef GONIO_WITH_MPI
  if (joined_) MPI_Finalize();
#endif
}

Ranks::Ranks(Ranks&& other) noexcept
    : rank_(other.rank_), size_(other.size_), joined_(std::exchange(other.joined_, false)) {}

Ranks& Ranks::operator=(Ranks&& other) noexcept {
  if (this != &other) {
    std::swap(rank_, other.rank_);
    std::swap(size_, other.size_);
    std::swap(joined_, other.joined_);
  }
  return *this;
}

Result<Ranks> Ranks::join_job() {
  Ranks r;
  if (!launched_by_mpi()) return r;
#ifdef GONIO_WITH_MPI
  int initialised = 0;
  MPI_Initialized(&initialised);
  GONIO_CHECK_MSG(!initialised, "Ranks::join_job called twice");
  // A rank waiting in a collective yields its core rather than spinning on
  // it (Open MPI; unless the user chose): gonio meets once per iteration,
  // and a spinning rank takes the core from tracing threads wherever cores
  // are shared — measured 34–36 ms against 6–14 ms per reduction with 2
  // ranks on a loaded 2-core machine.
  setenv("OMPI_MCA_mpi_yield_when_idle", "1", 0);
  // Only the main thread calls MPI; the tracing threads never do.
  int provided = 0;
  if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
    return make_error("MPI could not start (MPI_Init_thread failed)");
  r.joined_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &r.rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &r.size_);
  return r;
#else
  return make_error(
                    "this gonio was built without MPI (GONIO_MPI=OFF) but was started by an MPI "
                    "launcher: every rank would run the whole simulation alone; run it without "
                    "mpirun/srun, or build with MPI (libopenmpi-dev)");
#endif
}

std::string Ranks::name_of(int rank) const {
  return "rank " + std::to_string(rank) + " of " + std::to_string(size_);
}

void Ranks::sum(std::vector<std::uint64_t>& values) const {
  sum_in_pieces(*this, values, kMaxBytesPerMpiCall / sizeof(std::uint64_t));
}

void sum_in_pieces(const Ranks& ranks, std::vector<std::uint64_t>& values,
                   std::size_t max_values_per_call) {
  GONIO_CHECK(max_values_per_call >= 1);
  if (ranks.size() == 1 || values.empty()) return;
#ifdef GONIO_WITH_MPI
  const std::size_t piece =
      std::min(max_values_per_call, static_cast<std::size_t>(std::numeric_limits<int>::max()));
  for (std::size_t begin = 0; begin < values.size(); begin += piece) {
    const std::size_t n = std::min(piece, values.size() - begin);
    MPI_Allreduce(MPI_IN_PLACE, values.data() + begin, static_cast<int>(n), MPI_UINT64_T, MPI_SUM,
                  MPI_COMM_WORLD);
  }
#endif
}

std::vector<std::uint64_t> Ranks::gather(std::uint64_t value) const {
  std::vector<std::uint64_t> all(static_cast<std::size_t>(size_), value);
#ifdef GONIO_WITH_MPI
  if (size_ > 1)
    MPI_Allgather(&value, 1, MPI_UINT64_T, all.data(), 1, MPI_UINT64_T, MPI_COMM_WORLD);
#endif
  return all;
}

std::vector<double> Ranks::gather(double value) const {
  std::vector<double> all(static_cast<std::size_t>(size_), value);
#ifdef GONIO_WITH_MPI
  if (size_ > 1) MPI_Allgather(&value, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, MPI_COMM_WORLD);
#endif
  return all;
}

std::vector<std::string> gather_bytes(const Ranks& ranks, const std::string& bytes,
                                      std::size_t max_bytes_per_call) {
  GONIO_CHECK(max_bytes_per_call >= 1);
  std::vector<std::string> all(static_cast<std::size_t>(ranks.size()));
  if (ranks.size() == 1) {
    all[0] = bytes;
    return all;
  }
#ifdef GONIO_WITH_MPI
  const std::vector<std::uint64_t> sizes = ranks.gather(static_cast<std::uint64_t>(bytes.size()));
  const auto n_ranks = static_cast<std::size_t>(ranks.size());
  // Each round moves at most `share` bytes of each rank's payload, so at
  // most max_bytes_per_call (and under 2³¹) bytes in all: its counts and
  // displacements fit an int.
  const std::size_t call =
      std::min(max_bytes_per_call, static_cast<std::size_t>(std::numeric_limits<int>::max()));
  const std::size_t share = std::max<std::size_t>(1, call / n_ranks);
  std::uint64_t largest = 0;
  for (std::size_t r = 0; r < n_ranks; ++r) {
    all[r].reserve(static_cast<std::size_t>(sizes[r]));
    largest = std::max(largest, sizes[r]);
  }
  std::vector<int> counts(n_ranks), offsets(n_ranks);
  std::string round;
  for (std::uint64_t begin = 0; begin < largest; begin += share) {
    std::size_t total = 0;
    for (std::size_t r = 0; r < n_ranks; ++r) {
      const std::uint64_t n = sizes[r] > begin ? std::min<std::uint64_t>(share, sizes[r] - begin) : 0;
      counts[r] = static_cast<int>(n);
      offsets[r] = static_cast<int>(total);
      total += static_cast<std::size_t>(n);
    }
    round.assign(total, '\0');
    const std::size_t mine = static_cast<std::size_t>(ranks.rank());
    MPI_Allgatherv(bytes.data() + std::min<std::size_t>(static_cast<std::size_t>(begin), bytes.size()),
                   counts[mine], MPI_BYTE, round.data(), counts.data(), offsets.data(), MPI_BYTE,
                   MPI_COMM_WORLD);
    for (std::size_t r = 0; r < n_ranks; ++r)
      all[r].append(round, static_cast<std::size_t>(offsets[r]), static_cast<std::size_t>(counts[r]));
  }
#else
  all[static_cast<std::size_t>(ranks.rank())] = bytes;
#endif
  return all;
}

void Ranks::barrier() const {
#ifdef GONIO_WITH_MPI
  if (size_ > 1) MPI_Barrier(MPI_COMM_WORLD);
#endif
}

void Ranks::abort(int exit_code) const {
#ifdef GONIO_WITH_MPI
  int initialised = 0, finalised = 0;
  MPI_Initialized(&initialised);
  MPI_Finalized(&finalised);
  if (initialised && !finalised) MPI_Abort(MPI_COMM_WORLD, exit_code);
#endif
  std::exit(exit_code);
}

}  // namespace gonio::sim
