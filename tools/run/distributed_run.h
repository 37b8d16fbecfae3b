// How a subcommand runs as one rank of an MPI job (sim/distributed.h):
// join the job, agree before tracing that every rank holds the same model
// and settings, and the per-rank figures report.json records. Rank 0 alone
// writes files and shows progress; the other ranks trace their shares and
// print only their errors.
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "sim/distributed.h"
#include "sim/scene.h"
#include "sim/simulation.h"

namespace gonio::cli {

// Joins the MPI job gonio was launched in, or a job of one without a
// launcher. Prints the error and returns nothing where it cannot (an MPI
// launcher around a build without MPI).
std::optional<sim::Ranks> join_job(const std::string& command);

// What must be equal on every rank for the ranks' shares to make one run:
// the loaded scene (scene_hash: geometry, materials, emitters and their
// profiles, so a different file, buffer or profile counts) and the
// settings that shape the photons. 16 hex digits.
std::string run_fingerprint(const sim::SceneDesc& scene, const sim::SimulationSettings& settings);

// Collective, before tracing: `fingerprint` is this rank's run_fingerprint,
// or nothing where this rank could not get ready (could not read its model,
// make the output folder, …: its own error already printed). True on every
// rank when every rank is ready with the same fingerprint; otherwise rank 0
// prints "gonio: COMMAND: rank R of N ..." for each rank at fault (could not
// get ready, or a fingerprint other than rank 0's) and every rank returns
// false. In a job of one: whether `fingerprint` is set, printing nothing.
bool ranks_agree(const sim::Ranks& ranks, const std::optional<std::string>& fingerprint,
                 const std::string& command);

// Collective, after tracing: {"ranks": N, "per_rank": [{"rank", "photons",
// "threads", "trace_s", "photons_per_s", "wait_s", "reduce_s",
// "reduce_fastest_s"}]} from each rank's
// stats (sim/simulation.h), the same on every rank.
nlohmann::json ranks_json(const sim::Ranks& ranks, const sim::SimulationStats& stats);

}  // namespace gonio::cli
