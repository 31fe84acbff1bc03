#include "numerics/roots/chord_newton.hpp"
#include "numerics/util/error.hpp"

#include <Eigen/LU>
#include <cmath>
#include <stdexcept>

namespace yarnfit::numerics {

Problems ChordNewtonOptions::problems() const {
  Problems out;
  if (steps < 0) out.add_field("steps", "must be ≥ 0");
  if (!(max_abs > 0.0) || !std::isfinite(max_abs)) out.add_field("max_abs", "must be positive and finite");
  if (!(jacobian_step > 0.0) || !std::isfinite(jacobian_step)) out.add_field("jacobian_step", "must be positive and finite");
  return out;
}

ChordNewtonResult chord_newton(ChordNewtonProblem& problem, const Eigen::VectorXd& x0, const Eigen::VectorXd& f0,
                               const ChordNewtonOptions& options) {
  if (const Problems problems = options.problems(); !problems.empty())
    throw Error(ErrorCategory::input, "chord_newton: " + problems.one_line());
  const Eigen::Index n = x0.size();
  if (f0.size() != n) throw Error(ErrorCategory::input, "chord_newton: F(x0) and x0 differ in size");
  ChordNewtonResult out;
  out.x = x0;
  out.f = f0;
  const double h = options.jacobian_step;
  Eigen::MatrixXd jacobian(n, n);
  Eigen::VectorXd fk;
  for (Eigen::Index k = 0; k < n; ++k) {
    ++out.evaluations;
    if (!problem.evaluate(x0 + h * Eigen::VectorXd::Unit(n, k), fk)) {
      out.status = ChordNewtonStatus::jacobian_failed;
      return out;
    }
    jacobian.col(k) = (fk - f0) / h;
  }
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(jacobian);
  if (!lu.isInvertible()) {
    out.status = ChordNewtonStatus::jacobian_failed;
    return out;
  }
  Eigen::VectorXd x = x0, f = f0;
  double best = f0.cwiseAbs().maxCoeff();
  for (int step = 0; step < options.steps; ++step) {
    x = (x - lu.solve(f)).cwiseMax(-options.max_abs).cwiseMin(options.max_abs);
    ++out.evaluations;
    if (!problem.evaluate(x, f)) break;
    if (f.cwiseAbs().maxCoeff() < best) {
      best = f.cwiseAbs().maxCoeff();
      out.x = x;
      out.f = f;
      problem.keep();
    }
  }
  return out;
}

}  // namespace yarnfit::numerics
