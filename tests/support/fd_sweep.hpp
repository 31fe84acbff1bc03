#pragma once
// Central-difference step sweeps shared by the derivative checks of every module
// (tests/support/derivative_check.hpp): for each step
// h = rel · length, the worst entry's error relative to the analytic derivative's ∞-norm,
// keeping the best step (round-off and truncation errors trade off across the sweep).
#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <vector>

namespace yarnfit::testing {

struct GradientSweep {
  double error = std::numeric_limits<double>::infinity();
  double step = 0.0;
  Eigen::Index worst = 0;
  double worst_fd = 0.0;
};

// FD of value(x) against the gradient g (norm: the error scale).
template <class X, class G, class Value>
GradientSweep sweep_gradient(const X& x, const G& g, double norm, const std::vector<double>& relative_steps,
                             double length, Value&& value) {
  GradientSweep best;
  for (const double rel : relative_steps) {
    const double h = rel * length;
    GradientSweep at{0.0, h, 0, 0.0};
    for (Eigen::Index i = 0; i < x.size(); ++i) {
      X xp = x, xm = x;
      xp(i) += h;
      xm(i) -= h;
      const double fd = (value(xp) - value(xm)) / (2.0 * h);
      const double e = std::abs(fd - g(i)) / norm;
      if (!(e <= at.error)) {  // also catches NaN
        at.error = e;
        at.worst = i;
        at.worst_fd = fd;
      }
    }
    if (at.error < best.error) best = at;
  }
  return best;
}

struct HessianSweep {
  double error = std::numeric_limits<double>::infinity();
  double step = 0.0;
  Eigen::Index row = 0, col = 0;
  double worst_fd = 0.0;
};

// FD of gradient(x) against the Hessian h (norm: the error scale).
template <class X, class H, class Gradient>
HessianSweep sweep_hessian(const X& x, const H& hess, double norm, const std::vector<double>& relative_steps,
                           double length, Gradient&& gradient) {
  HessianSweep best;
  for (const double rel : relative_steps) {
    const double h = rel * length;
    HessianSweep at{0.0, h, 0, 0, 0.0};
    for (Eigen::Index j = 0; j < x.size(); ++j) {
      X xp = x, xm = x;
      xp(j) += h;
      xm(j) -= h;
      const X column = (gradient(xp) - gradient(xm)) / (2.0 * h);
      for (Eigen::Index i = 0; i < x.size(); ++i) {
        const double e = std::abs(column(i) - hess(i, j)) / norm;
        if (!(e <= at.error)) {
          at.error = e;
          at.row = i;
          at.col = j;
          at.worst_fd = column(i);
        }
      }
    }
    if (at.error < best.error) best = at;
  }
  return best;
}

}  // namespace yarnfit::testing
