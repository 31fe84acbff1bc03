// Bisection and bracketing on a monotone predicate (numerics/roots/bisection.hpp): the same
// bits as the hand-written loops they replaced, their stopping rules, and their failures.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <stdexcept>
#include <vector>

#include "numerics/roots/bisection.hpp"
#include "tests/expect_error.hpp"

namespace yarnfit::numerics {
namespace {

// √2 as the crossing of x² < 2.
std::optional<bool> below_sqrt2(double x) { return x * x < 2.0; }

TEST(Bisection, ArithmeticToARelativeWidthMatchesTheLoopItReplaced) {
  double lo = 1e-9, hi = 4.0;
  for (int it = 0; it < 200 && hi - lo > 1e-12 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (mid * mid < 2.0 ? lo : hi) = mid;
  }
  BisectionOptions o;
  o.halvings = 200;
  o.relative_width = 1e-12;
  const BisectionResult r = bisect(below_sqrt2, 1e-9, 4.0, o);
  EXPECT_EQ(r.lower, lo);
  EXPECT_EQ(r.upper, hi);
  EXPECT_EQ(r.x, 0.5 * (lo + hi));
  EXPECT_FALSE(r.evaluation_failed);
  EXPECT_LT(r.halvings, 200) << "the width stops it first";
  EXPECT_NEAR(r.x, std::sqrt(2.0), 1e-11);
}

TEST(Bisection, GeometricFixedCountMatchesTheLoopItReplaced) {
  double lo = 1e-4, hi = 1e2;
  for (int it = 0; it < 60; ++it) (std::sqrt(lo * hi) * std::sqrt(lo * hi) < 2.0 ? lo : hi) = std::sqrt(lo * hi);
  BisectionOptions o;
  o.midpoint = Midpoint::geometric;
  o.halvings = 60;
  int evaluations = 0;
  const BisectionResult r = bisect([&](double x) { ++evaluations; return below_sqrt2(x); }, 1e-4, 1e2, o);
  EXPECT_EQ(evaluations, 60) << "relative_width 0: every halving is made";
  EXPECT_EQ(r.lower, lo);
  EXPECT_EQ(r.upper, hi);
  EXPECT_EQ(r.x, std::sqrt(lo * hi));
  EXPECT_NEAR(r.x, std::sqrt(2.0), 1e-14);
}

TEST(Bisection, StopsAtAFailedEvaluationWithTheBracketBeforeIt) {
  BisectionOptions o;
  o.halvings = 10;
  std::vector<double> xs;
  const BisectionResult r = bisect(
      [&](double x) -> std::optional<bool> {
        xs.push_back(x);
        if (xs.size() == 3) return std::nullopt;
        return x < 0.3;
      },
      0.0, 1.0, o);
  ASSERT_EQ(xs.size(), 3u);
  EXPECT_TRUE(r.evaluation_failed);
  EXPECT_EQ(r.halvings, 2);
  EXPECT_EQ(r.lower, 0.25);  // 0.5 above, 0.25 below, 0.375 failed
  EXPECT_EQ(r.upper, 0.5);
  EXPECT_EQ(r.x, 0.375);
}

TEST(Bisection, RejectsInvalidBrackets) {
  BisectionOptions o;
  EXPECT_ERROR(bisect(below_sqrt2, 2.0, 1.0, o), yarnfit::ErrorCategory::input);
  o.midpoint = Midpoint::geometric;
  EXPECT_ERROR(bisect(below_sqrt2, 0.0, 1.0, o), yarnfit::ErrorCategory::input);
  o.halvings = -1;
  EXPECT_ERROR(bisect(below_sqrt2, 1.0, 2.0, o), yarnfit::ErrorCategory::input);
}

TEST(FactorBracket, StepsUpOrDownUntilBothSidesAreSeen) {
  FactorBracketOptions o;
  o.lower = 1e-3;
  o.upper = 100.0;
  std::vector<double> xs;
  const auto below = [&](double x) -> std::optional<bool> {
    xs.push_back(x);
    return x < 5.0;
  };
  const FactorBracket up = bracket_by_factor(below, 0.5, o);
  ASSERT_TRUE(up.bracketed());
  EXPECT_EQ(*up.below, 4.0);
  EXPECT_EQ(*up.above, 8.0);
  EXPECT_EQ(up.evaluations, 5);
  EXPECT_EQ(xs, (std::vector<double>{0.5, 1.0, 2.0, 4.0, 8.0}));
  xs.clear();
  const FactorBracket down = bracket_by_factor(below, 40.0, o);
  ASSERT_TRUE(down.bracketed());
  EXPECT_EQ(*down.above, 5.0);
  EXPECT_EQ(*down.below, 2.5);
  EXPECT_EQ(xs, (std::vector<double>{40.0, 20.0, 10.0, 5.0, 2.5}));
}

TEST(FactorBracket, StopsAtTheBoundsAndAtAFailure) {
  FactorBracketOptions o;
  o.lower = 0.1;
  o.upper = 3.0;
  const FactorBracket never = bracket_by_factor([](double) { return std::optional<bool>(true); }, 1.0, o);
  EXPECT_FALSE(never.bracketed());
  EXPECT_EQ(*never.below, 3.0) << "the last step is clamped to the bound";
  EXPECT_EQ(never.evaluations, 3);  // 1, 2, 3
  const FactorBracket always = bracket_by_factor([](double) { return std::optional<bool>(false); }, 1.0, o);
  EXPECT_EQ(*always.above, 0.1);
  EXPECT_EQ(always.evaluations, 5);  // 1, 0.5, 0.25, 0.125, 0.1
  const FactorBracket failed = bracket_by_factor(
      [](double x) { return x > 1.5 ? std::nullopt : std::optional<bool>(true); }, 1.0, o);
  EXPECT_FALSE(failed.bracketed());
  EXPECT_EQ(*failed.below, 1.0);
  EXPECT_EQ(*failed.failed_at, 2.0);
  o.lower = 0.0;
  EXPECT_ERROR(bracket_by_factor([](double) { return std::optional<bool>(true); }, 1.0, o),
               yarnfit::ErrorCategory::input);
}

}  // namespace
}  // namespace yarnfit::numerics
