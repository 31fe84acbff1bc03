#pragma once
// The swarm's objectives: the generic ones of numerics/optim/objective.hpp, and the context a
// particle's evaluation is given.

#include <Eigen/Core>
#include <functional>
#include <limits>

#include "numerics/optim/objective.hpp"

namespace yarnfit::swarm {

using numerics::evaluate_guarded;
using numerics::Evaluation;
using numerics::FailedEvaluation;
using numerics::keep_failure;
using numerics::add_local_stopping_problems;
using numerics::Objective;

// Which particle is being evaluated, so that an objective can keep per-particle state (for
// example a warm start from the particle's previous position). iteration counts from 1.
//
// cutoff is the particle's best value so far (+inf until it has one). A value at or above it
// changes nothing in the swarm (neither the particle's best nor the swarm's), so an
// objective that accumulates non-negative terms may stop as soon as its partial sum reaches
// the cutoff and return that partial sum: a lower bound, at or above the cutoff. The run is
// then the same as with the exact value; only the iteration's statistics see the bound.
struct ParticleContext {
  int iteration = 0;
  int particle = 0;
  double cutoff = std::numeric_limits<double>::infinity();
};
using ParticleObjective = std::function<double(const Eigen::VectorXd& x, const ParticleContext& context)>;

}  // namespace yarnfit::swarm
