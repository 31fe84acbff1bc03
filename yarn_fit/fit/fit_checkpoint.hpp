#pragma once
// The yarn fit's checkpoint, so that a fit killed in any stage resumes to bitwise the result
// of an uninterrupted one (issue 33). One JSON file (YarnFitSettings::checkpoint, written whole
// or not at all) holds what the stages produced that is not recomputed for free on resume:
//  * the rescored candidates of the staged search (the local step's starts, with their g);
//  * every finished local run (its best point and g, rounds, and the linearisation at its
//    best for the identifiability profile).
// The swarm stages keep their own checkpoints beside it (<file>.<stage>, swarm/checkpoint.cpp),
// written after every iteration: a resumed swarm continues from its last iteration, a finished
// one returns its summary without evaluating. A local run that was in progress is run again
// from its start: runs are deterministic, so it ends where it would have. Doubles are written
// with 17 significant digits, which round-trips every finite double.

#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <vector>

#include "yarn_fit/fit/alternation.hpp"
#include "yarn_fit/fit/global_search.hpp"

namespace yarnfit::yarn {

struct FitCheckpoint {
  std::optional<std::vector<GlobalCandidate>> rescored;  // the staged search's starts, best first
  std::vector<std::optional<AlternationSummary>> local;  // per start, when that run finished
};

// Throws an Error naming the file and the field when it cannot be read.
FitCheckpoint read_fit_checkpoint(const std::filesystem::path& file);
// Written atomically; throws an Error naming the file when it cannot be.
void write_fit_checkpoint(const std::filesystem::path& file, const FitCheckpoint& checkpoint);
// Removes the file and its stages' swarm checkpoints beside it (what a fit starting afresh does).
void remove_fit_checkpoint(const std::filesystem::path& file);

}  // namespace yarnfit::yarn
