#pragma once
// The thesis's local step (6.5.3: the swarm's best particle is refined by COBYLA) on a
// ParameterSpace: numerics' COBYLA wrapper (numerics/optim/cobyla.hpp, which keeps NLopt's
// pitfalls from the caller) run in the space's unit cube (log-space parameters per decade), so
// initial_step and x_tolerance are fractions of each parameter's range.

#include <Eigen/Core>

#include "numerics/optim/cobyla.hpp"
#include "swarm/objective.hpp"
#include "swarm/parameter_space.hpp"

namespace yarnfit::swarm {

using numerics::CobylaSettings;
using numerics::CobylaStatus;
using numerics::CobylaSummary;
using numerics::is_converged;
using numerics::to_string;

// Minimises objective from `start` (caller's coordinates, inside the bounds); best point and
// failures are reported in the caller's coordinates. Throws an input Error for invalid
// settings (initial_step in (0, 1], x_tolerance in [0, 1): fractions of the ranges) or a start
// outside the bounds; failed evaluations and NLopt failures are reported in the summary.
[[nodiscard]] CobylaSummary run_cobyla(const ParameterSpace& space, const Objective& objective,
                                       const Eigen::VectorXd& start, const CobylaSettings& settings = {});

}  // namespace yarnfit::swarm
