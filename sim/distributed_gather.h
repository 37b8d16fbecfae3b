// Variable-length gathers across the ranks of an MPI job (sim/distributed.h):
// what `gonio optimize` needs beyond the simulation's integer sums (the
// escaped photons of a shared trace, the merits of a generation's points).
// Implemented in sim/distributed.cpp, the only file that calls MPI; a job of
// one (or a build without MPI) returns this rank's bytes alone.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sim/distributed.h"

namespace gonio::sim {

// Every rank's `bytes`, by rank, on every rank (each rank's at most 2³¹ − 1
// bytes). Collective.
std::vector<std::string> gather_bytes(const Ranks& ranks, const std::string& bytes);

}  // namespace gonio::sim
