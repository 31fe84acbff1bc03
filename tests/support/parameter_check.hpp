#pragma once
// Central differences in one parameter θ of a scalar and a vector that depend on it (an
// energy and its gradient, a read-out and its vector of stresses) against their analytic
// derivatives, keeping the best step of a sweep of relative steps h = rel · |θ| (truncation
// falls as h², round-off and solver noise grow as 1/h):
//
//   err(h) = |FD_h − analytic| / max(|analytic|, floor)   (∞-norm for the vector)
//
// Used by the parameter-derivative tests of the yarn elements, terms, equilibria and the
// calibration residuals.

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace yarnfit::testing {

struct ParameterSweep {
  double value_error = std::numeric_limits<double>::infinity();
  double vector_error = std::numeric_limits<double>::infinity();
  double value_step = 0.0, vector_step = 0.0;
  double value_fd = 0.0;         // at the best step
  Eigen::Index worst = 0;        // worst vector entry at the best step
  double worst_fd = 0.0;
};

// eval(θ) returns {value, vector}; d_value and d_vector are the analytic derivatives at θ.
template <class Eval>
ParameterSweep sweep_parameter(Eval&& eval, double theta, double d_value, const Eigen::VectorXd& d_vector,
                               double value_floor, double vector_floor,
                               const std::vector<double>& relative_steps = {1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5,
                                                                            1e-5, 1e-6, 1e-7}) {
  ParameterSweep best;
  const double value_norm = std::max(std::abs(d_value), value_floor);
  const double vector_norm = std::max(d_vector.size() > 0 ? d_vector.lpNorm<Eigen::Infinity>() : 0.0, vector_floor);
  for (const double rel : relative_steps) {
    const double h = rel * std::max(std::abs(theta), 1e-300);
    const auto [vp, gp] = eval(theta + h);
    const auto [vm, gm] = eval(theta - h);
    const double fd = (vp - vm) / (2.0 * h);
    const double ev = std::abs(fd - d_value) / value_norm;
    if (ev < best.value_error) {
      best.value_error = ev;
      best.value_step = h;
      best.value_fd = fd;
    }
    if (d_vector.size() == 0) continue;
    const Eigen::VectorXd fdv = (gp - gm) / (2.0 * h);
    Eigen::Index worst = 0;
    const double eg = (fdv - d_vector).cwiseAbs().maxCoeff(&worst) / vector_norm;
    if (eg < best.vector_error) {
      best.vector_error = eg;
      best.vector_step = h;
      best.worst = worst;
      best.worst_fd = fdv(worst);
    }
  }
  if (d_vector.size() == 0) best.vector_error = 0.0;
  return best;
}

}  // namespace yarnfit::testing
