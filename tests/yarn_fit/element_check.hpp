#pragma once
// Finite-difference check for one fixed-size yarn element (STYLE "Derivatives are always
// checked"): central differences of the value against the gradient and of the gradient
// against the Hessian, over a sweep of steps, keeping each check's best step.
//
//   err(h) = max_i |FD_h(i) − analytic(i)| / max(‖analytic‖∞, floor)
//
// The element is any callable  double f(const Vec<N>& x, Vec<N>* g, Mat<N>* H)  with the
// element convention (outputs overwritten, nullptr = not wanted). Steps are fractions of a
// length scale, so the check is independent of the problem's units: truncation error falls as
// h², round-off grows as 1/h, and the best step lies in between.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "tests/fd_sweep.hpp"
#include "yarn_fit/energies/yarn_elements.hpp"

namespace yarnfit::yarn::testing {

struct ElementCheckOptions {
  double length_scale = 1e-3;  // typical coordinate magnitude [m]; steps are fractions of it
  std::vector<double> relative_steps{1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8};
  double tolerance = 1e-6;  // best-step relative error
  double floor = 1e-300;    // smallest norm used to relativise (a zero derivative at rest)
};

struct ElementCheckResult {
  double gradient_error = std::numeric_limits<double>::infinity();  // best-step relative error
  double gradient_step = 0.0;
  double hessian_error = std::numeric_limits<double>::infinity();
  double hessian_step = 0.0;
};

// Checks the derivatives of `f` at `x` and adds gtest failures (tagged `what`) on mismatch.
template <int N, class F>
ElementCheckResult expect_element_derivatives(F&& f, const Vec<N>& x, const std::string& what,
                                              const ElementCheckOptions& options = {}) {
  ElementCheckResult result;
  Vec<N> g;
  Mat<N> hess;
  const double value = f(x, &g, &hess);
  EXPECT_TRUE(std::isfinite(value)) << what << ": value " << value;
  if (!std::isfinite(value)) return result;
  EXPECT_TRUE(g.allFinite()) << what << ": non-finite gradient";
  EXPECT_TRUE(hess.allFinite()) << what << ": non-finite Hessian";

  const auto value_at = [&f](const Vec<N>& y) { return f(y, nullptr, nullptr); };
  const auto gradient_at = [&f](const Vec<N>& y) {
    Vec<N> gy;
    f(y, &gy, nullptr);
    return gy;
  };

  // --- value vs gradient
  const double g_norm = std::max(g.template lpNorm<Eigen::Infinity>(), options.floor);
  const yarnfit::testing::GradientSweep gs =
      yarnfit::testing::sweep_gradient(x, g, g_norm, options.relative_steps, options.length_scale, value_at);
  result.gradient_error = gs.error;
  result.gradient_step = gs.step;
  const auto worst_g = gs.worst;
  const double worst_g_fd = gs.worst_fd;
  EXPECT_LT(result.gradient_error, options.tolerance)
      << what << ": gradient vs FD of value, best step " << result.gradient_step
      << ", worst entry " << worst_g << ": analytic " << g(worst_g) << ", FD " << worst_g_fd
      << ", |g|∞ " << g_norm;

  // --- gradient vs Hessian
  const double h_norm = std::max(hess.template lpNorm<Eigen::Infinity>(), options.floor);
  const yarnfit::testing::HessianSweep hs =
      yarnfit::testing::sweep_hessian(x, hess, h_norm, options.relative_steps, options.length_scale, gradient_at);
  result.hessian_error = hs.error;
  result.hessian_step = hs.step;
  const auto worst_r = hs.row, worst_c = hs.col;
  const double worst_h_fd = hs.worst_fd;
  EXPECT_LT(result.hessian_error, options.tolerance)
      << what << ": Hessian vs FD of gradient, best step " << result.hessian_step
      << ", worst entry (" << worst_r << ", " << worst_c << "): analytic " << hess(worst_r, worst_c)
      << ", FD " << worst_h_fd << ", |H|∞ " << h_norm;
  EXPECT_LE((hess - hess.transpose()).template lpNorm<Eigen::Infinity>(), 1e-12 * h_norm)
      << what << ": Hessian not symmetric";
  return result;
}

// Smallest eigenvalue of the symmetric part of a fixed-size block.
template <int N>
double min_eigenvalue(const Mat<N>& m) {
  const Mat<N> sym = 0.5 * (m + m.transpose());
  const Eigen::SelfAdjointEigenSolver<Mat<N>> eig(sym, Eigen::EigenvaluesOnly);
  return eig.eigenvalues().minCoeff();
}

// Worst errors over a group of checks, for the test log.
struct ErrorTally {
  double gradient = 0.0;
  double hessian = 0.0;
  int count = 0;
  void add(const ElementCheckResult& r) {
    gradient = std::max(gradient, r.gradient_error);
    hessian = std::max(hessian, r.hessian_error);
    ++count;
  }
};

}  // namespace yarnfit::yarn::testing
