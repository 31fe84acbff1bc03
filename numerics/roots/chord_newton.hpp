#pragma once
// A few steps of chord Newton on F(x) = 0 for a few unknowns whose every evaluation is costly:
// the Jacobian is taken once, by forward differences at the start x0,
//   J e_k ≈ (F(x0 + h e_k) − F(x0)) / h,
// and every step is x ← clamp(x − J⁻¹ F(x), −max_abs, max_abs); the point with the smallest
// ‖F‖∞ seen (the start included) is returned. For the rest-shape heuristic's period chord
// steps (yarn_fit/homogenise/rest_shape.hpp), where solving further loosened the tile: a
// fixed, small number of steps, not a tolerance, ends it.
//
// The problem may carry a state from one evaluation to the next (a warm start): every
// evaluation is meant to start from the best point's, and keep() says when the last one
// became the best.

#include <Eigen/Core>

#include "numerics/problems.hpp"

namespace yarnfit::numerics {

struct ChordNewtonOptions {
  int steps = 4;               // chord steps after the Jacobian
  double max_abs = 0.1;        // |x_i| ≤ max_abs
  double jacobian_step = 1e-3; // h of the forward differences

  // Every invalid field, under its name; empty when valid.
  [[nodiscard]] Problems problems() const;
};

class ChordNewtonProblem {
 public:
  virtual ~ChordNewtonProblem() = default;
  // F(x) (resized to #x); false when it cannot be evaluated there.
  virtual bool evaluate(const Eigen::VectorXd& x, Eigen::VectorXd& f) = 0;
  // The last evaluate() is the best point so far (strictly smaller ‖F‖∞).
  virtual void keep() = 0;
};

enum class ChordNewtonStatus {
  done,              // the steps were taken (or ended at a failed evaluation); x is the best
  jacobian_failed,   // a difference could not be evaluated, or J is singular: x is the start
};

struct ChordNewtonResult {
  ChordNewtonStatus status = ChordNewtonStatus::done;
  Eigen::VectorXd x;  // the best point
  Eigen::VectorXd f;  // F there
  int evaluations = 0;
};

// From x0 with F(x0) = f0 known. Throws an input Error for invalid options or sizes.
ChordNewtonResult chord_newton(ChordNewtonProblem& problem, const Eigen::VectorXd& x0, const Eigen::VectorXd& f0,
                               const ChordNewtonOptions& options);

}  // namespace yarnfit::numerics
