#pragma once
// One reusable finite-difference check for every energy term (STYLE "Derivatives are always
// checked"): central differences of the value against the gradient and of the gradient
// against the Hessian, over a sweep of steps, keeping each check's best step.
//
//   err(h) = max_i |FD_h(i) − analytic(i)| / max(‖analytic‖∞, floor)
//
// The check passes when min_h err(h) < tolerance. The sweep makes the check independent of
// the problem's scale: truncation error falls as h², round-off grows as 1/h, and the best
// step lies in between. On failure the message names the worst entry at the best step.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "shell_fit/core/energy_term.hpp"
#include "tests/fd_sweep.hpp"

namespace yarnfit::shell::testing {

struct DerivativeCheckOptions {
  double length_scale = 1.0;  // typical coordinate magnitude [m]; steps are fractions of it
  std::vector<double> relative_steps{1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8};
  double tolerance = 1e-6;  // best-step relative error
  double floor = 1e-300;    // smallest norm used to relativise (a zero derivative at rest)
  bool check_hessian = true;
  bool check_psd_projection = true;  // the projected Hessian must be PSD and symmetric
};

struct DerivativeCheckResult {
  double gradient_error = std::numeric_limits<double>::infinity();  // best-step relative error
  double gradient_step = 0.0;
  double hessian_error = std::numeric_limits<double>::infinity();
  double hessian_step = 0.0;
};

inline Eigen::MatrixXd dense_hessian(const EnergyTerm& term, const Eigen::VectorXd& x,
                                     bool project_psd) {
  Triplets triplets;
  term.add_hessian(x, triplets, project_psd);
  Eigen::SparseMatrix<double> h(x.size(), x.size());
  h.setFromTriplets(triplets.begin(), triplets.end());
  return Eigen::MatrixXd(h);
}

inline Eigen::VectorXd gradient_of(const EnergyTerm& term, const Eigen::VectorXd& x) {
  Eigen::VectorXd g = Eigen::VectorXd::Zero(x.size());
  term.add_gradient(x, g);
  return g;
}

// Checks `term` at `x`; returns the errors for printing. Adds gtest failures on mismatch.
inline DerivativeCheckResult expect_derivatives_match(const EnergyTerm& term,
                                                      const Eigen::VectorXd& x,
                                                      const DerivativeCheckOptions& options = {}) {
  DerivativeCheckResult result;
  const Eigen::Index n = x.size();
  const double value = term.value(x);
  EXPECT_TRUE(std::isfinite(value)) << term.name() << ": value " << value << " at the check point";
  if (!std::isfinite(value)) return result;
  const Eigen::VectorXd g = gradient_of(term, x);
  EXPECT_TRUE(g.allFinite()) << term.name() << ": non-finite gradient";

  // --- value vs gradient
  const double g_norm = std::max(g.lpNorm<Eigen::Infinity>(), options.floor);
  const yarnfit::testing::GradientSweep gs = yarnfit::testing::sweep_gradient(
      x, g, g_norm, options.relative_steps, options.length_scale,
      [&](const Eigen::VectorXd& y) { return term.value(y); });
  result.gradient_error = gs.error;
  result.gradient_step = gs.step;
  const auto worst_g = gs.worst;
  const double worst_g_fd = gs.worst_fd;
  EXPECT_LT(result.gradient_error, options.tolerance)
      << term.name() << ": gradient vs FD of value, best step " << result.gradient_step
      << ", worst entry " << worst_g << ": analytic " << g(worst_g) << ", FD " << worst_g_fd
      << ", |g|∞ " << g_norm;

  if (!options.check_hessian) return result;

  // --- gradient vs Hessian
  const Eigen::MatrixXd H = dense_hessian(term, x, false);
  EXPECT_TRUE(H.allFinite()) << term.name() << ": non-finite Hessian";
  const double h_norm = std::max(H.lpNorm<Eigen::Infinity>(), options.floor);
  const yarnfit::testing::HessianSweep hs = yarnfit::testing::sweep_hessian(
      x, H, h_norm, options.relative_steps, options.length_scale,
      [&](const Eigen::VectorXd& y) { return gradient_of(term, y); });
  result.hessian_error = hs.error;
  result.hessian_step = hs.step;
  const auto worst_r = hs.row, worst_c = hs.col;
  const double worst_h_fd = hs.worst_fd;
  EXPECT_LT(result.hessian_error, options.tolerance)
      << term.name() << ": Hessian vs FD of gradient, best step " << result.hessian_step
      << ", worst entry (" << worst_r << ", " << worst_c << "): analytic " << H(worst_r, worst_c)
      << ", FD " << worst_h_fd << ", |H|∞ " << h_norm;
  EXPECT_LE((H - H.transpose()).lpNorm<Eigen::Infinity>(), 1e-10 * h_norm)
      << term.name() << ": Hessian not symmetric";

  if (options.check_psd_projection && n > 0) {
    const Eigen::MatrixXd P = dense_hessian(term, x, true);
    EXPECT_TRUE(P.allFinite()) << term.name() << ": non-finite projected Hessian";
    EXPECT_LE((P - P.transpose()).lpNorm<Eigen::Infinity>(), 1e-10 * h_norm)
        << term.name() << ": projected Hessian not symmetric";
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (P + P.transpose()));
    EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-10 * h_norm)
        << term.name() << ": projected Hessian has a negative eigenvalue";
  }
  return result;
}

}  // namespace yarnfit::shell::testing
