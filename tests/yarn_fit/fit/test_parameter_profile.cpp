// The identifiability profile of a fit: the Gauss–Newton ranges against the Schur-complement
// formula worked by hand, singular directions reported as free, and on the stockinette tile
// R1 (which sets the loops' jamming) pinned far tighter than ks1 (in series with the softer
// bending and contact of the loops).
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "yarn_fit/fit/parameter_profile.hpp"
#include "yarn_fit/fit/yarn_fit.hpp"
#include "tests/yarn_fit/fit/stockinette_case.hpp"
#include "tests/test_support.hpp"
#include "tests/expect_error.hpp"

namespace yarnfit::yarn {
namespace {

TEST(GaussNewtonRanges, MatchTheSchurComplementOfTwoCorrelatedParameters) {
  // Columns a and b: holding p1, moving p0 by δ raises g by δ²|a|²; letting p1 follow
  // (Δ1 = −(a·b)/|b|² δ) the rise is δ²(|a|² − (a·b)²/|b|²).
  Eigen::MatrixXd jac(3, 2);
  jac << 1.0, 0.8, 0.5, 0.6, -0.2, 0.1;
  const double g = 0.03;
  const Eigen::Vector3d a = jac.col(0), b = jac.col(1);
  const auto ranges = gauss_newton_ranges(jac.transpose() * jac, g);
  ASSERT_EQ(ranges.size(), 2u);
  EXPECT_NEAR(std::log(ranges[0].alone), std::sqrt(g / a.squaredNorm()), 1e-12);
  EXPECT_NEAR(std::log(ranges[1].alone), std::sqrt(g / b.squaredNorm()), 1e-12);
  const double schur0 = a.squaredNorm() - std::pow(a.dot(b), 2) / b.squaredNorm();
  const double schur1 = b.squaredNorm() - std::pow(a.dot(b), 2) / a.squaredNorm();
  EXPECT_NEAR(std::log(ranges[0].refitted), std::sqrt(g / schur0), 1e-10);
  EXPECT_NEAR(std::log(ranges[1].refitted), std::sqrt(g / schur1), 1e-10);
  // Correlated columns: each can go further when the other follows.
  EXPECT_GT(std::log(ranges[0].refitted), 1.5 * std::log(ranges[0].alone));
}

TEST(GaussNewtonRanges, ParametersThatOnlyActTogetherAreFree) {
  // p0 and p1 enter only as p0 + 2 p1 (collinear columns); p2 acts on its own.
  Eigen::MatrixXd jac(3, 3);
  jac << 1.0, 2.0, 0.0, 0.5, 1.0, 0.0, 0.0, 0.0, 3.0;
  const auto ranges = gauss_newton_ranges(jac.transpose() * jac, 0.01);
  EXPECT_TRUE(std::isinf(ranges[0].refitted));
  EXPECT_TRUE(std::isinf(ranges[1].refitted));
  EXPECT_TRUE(std::isfinite(ranges[0].alone));
  EXPECT_NEAR(std::log(ranges[2].refitted), std::sqrt(0.01) / 3.0, 1e-10);
  // A column of zeros: no evidence at all, held or not.
  jac.col(2).setZero();
  EXPECT_TRUE(std::isinf(gauss_newton_ranges(jac.transpose() * jac, 0.01)[2].alone));
}

TEST(ParameterProfile, PinsR1FarTighterThanKs1OnStockinette) {
  YARNFIT_REQUIRE_SHARED(testcase::stockinette_pattern());
  const testcase::Stockinette st = testcase::load_stockinette();
  const yarn::YarnParams truth = st.soft_toe_params();
  const SyntheticYarnResult synth = st.synthesise(truth, {db::Direction::weft}, 0.2, 4);
  ObjectiveOptions oo;
  oo.samples = 4;
  const YarnObjective objective(st.yarn_tile(), synth.targets, oo);
  const swarm::ParameterSpace space = yarn_parameter_space(st.scales, false);
  const auto to_params = [&](const Eigen::VectorXd& x) { return params_from_point(x, st.scales, false); };

  // A "fit" just off the truth, so that g there is not zero.
  yarn::YarnParams fit = truth;
  fit.r1 *= 1.005;
  const Eigen::VectorXd x = point_from_params(fit, false);
  const ObjectiveResult at_fit = objective.evaluate(fit);
  ASSERT_TRUE(at_fit.ok) << at_fit.message;
  const ParameterProfile p = profile_parameters(objective, space, x, at_fit, to_params, 0.1, 2);
  ASSERT_TRUE(p.computed) << p.message;
  EXPECT_TRUE(p.message.empty()) << p.message;
  EXPECT_EQ(p.evaluations, 10);
  ASSERT_EQ(p.entries.size(), 5u);
  for (const auto& e : p.entries)
    std::cout << "[ profile  ] " << e.name << ": g " << e.g_lower << " / " << e.g_upper << " (fit " << p.g_fit
              << "), range x/÷ " << e.range_factor << " re-fitted, " << e.range_alone_factor << " held\n";
  const ParameterProfileEntry& ks1 = p.entries[0];
  const ParameterProfileEntry& r1 = p.entries[3];
  ASSERT_EQ(ks1.name, "ks1");
  ASSERT_EQ(r1.name, "R1");
  EXPECT_EQ(r1.value, fit.r1);
  // R1 10 % off raises g by orders of magnitude; the held range is a fraction of a percent.
  EXPECT_GT(std::min(r1.g_lower, r1.g_upper), 100.0 * p.g_fit);
  EXPECT_LT(r1.range_alone_factor, 1.01);
  EXPECT_LT(r1.range_factor, 1.1);
  EXPECT_GT(ks1.range_factor, 5.0 * (r1.range_factor - 1.0) + 1.0);
  // Up to 20 % weft stretch the yarns strain by less than 0.3 %, below the truth's onset
  // ε̄s = 0.5 %: the targets carry no trace of ε̄s.
  const ParameterProfileEntry& eps_s = p.entries[1];
  ASSERT_EQ(eps_s.name, "eps_s");
  EXPECT_GT(eps_s.range_factor, 10.0);
  // The parameters are the ones the fit would report, not moved by the profile.
  EXPECT_EQ(p.g_fit, at_fit.value);
  const results::Identifiability record = to_record(p);
  EXPECT_TRUE(record.computed);
  EXPECT_EQ(record.parameters.at("R1").value, fit.r1);
}

TEST(ParameterProfile, ReportsAnIncompleteFitInsteadOfProfilingIt) {
  YARNFIT_REQUIRE_SHARED(testcase::stockinette_pattern());
  const testcase::Stockinette st = testcase::load_stockinette();
  const SyntheticYarnResult synth = st.synthesise(st.soft_toe_params(), {db::Direction::weft}, 0.1, 2);
  ObjectiveOptions oo;
  oo.samples = 2;
  const YarnObjective objective(st.yarn_tile(), synth.targets, oo);
  yarn::YarnParams bad = st.soft_toe_params();
  bad.ks1 = -1.0;
  const ObjectiveResult failed = objective.evaluate(bad);
  ASSERT_FALSE(failed.ok);
  const ParameterProfile p = profile_parameters(
      objective, yarn_parameter_space(st.scales, false), point_from_params(bad, false), failed,
      [&](const Eigen::VectorXd& x) { return params_from_point(x, st.scales, false); }, 0.1, 1);
  EXPECT_FALSE(p.computed);
  EXPECT_EQ(p.evaluations, 0);
  EXPECT_FALSE(p.message.empty());
  EXPECT_ERROR((void)profile_parameters(objective, yarn_parameter_space(st.scales, false),
                                        point_from_params(bad, false), failed,
                                        [&](const Eigen::VectorXd& x) { return params_from_point(x, st.scales, false); },
                                        0.0, 1), yarnfit::ErrorCategory::input);
}

}  // namespace
}  // namespace yarnfit::yarn
