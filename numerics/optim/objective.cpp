#include "numerics/optim/objective.hpp"

#include <cmath>
#include <exception>
#include <sstream>

namespace yarnfit::numerics {

Evaluation evaluate_guarded(const std::function<double()>& f) noexcept {
  Evaluation e;
  try {
    const double v = f();
    if (std::isfinite(v)) {
      e.value = v;
      e.ok = true;
    } else {
      e.message = std::isnan(v) ? "objective returned NaN" : (v > 0 ? "objective returned +inf" : "objective returned -inf");
    }
  } catch (const std::exception& ex) {
    try {
      e.message = std::string("objective threw: ") + ex.what();
    } catch (...) {
      // Out of memory while copying the message: the failure is still counted.
    }
  } catch (...) {
    try {
      e.message = "objective threw an exception not derived from std::exception";
    } catch (...) {
    }
  }
  return e;
}

void keep_failure(std::vector<FailedEvaluation>& failures, int max_kept, int evaluation, int iteration, int particle,
                  const Eigen::VectorXd& x, const std::string& message) noexcept {
  if (static_cast<int>(failures.size()) >= max_kept) return;
  try {
    failures.push_back({evaluation, iteration, particle, x, message});
  } catch (...) {
    // Out of memory for the record: the failure is still counted by the caller.
  }
}

void add_local_stopping_problems(Problems& out, int max_evaluations, double max_seconds, double stop_value,
                                 int max_failures_kept) {
  if (max_evaluations < 1)
    out.add_field("max_evaluations", "must be at least 1 (got " + std::to_string(max_evaluations) + ")");
  if (!(max_seconds >= 0.0) || std::isinf(max_seconds)) out.add_field("max_seconds", "must be finite and ≥ 0 (0: no limit)");
  if (std::isnan(stop_value)) out.add_field("stop_value", "must not be NaN (-inf: off)");
  if (max_failures_kept < 0) out.add_field("max_failures_kept", "must be ≥ 0");
}

}  // namespace yarnfit::numerics
