// Brent's minimisation (numerics/optim/brent_minimize.hpp) against known minima, beside the
// golden section it replaces.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "numerics/optim/brent_minimize.hpp"

namespace yarnfit::numerics {
namespace {

// Golden-section search to the same tolerance: its evaluations, for the comparison.
int golden_evaluations(const std::function<double(double)>& f, double a, double b, double tolerance) {
  const double phi = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = b - phi * (b - a), x2 = a + phi * (b - a);
  double f1 = f(x1), f2 = f(x2);
  int n = 2;
  while (b - a > tolerance) {
    if (f1 <= f2) b = x2, x2 = x1, f2 = f1, x1 = b - phi * (b - a), f1 = f(x1);
    else a = x1, x1 = x2, f1 = f2, x2 = a + phi * (b - a), f2 = f(x2);
    ++n;
  }
  return n;
}

TEST(BrentMinimize, FindsASmoothMinimumInFewerEvaluationsThanGoldenSection) {
  // A least-squares misfit in log k: smooth, asymmetric, minimum at log 3e-6.
  const double truth = std::log(3e-6);
  const auto f = [truth](double x) { return std::pow(std::exp(x - truth) - 1.0, 2) + 0.1 * std::pow(x - truth, 2); };
  const double lo = std::log(1e-9), hi = std::log(1e-3), tol = 2e-3;
  const auto m = brent_minimize(f, lo, hi, tol);
  EXPECT_TRUE(m.converged);
  EXPECT_NEAR(m.x, truth, tol);
  const int golden = golden_evaluations(f, lo, hi, tol);
  EXPECT_LT(m.evaluations, golden * 3 / 4) << "Brent " << m.evaluations << ", golden " << golden;
}

TEST(BrentMinimize, KeepsTheBracketWhereEvaluationsFail) {
  // No value below 1 (a loop with no equilibrium); the minimum of (x − 2)² above.
  const auto f = [](double x) { return x < 1.0 ? std::numeric_limits<double>::quiet_NaN() : (x - 2.0) * (x - 2.0); };
  const auto m = brent_minimize(f, -10.0, 10.0, 1e-6);
  EXPECT_TRUE(m.converged);
  EXPECT_NEAR(m.x, 2.0, 1e-6);
  EXPECT_NEAR(m.value, 0.0, 1e-11);
}

TEST(BrentMinimize, AMinimumAtTheEndOfTheIntervalIsApproached) {
  const auto m = brent_minimize([](double x) { return x; }, 0.0, 1.0, 1e-5);
  EXPECT_TRUE(m.converged);
  EXPECT_LT(m.x, 2e-5);
}

TEST(BrentMinimize, StopsAtTheEvaluationCapAndSaysSo) {
  const auto m = brent_minimize([](double x) { return std::cos(x); }, 0.0, 6.0, 1e-12, 5);
  EXPECT_FALSE(m.converged);
  EXPECT_EQ(m.evaluations, 5);
  EXPECT_TRUE(std::isfinite(m.value));
}

}  // namespace
}  // namespace yarnfit::numerics
