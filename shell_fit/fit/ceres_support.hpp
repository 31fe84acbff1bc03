#pragma once
// What the shell fits share in driving Ceres: dense least squares on a few log-parameters,
// stopping tolerances chosen per fit (they must sit above the noise of the inner equilibrium
// solves), and progress reported through a plain callback.

#include <ceres/ceres.h>

#include <functional>
#include <utility>

namespace yarnfit::shell {

// Forwards Ceres iterations to fn(iteration, cost, seconds so far).
class ProgressCallback : public ceres::IterationCallback {
 public:
  explicit ProgressCallback(std::function<void(int, double, double)> fn) : m_fn(std::move(fn)) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    if (m_fn) m_fn(s.iteration, s.cost, s.cumulative_time_in_seconds);
    return ceres::SOLVER_CONTINUE;
  }

 private:
  std::function<void(int, double, double)> m_fn;
};

inline ceres::Solver::Options least_squares_options(int max_iterations, double function_tolerance,
                                                    double parameter_tolerance,
                                                    ProgressCallback* progress, bool report_progress) {
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = max_iterations;
  so.function_tolerance = function_tolerance;
  so.gradient_tolerance = 1e-10;
  so.parameter_tolerance = parameter_tolerance;
  so.num_threads = 1;  // parallelism is in the scenes
  if (report_progress && progress) {
    so.callbacks.push_back(progress);
    so.update_state_every_iteration = true;
  }
  return so;
}

}  // namespace yarnfit::shell
