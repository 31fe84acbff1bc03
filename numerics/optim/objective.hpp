#pragma once
// What the optimisers call (the swarm, implicit filtering, COBYLA), and how a failing call is
// caught.
//
// An evaluation fails when the objective throws or returns NaN or ±inf (a yarn simulation
// that did not converge, a parameter set the model rejects). One failure must not end a
// calibration that has spent an hour on other candidates, so the optimisers count it, keep
// its message and treat it as the worst possible value (+inf in the swarm; a large finite
// penalty in COBYLA, whose linear models cannot take inf).

#include <Eigen/Core>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "numerics/problems.hpp"

namespace yarnfit::numerics {

// f(x) with x in the caller's coordinates (inside the optimiser's bounds). The swarm calls it
// from several OpenMP threads at once, so it must be safe to call concurrently.
using Objective = std::function<double(const Eigen::VectorXd& x)>;

// One evaluation's outcome: ok with a finite value, or failed with value = +inf and why.
struct Evaluation {
  double value = std::numeric_limits<double>::infinity();
  bool ok = false;
  std::string message;
};

// Calls f and turns an exception, NaN or inf into a failed Evaluation. Never throws (it runs
// inside OpenMP regions, which an exception must not leave).
[[nodiscard]] Evaluation evaluate_guarded(const std::function<double()>& f) noexcept;

// A failed evaluation as reported in a summary.
struct FailedEvaluation {
  int evaluation = 0;  // 0-based position in the run's sequence of evaluations
  int iteration = 0;   // swarm iteration (from 1); 0 for COBYLA
  int particle = -1;   // swarm particle; -1 for COBYLA
  Eigen::VectorXd x;   // caller's coordinates
  std::string message;
};

// Keeps a failed evaluation for the summary while fewer than `max_kept` are kept. Never
// throws: out of memory, the record is lost (the caller still counts the failure).
void keep_failure(std::vector<FailedEvaluation>& failures, int max_kept, int evaluation, int iteration, int particle,
                  const Eigen::VectorXd& x, const std::string& message) noexcept;

// Adds to `out` what is wrong with the stopping settings both local optimisers share, each
// under its field's name: max_evaluations ≥ 1; max_seconds finite and ≥ 0 (0: no limit);
// stop_value not NaN (-inf: off); max_failures_kept ≥ 0.
void add_local_stopping_problems(Problems& out, int max_evaluations, double max_seconds, double stop_value,
                                 int max_failures_kept);

}  // namespace yarnfit::numerics
