#pragma once
// Internal: the complete state of a swarm run between two iterations, and its checkpoint
// file. Everything the next iteration reads is here, so a run restored from the file
// continues bitwise like one that never stopped.

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "swarm/particle_swarm.hpp"

namespace yarnfit::swarm::detail {

struct SwarmState {
  SwarmSettings settings;
  int iterations_done = 0;
  std::string random_state;  // RandomStream::state() after the last draw
  // Unit-cube coordinates, one column per particle (d × N).
  Eigen::MatrixXd position;
  Eigen::MatrixXd velocity;
  Eigen::MatrixXd best_position;  // each particle's best
  Eigen::VectorXd best_value;     // N; +inf while the particle has no successful evaluation
  // The swarm's best, unit cube; meaningful when best.usable().
  Eigen::VectorXd global_best;
  // Best value, history, counters, failures and time, as reported.
  SwarmSummary summary;
};

// Writes the state to `path` through a temporary file in the same folder renamed over it
// (atomic on POSIX), so a reader never sees half a file. Throws an Error.
void write_checkpoint(const std::filesystem::path& path, const ParameterSpace& space, const SwarmState& state);

// Reads a checkpoint written by write_checkpoint for this space. Throws an Error
// naming the file and the field (missing, wrong type, wrong size, other space).
[[nodiscard]] SwarmState read_checkpoint(const std::filesystem::path& path, const ParameterSpace& space);

}  // namespace yarnfit::swarm::detail
