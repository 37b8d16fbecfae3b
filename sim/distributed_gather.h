// Variable-length gathers across the ranks of an MPI job (sim/distributed.h):
// what `gonio optimize` needs beyond the simulation's integer sums (the
// escaped photons of a shared trace, the merits of a generation's points).
// Implemented in sim/distributed.cpp, the only file that calls MPI; a job of
// one (or a build without MPI) returns this rank's bytes alone.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "sim/distributed.h"

namespace gonio::sim {

// The most bytes one MPI call of gather_bytes (or Ranks::sum) moves: MPI
// counts and displacements are ints, so larger payloads travel in pieces.
inline constexpr std::size_t kMaxBytesPerMpiCall = std::size_t{1} << 30;

// Every rank's `bytes`, by rank, on every rank, whatever their sizes (any
// rank's or their total beyond 2³¹ bytes too). Collective. The payloads
// travel in rounds of MPI_Allgatherv, each moving at most
// `max_bytes_per_call` bytes in all (each rank at most its share of them,
// max_bytes_per_call / ranks, at least 1); the result does not depend on
// it (tests set it small to cross several rounds).
std::vector<std::string> gather_bytes(const Ranks& ranks, const std::string& bytes,
                                      std::size_t max_bytes_per_call = kMaxBytesPerMpiCall);

// Ranks::sum in pieces of at most `max_values_per_call` values per MPI call
// (Ranks::sum: kMaxBytesPerMpiCall bytes a piece); the same sums whatever
// the piece size. Collective.
void sum_in_pieces(const Ranks& ranks, std::vector<std::uint64_t>& values,
                   std::size_t max_values_per_call);

}  // namespace gonio::sim
