#pragma once
// The one finite-difference check of the project (STYLE "Derivatives are always checked"),
// used by every energy term's test and every element's test: central differences of the
// value against the gradient and of the gradient against the Hessian, over a sweep of steps,
// keeping each check's best step.
//
//   err(h) = max_i |FD_h(i) − analytic(i)| / max(‖analytic‖∞, floor)
//
// The check passes when min_h err(h) < tolerance. The sweep makes it independent of the
// problem's scale: truncation error falls as h², round-off grows as 1/h, and the best step
// lies in between. On failure the message names the worst entry at the best step.
//
//  * expect_derivatives_match(term, x): a numerics::EnergyTerm (shell membrane, bending,
//    gravity; yarn stretch, bending, contact; test terms), its assembled gradient and sparse
//    Hessian, and its PSD projection;
//  * expect_element_derivatives<N>(f, x, what): one fixed-size element
//    double f(const Vec<N>& x, Vec<N>* g, Mat<N>* H) with the element convention (outputs
//    overwritten, nullptr = not wanted).

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "numerics/terms/energy_term.hpp"
#include "tests/support/fd_sweep.hpp"

namespace yarnfit::testing {

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

inline Eigen::MatrixXd dense_hessian(const numerics::EnergyTerm& term, const Eigen::VectorXd& x, bool project_psd) {
  numerics::Triplets triplets;
  term.add_hessian(x, triplets, {project_psd, false});
  Eigen::SparseMatrix<double> h(x.size(), x.size());
  h.setFromTriplets(triplets.begin(), triplets.end());
  return Eigen::MatrixXd(h);
}

inline Eigen::VectorXd gradient_of(const numerics::EnergyTerm& term, const Eigen::VectorXd& x) {
  Eigen::VectorXd g = Eigen::VectorXd::Zero(x.size());
  term.add_gradient(x, g);
  return g;
}

namespace detail {

// The sweeps shared by both checks, with gtest failures tagged `what`.
template <class X, class G, class H, class Value, class Gradient>
DerivativeCheckResult check_sweeps(const std::string& what, const X& x, const G& g, const H& hess, Value&& value_at,
                                   Gradient&& gradient_at, const DerivativeCheckOptions& options) {
  DerivativeCheckResult result;
  const double g_norm = std::max(g.template lpNorm<Eigen::Infinity>(), options.floor);
  const GradientSweep gs = sweep_gradient(x, g, g_norm, options.relative_steps, options.length_scale, value_at);
  result.gradient_error = gs.error;
  result.gradient_step = gs.step;
  EXPECT_LT(result.gradient_error, options.tolerance)
      << what << ": gradient vs FD of value, best step " << gs.step << ", worst entry " << gs.worst << ": analytic "
      << g(gs.worst) << ", FD " << gs.worst_fd << ", |g|∞ " << g_norm;
  if (!options.check_hessian) return result;
  const double h_norm = std::max(hess.template lpNorm<Eigen::Infinity>(), options.floor);
  const HessianSweep hs = sweep_hessian(x, hess, h_norm, options.relative_steps, options.length_scale, gradient_at);
  result.hessian_error = hs.error;
  result.hessian_step = hs.step;
  EXPECT_LT(result.hessian_error, options.tolerance)
      << what << ": Hessian vs FD of gradient, best step " << hs.step << ", worst entry (" << hs.row << ", " << hs.col
      << "): analytic " << hess(hs.row, hs.col) << ", FD " << hs.worst_fd << ", |H|∞ " << h_norm;
  EXPECT_LE((hess - hess.transpose()).template lpNorm<Eigen::Infinity>(), 1e-10 * h_norm)
      << what << ": Hessian not symmetric";
  return result;
}

}  // namespace detail

// Checks `term` at `x`; returns the errors for printing. Adds gtest failures on mismatch.
inline DerivativeCheckResult expect_derivatives_match(const numerics::EnergyTerm& term, const Eigen::VectorXd& x,
                                                      const DerivativeCheckOptions& options = {}) {
  const double value = term.value(x);
  EXPECT_TRUE(std::isfinite(value)) << term.name() << ": value " << value << " at the check point";
  if (!std::isfinite(value)) return {};
  const Eigen::VectorXd g = gradient_of(term, x);
  EXPECT_TRUE(g.allFinite()) << term.name() << ": non-finite gradient";
  const Eigen::MatrixXd H = options.check_hessian ? dense_hessian(term, x, false) : Eigen::MatrixXd();
  if (options.check_hessian) {
    EXPECT_TRUE(H.allFinite()) << term.name() << ": non-finite Hessian";
  }
  const DerivativeCheckResult result = detail::check_sweeps(
      term.name(), x, g, H, [&](const Eigen::VectorXd& y) { return term.value(y); },
      [&](const Eigen::VectorXd& y) { return gradient_of(term, y); }, options);
  if (options.check_hessian && options.check_psd_projection && x.size() > 0) {
    const double h_norm = std::max(H.lpNorm<Eigen::Infinity>(), options.floor);
    const Eigen::MatrixXd P = dense_hessian(term, x, true);
    EXPECT_TRUE(P.allFinite()) << term.name() << ": non-finite projected Hessian";
    EXPECT_LE((P - P.transpose()).lpNorm<Eigen::Infinity>(), 1e-10 * h_norm)
        << term.name() << ": projected Hessian not symmetric";
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (P + P.transpose()));
    EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-10 * h_norm) << term.name() << ": projected Hessian has a negative eigenvalue";
  }
  return result;
}

// Checks the derivatives of the element `f` at `x` and adds gtest failures (tagged `what`).
template <int N, class F>
DerivativeCheckResult expect_element_derivatives(F&& f, const Eigen::Matrix<double, N, 1>& x, const std::string& what,
                                                 const DerivativeCheckOptions& options) {
  using V = Eigen::Matrix<double, N, 1>;
  using M = Eigen::Matrix<double, N, N>;
  V g;
  M hess;
  const double value = f(x, &g, &hess);
  EXPECT_TRUE(std::isfinite(value)) << what << ": value " << value;
  if (!std::isfinite(value)) return {};
  EXPECT_TRUE(g.allFinite()) << what << ": non-finite gradient";
  EXPECT_TRUE(hess.allFinite()) << what << ": non-finite Hessian";
  return detail::check_sweeps(
      what, x, g, hess, [&f](const V& y) { return f(y, nullptr, nullptr); },
      [&f](const V& y) {
        V gy;
        f(y, &gy, nullptr);
        return gy;
      },
      options);
}

// Smallest eigenvalue of the symmetric part of a fixed-size block.
template <int N>
double min_eigenvalue(const Eigen::Matrix<double, N, N>& m) {
  const Eigen::Matrix<double, N, N> sym = 0.5 * (m + m.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> eig(sym, Eigen::EigenvaluesOnly);
  return eig.eigenvalues().minCoeff();
}

// Worst errors over a group of checks, for the test log.
struct ErrorTally {
  double gradient = 0.0;
  double hessian = 0.0;
  int count = 0;
  void add(const DerivativeCheckResult& r) {
    gradient = std::max(gradient, r.gradient_error);
    hessian = std::max(hessian, r.hessian_error);
    ++count;
  }
};

}  // namespace yarnfit::testing
