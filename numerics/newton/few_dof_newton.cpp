#include "numerics/newton/few_dof_newton.hpp"
#include "numerics/util/error.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace yarnfit::numerics {

Problems FewDofNewtonOptions::problems() const {
  Problems out;
  if (max_steps < 0) out.add_field("max_steps", "must be ≥ 0");
  if (!(max_step > 0.0) || !std::isfinite(max_step)) out.add_field("max_step", "must be positive and finite");
  if (halvings < 0) out.add_field("halvings", "must be ≥ 0");
  if (!(armijo > 0.0 && armijo < 0.5)) out.add_field("armijo", "must be in (0, 0.5)");
  return out;
}

namespace detail {
void throw_if_invalid(const FewDofNewtonOptions& options) {
  if (const Problems problems = options.problems(); !problems.empty())
    throw Error(ErrorCategory::input, "minimise_few_dofs: " + problems.one_line());
}
}  // namespace detail

const char* to_string(FewDofNewtonStatus status) {
  switch (status) {
    case FewDofNewtonStatus::converged: return "converged";
    case FewDofNewtonStatus::max_steps: return "max_steps";
    case FewDofNewtonStatus::no_descent: return "no_descent";
    case FewDofNewtonStatus::evaluation_failed: return "evaluation_failed";
  }
  return "unknown";
}

}  // namespace yarnfit::numerics
