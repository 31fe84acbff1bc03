// The one root finder (numerics/roots): roots of known functions, its mirror symmetry, its
// bounds and its failure statuses.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "numerics/roots/bracketed_root.hpp"
#include "tests/expect_error.hpp"

namespace yarnfit::numerics {
namespace {

// A smooth increasing function with a known root r, curved like a stress-strain response.
double cubic(double x, double r) { return (x - r) + 4.0 * std::pow(x - r, 3); }

TEST(BracketedRoot, FindsTheRootFromEitherSide) {
  RootFindOptions o;
  o.x_tolerance = 1e-10;
  for (const double guess : {-0.4, 0.0, 0.29, 0.31, 0.9}) {
    const RootResult r = find_root([](double x) { return cubic(x, 0.3); }, guess, o);
    ASSERT_TRUE(r.converged()) << guess;
    EXPECT_NEAR(r.x, 0.3, 1e-9) << guess;
    EXPECT_LE(r.evaluations, 25) << guess;
  }
}

// f and its mirror m(x) = −f(−x) (increasing too, root −r) must be searched identically when
// started from mirrored guesses: a search downwards is an upward one seen in a mirror. The
// downward bracketing step once ignored the secant (it always quadrupled), which this catches.
TEST(BracketedRoot, SearchesDownwardsAsItSearchesUpwards) {
  RootFindOptions o;
  o.initial_step = 0.01;
  o.x_tolerance = 1e-9;
  for (const double root : {0.05, 0.13, 0.4, 1.7}) {
    std::vector<double> up, down;
    const RootResult ru = find_root([&](double x) { up.push_back(x); return cubic(x, root); }, 0.0, o);
    const RootResult rd = find_root([&](double x) { down.push_back(x); return -cubic(-x, root); }, 0.0, o);
    ASSERT_TRUE(ru.converged() && rd.converged()) << root;
    ASSERT_EQ(up.size(), down.size()) << "root " << root;
    for (std::size_t k = 0; k < up.size(); ++k) EXPECT_DOUBLE_EQ(up[k], -down[k]) << "root " << root << ", evaluation " << k;
  }
}

TEST(BracketedRoot, StopsWithinTheValueTolerance) {
  RootFindOptions o;
  o.f_tolerance = 1e-3;
  const RootResult r = find_root([](double x) { return cubic(x, 0.2); }, 0.0, o);
  ASSERT_TRUE(r.converged());
  EXPECT_LE(std::abs(r.f), 1e-3);
  EXPECT_LE(std::abs(r.x - 0.2), 2e-3);
}

TEST(BracketedRoot, NeverEvaluatesOutsideItsBounds) {
  RootFindOptions o;
  o.lower = -0.1;
  o.upper = 0.25;
  o.initial_step = 0.2;
  std::vector<double> xs;
  const RootResult r = find_root([&](double x) { xs.push_back(x); return cubic(x, 0.24); }, 0.0, o);
  ASSERT_TRUE(r.converged());
  for (const double x : xs) {
    EXPECT_GE(x, o.lower);
    EXPECT_LE(x, o.upper);
  }
}

TEST(BracketedRoot, ReportsARootOutsideTheBoundsAsNotBracketed) {
  RootFindOptions o;
  o.lower = 0.0;
  o.upper = 0.5;
  const RootResult r = find_root([](double x) { return cubic(x, 0.8); }, 0.1, o);
  EXPECT_EQ(r.status, RootStatus::not_bracketed);
  EXPECT_DOUBLE_EQ(r.x, 0.5);
}

TEST(BracketedRoot, StopsWhereTheFunctionCannotBeEvaluated) {
  const RootResult r = find_root([](double x) -> std::optional<double> {
    if (x > 0.12) return std::nullopt;
    return cubic(x, 0.3);
  }, 0.0, {});
  EXPECT_EQ(r.status, RootStatus::evaluation_failed);
}

// Past a barrier the function is +inf: its sign still brackets the root, and the search
// halves that end instead of using regula falsi with an infinite value.
TEST(BracketedRoot, BisectsTowardsABarrier) {
  RootFindOptions o;
  o.x_tolerance = 1e-10;
  const RootResult r = find_root([](double x) {
    return x >= 0.35 ? std::numeric_limits<double>::infinity() : cubic(x, 0.3);
  }, 0.0, o);
  ASSERT_TRUE(r.converged());
  EXPECT_NEAR(r.x, 0.3, 1e-9);
}

TEST(BracketedRoot, RefusesInvalidOptions) {
  RootFindOptions o;
  o.initial_step = 0.0;
  EXPECT_ERROR(find_root([](double x) { return x; }, 0.0, o), yarnfit::ErrorCategory::input);
  o = {};
  o.lower = 1.0;
  o.upper = 0.0;
  EXPECT_ERROR(find_root([](double x) { return x; }, 0.0, o), yarnfit::ErrorCategory::input);
}

}  // namespace
}  // namespace yarnfit::numerics
