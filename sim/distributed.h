// One simulation over many processes: the ranks of an MPI job (mpirun, srun).
//
// The same discipline as the threads: every iteration's photon chunks are
// split by index range across the ranks (rank_share), each rank traces its
// range into integer accumulators, and the accumulators are summed across
// the ranks (Ranks::sum). Integer sums do not depend on their order, so any
// rank count gives the bytes one process gives. Every MPI call is in
// distributed.cpp; a build without MPI (GONIO_MPI=OFF) has the same
// interface, always a job of one.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "photometry/diagnostics.h"

namespace gonio::sim {

// Items [begin, end).
struct IndexRange {
  std::uint64_t begin = 0;
  std::uint64_t end = 0;
  std::uint64_t size() const { return end - begin; }
};

// The share of `count` items that rank `rank` of `ranks` (0 ≤ rank < ranks)
// takes: contiguous ranges in rank order that cover [0, count), the first
// count % ranks of them one item longer than the others.
IndexRange rank_share(std::uint64_t count, int rank, int ranks);

// Whether this build can join MPI jobs (configured with GONIO_MPI on and an
// MPI library found).
bool mpi_built_in();

// Whether the environment says this process was started by an MPI launcher
// (mpirun / mpiexec of Open MPI, srun or another PMI launcher), whatever the
// build.
bool launched_by_mpi();

// This process's place in its job, and the collective operations the
// simulation needs. Collective calls must be made by every rank in the same
// order; they are no-ops in a job of one. Move-only: the object that joined
// the job ends it (MPI_Finalize) when destroyed.
class Ranks {
 public:
  // A job of this process alone.
  Ranks() = default;
  ~Ranks();
  Ranks(Ranks&& other) noexcept;
  Ranks& operator=(Ranks&& other) noexcept;
  Ranks(const Ranks&) = delete;
  Ranks& operator=(const Ranks&) = delete;

  // Joins the MPI job this process was launched in (launched_by_mpi()), or
  // returns a job of one where there is none. An error where the launcher's
  // environment is there but this build has no MPI (it would otherwise run
  // the whole simulation once per rank) or MPI cannot start. At most one
  // Ranks per process may join.
  static Result<Ranks> join_job();

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool distributed() const { return size_ > 1; }
  // "rank R of N" for this rank, or for rank `rank` of this job.
  std::string name() const { return name_of(rank_); }
  std::string name_of(int rank) const;

  // Element-wise sums across every rank, in place, the same on every rank.
  // Collective.
  void sum(std::vector<std::uint64_t>& values) const;
  // Every rank's `value`, by rank, on every rank. Collective.
  std::vector<std::uint64_t> gather(std::uint64_t value) const;
  std::vector<double> gather(double value) const;
  // Returns when every rank has called it. Collective.
  void barrier() const;
  // Ends every rank of the job with `exit_code` (MPI_Abort); exit() in a job
  // of one. For a failure that leaves the ranks unable to meet again.
  [[noreturn]] void abort(int exit_code) const;

 private:
  int rank_ = 0;
  int size_ = 1;
  bool joined_ = false;  // this object called MPI_Init and must finalize
};

}  // namespace gonio::sim
