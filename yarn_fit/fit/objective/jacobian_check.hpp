#pragma once
// The residual Jacobian of the yarn objective (evaluate_at_rest: exact sensitivities) against
// central differences of the residuals themselves, per parameter: the check behind issue 33's
// "residual Jacobian against central differences ≤ 1e-4 relative" (bench_calibration
// jacobian, tests/yarn_fit/fit).
//
// The differences re-solve every sample at θ ± h on the same held rest state; for them to
// resolve the derivative the objective should solve its equilibria and compression roots
// tightly (a force tolerance far below the default and a narrow compression band): that is
// what "smooth cases" means. Per parameter the best of a sweep of relative steps is kept.

#include <Eigen/Core>
#include <span>
#include <string>
#include <vector>

#include "yarn_fit/fit/objective/yarn_objective.hpp"

namespace yarnfit::yarn {

struct JacobianColumnCheck {
  yarn::YarnParam param = yarn::YarnParam::ks1;
  double relative_error = 0.0;  // min over steps of ‖J_k − FD_k‖∞ / ‖J_k‖∞
  double step = 0.0;            // relative step of the best difference
  double column_norm = 0.0;     // ‖J_k‖∞ (dr/d log θ: the column times θ)
  Eigen::Index worst_row = 0;
};

struct JacobianCheck {
  bool ok = false;
  std::string message;
  std::vector<JacobianColumnCheck> columns;
  double worst = 0.0;           // the largest relative error over the columns
  int evaluations = 0;
  double seconds = 0.0;
};

// At `params` on `rest` (a rest state of the objective), for the parameters `wanted`.
JacobianCheck check_residual_jacobian(const YarnObjective& objective, const RestState& rest,
                                      const yarn::YarnParams& params, std::span<const yarn::YarnParam> wanted,
                                      const std::vector<double>& relative_steps = {1e-3, 3e-4, 1e-4, 3e-5});

}  // namespace yarnfit::yarn
