#pragma once
// What the shell fits share in driving Ceres: dense least squares on a few log-parameters,
// stopping tolerances chosen per fit (they must sit above the noise of the inner equilibrium
// solves), and progress reported through a plain callback.

#include <ceres/ceres.h>
#include <glog/logging.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <utility>

#include "numerics/util/clock.hpp"
#include "numerics/progress.hpp"

namespace yarnfit::shell {

// Forwards Ceres iterations as progress events: the stage's name, the iteration and the
// stage's iteration budget, the best error so far (error_of(cost) over this and earlier
// stages: the root-mean-square residual in percent of the mean measured value) and the
// seconds since `start`.
class ProgressCallback : public ceres::IterationCallback {
 public:
  ProgressCallback(numerics::ProgressFn fn, numerics::Clock::time_point start,
                   std::function<double(double)> error_of)
      : m_fn(std::move(fn)), m_start(start), m_error_of(std::move(error_of)) {}
  // A new stage: its name, its budget of iterations (0: unknown) and what a step is.
  void set_stage(std::string stage, int steps = 0, std::string step_name = "iteration") {
    m_stage = std::move(stage);
    m_steps = steps;
    m_step_name = std::move(step_name);
  }
  // Reports a step that is not a Ceres iteration (a start search's trial).
  void report(int iteration, double cost) {
    if (std::isfinite(cost)) m_best = std::min(m_best, m_error_of(cost));
    if (!m_fn) return;
    numerics::Progress p;
    p.stage = m_stage;
    p.step_name = m_step_name;
    p.step = iteration;
    p.steps = m_steps;
    p.budget = m_steps > 0;  // Ceres may converge before its iteration limit
    p.best = std::isfinite(m_best) ? m_best : std::numeric_limits<double>::quiet_NaN();
    p.best_label = "rms error";
    p.best_unit = "%";
    p.seconds = numerics::seconds_since(m_start);
    m_fn(p);
  }
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    report(s.iteration, s.cost);
    return ceres::SOLVER_CONTINUE;
  }
  [[nodiscard]] bool active() const { return static_cast<bool>(m_fn); }

 private:
  numerics::ProgressFn m_fn;
  numerics::Clock::time_point m_start;
  std::function<double(double)> m_error_of;
  std::string m_stage;
  int m_steps = 0;
  std::string m_step_name = "iteration";
  double m_best = std::numeric_limits<double>::infinity();
};

// Ceres logs a warning for every trial point whose evaluation fails, and an error when a start
// cannot be evaluated; the fits return false on purpose there (a scene did not reach
// equilibrium: Ceres shrinks its step, or the fit tries its next start) and report every
// outcome through Ceres' summary, so those lines are noise on the user's terminal.
inline void quiet_solver_warnings() { FLAGS_minloglevel = std::max(FLAGS_minloglevel, 3); }

inline ceres::Solver::Options least_squares_options(int max_iterations, double function_tolerance,
                                                    double parameter_tolerance,
                                                    ProgressCallback* progress) {
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = max_iterations;
  so.function_tolerance = function_tolerance;
  so.gradient_tolerance = 1e-10;
  so.parameter_tolerance = parameter_tolerance;
  so.num_threads = 1;  // parallelism is in the scenes
  so.logging_type = ceres::SILENT;
  if (progress) {
    so.callbacks.push_back(progress);
    so.update_state_every_iteration = true;
  }
  return so;
}

}  // namespace yarnfit::shell
