#pragma once
// Newton on a function of a few variables whose every evaluation is costly (an equilibrium
// solve behind each value), with no Hessian but what the problem estimates (differences of
// its gradient): the rest-period relaxation of the yarn tile (yarn_fit/homogenise/
// rest_period.hpp) minimises the tile's energy over its two period stretches this way.
//
// Every step
//   1. asks the problem for a Hessian estimate at the current point and takes its symmetric
//      part H; where H is not safely positive definite (lowest eigenvalue ≤ 1e-6 of the
//      largest |eigenvalue|), shifts it to a lowest eigenvalue of 1e-3 of that;
//   2. solves H d = −∇f (with no usable H, d = −sign(∇f) · max_step), and caps d to
//      ‖d‖∞ ≤ max_step;
//   3. tries x + d, x + d/2, … (halvings + 1 trials) and accepts the first whose value meets
//      the Armijo condition, or, where f no longer resolves the change (|Δf| ≤ 1e-12 |f|),
//      whose residual is smaller. A trial the problem cannot evaluate is skipped.
// Converged when the problem's residual (its own stopping measure, scaled so that 1 is its
// tolerance) is at most 1. Unlike solve_newton (newton_solver.hpp) it keeps no sparse
// factorisation and assumes nothing of how a value is found: the problem may carry a state
// from one evaluation to the next (a warm start) and is told which evaluation was accepted.

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <cmath>

#include "numerics/problems.hpp"

namespace yarnfit::numerics {

struct FewDofNewtonOptions {
  int max_steps = 40;
  double max_step = 0.05;  // ‖d‖∞ per step
  int halvings = 6;        // a step is tried at d, d/2, …, d/2^halvings
  double armijo = 1e-4;    // c in f(x + t d) ≤ f(x) + c·t·∇fᵀd

  // Every invalid field, under its name; empty when valid.
  [[nodiscard]] Problems problems() const;
};

enum class FewDofNewtonStatus {
  converged,          // residual ≤ 1
  max_steps,          // the step budget spent
  no_descent,         // no trial along the step was accepted
  evaluation_failed,  // the start or a Hessian estimate could not be evaluated
};

[[nodiscard]] const char* to_string(FewDofNewtonStatus status);

// A function value, its gradient and the problem's residual at one point (N: Eigen's size,
// Eigen::Dynamic allowed).
template <int N>
struct FewDofPoint {
  double value = 0.0;
  Eigen::Matrix<double, N, 1> gradient;
  double residual = 0.0;  // the stopping measure: converged at ≤ 1
};

template <int N>
class FewDofProblem {
 public:
  using Vector = Eigen::Matrix<double, N, 1>;
  using Matrix = Eigen::Matrix<double, N, N>;
  virtual ~FewDofProblem() = default;
  // The function at x; false when it cannot be evaluated there. The problem keeps what it
  // needs for accept().
  virtual bool evaluate(const Vector& x, FewDofPoint<N>& at) = 0;
  // The last evaluate() is the new current point.
  virtual void accept() = 0;
  // An estimate of ∇²f at the current point x (its symmetric part is used); false when it
  // cannot be computed. Called right after the current point was accepted.
  virtual bool hessian(const Vector& x, const FewDofPoint<N>& at, Matrix& h) = 0;
};

template <int N>
struct FewDofNewtonResult {
  FewDofNewtonStatus status = FewDofNewtonStatus::evaluation_failed;
  int steps = 0;  // accepted steps
  FewDofPoint<N> at;  // at the returned x (unset when the start could not be evaluated)
};

// Minimises the problem's function from x (updated in place to the last accepted point; the
// start is accepted once evaluated). Throws an input Error for invalid options.
template <int N>
FewDofNewtonResult<N> minimise_few_dofs(FewDofProblem<N>& problem, Eigen::Matrix<double, N, 1>& x,
                                        const FewDofNewtonOptions& options);

// ---------------------------------------------------------------------------------------------

namespace detail {
void throw_if_invalid(const FewDofNewtonOptions& options);
}  // namespace detail

template <int N>
FewDofNewtonResult<N> minimise_few_dofs(FewDofProblem<N>& problem, Eigen::Matrix<double, N, 1>& x,
                                        const FewDofNewtonOptions& options) {
  using Vector = Eigen::Matrix<double, N, 1>;
  using Matrix = Eigen::Matrix<double, N, N>;
  detail::throw_if_invalid(options);
  FewDofNewtonResult<N> out;
  FewDofPoint<N>& at = out.at;
  if (!problem.evaluate(x, at)) return out;
  problem.accept();
  for (; out.steps < options.max_steps; ++out.steps) {
    if (at.residual <= 1.0) {
      out.status = FewDofNewtonStatus::converged;
      return out;
    }
    Matrix estimate;
    if (!problem.hessian(x, at, estimate)) {
      out.status = FewDofNewtonStatus::evaluation_failed;
      return out;
    }
    // Far from the minimum f need not be convex: shift the symmetric part until it is
    // positive definite, so that the step goes downhill.
    Matrix hessian = 0.5 * (estimate + estimate.transpose());
    const Eigen::SelfAdjointEigenSolver<Matrix> eig(hessian);
    const double largest_curvature = eig.eigenvalues().cwiseAbs().maxCoeff();
    const double lowest = eig.eigenvalues().minCoeff();
    if (!(lowest > 1e-6 * largest_curvature)) hessian.diagonal().array() += 1e-3 * largest_curvature - lowest;
    Vector step = -hessian.ldlt().solve(at.gradient);
    if (!step.allFinite() || !(largest_curvature > 0.0)) step = -at.gradient.cwiseSign() * options.max_step;
    const double largest = step.cwiseAbs().maxCoeff();
    if (largest > options.max_step) step *= options.max_step / largest;
    const double slope = at.gradient.dot(step);
    bool accepted = false;
    for (int h = 0; h <= options.halvings && !accepted; ++h, step *= 0.5) {
      FewDofPoint<N> trial;
      if (!problem.evaluate(x + step, trial)) continue;
      // Armijo, or, where f no longer resolves the change, a smaller residual.
      if (trial.value <= at.value + options.armijo * std::ldexp(slope, -h) ||
          (std::abs(trial.value - at.value) <= 1e-12 * std::abs(at.value) && trial.residual < at.residual)) {
        x += step;
        at = trial;
        problem.accept();
        accepted = true;
      }
    }
    if (!accepted) {
      out.status = FewDofNewtonStatus::no_descent;
      return out;
    }
  }
  out.status = at.residual <= 1.0 ? FewDofNewtonStatus::converged : FewDofNewtonStatus::max_steps;
  return out;
}

}  // namespace yarnfit::numerics
