// The exact residual Jacobian of the yarn objective (issue 33; jacobian_check.hpp) against
// central differences of the residuals on the stockinette tile, in a smooth case: every yarn
// in the soft phase (ε̄s beyond the yarns' strains), weft and bias (the warp is slack across at
// rest), tight solves and a narrow band; and the residual vector and Jacobian line up with
// the objective's value.

#include <gtest/gtest.h>

#include <iostream>

#include "yarn_fit/fit/objective/jacobian_check.hpp"
#include "tests/yarn_fit/fit/stockinette_case.hpp"
#include "tests/test_support.hpp"

namespace yarnfit::yarn {
namespace {

// Tight solves and a narrow band, so that central differences of the residuals are exact enough.
ObjectiveOptions tight_options(const testcase::Stockinette& st) {
  ObjectiveOptions o;
  o.samples = 3;
  o.compression_stress_fraction = 1e-8;
  o.compression.tolerance = 1e-10;
  o.solve.force_tolerance = 1e-12 * st.scales.ks2;
  o.solve.stress_tolerance = 0.0;
  o.solve.loose_tolerance = 1e-300;
  o.solve.max_iterations = 1000;
  return o;
}

TEST(ResidualJacobian, MatchesCentralDifferencesInASmoothCase) {
  YARNFIT_REQUIRE_SHARED(testcase::stockinette_pattern());
  const testcase::Stockinette st = testcase::load_stockinette();
  yarn::YarnParams truth = st.soft_toe_params();
  truth.eps_s = 0.05;  // beyond every yarn strain up to 20 % stretch: no kink of the biphasic law
  auto targets = st.synthesise(truth, {db::Direction::weft, db::Direction::bias}, 0.2, 5).targets;
  // The targets' c moved off the simulated roots: at s = 0 the rest state makes c* = 0 at any
  // parameters it was relaxed for, so the read-out would sit inside its (narrow) band there, a
  // plateau whose edge is a kink a difference step can cross.
  for (auto& t : targets)
    for (auto& point : t.stretch) point.compression += 2e-3;
  const YarnObjective objective(st.yarn_tile(), targets, tight_options(st));
  // Off the truth, so that the residuals are not zero.
  yarn::YarnParams at = truth;
  at.kb *= 1.3;
  at.kc1 *= 0.8;
  const RestState rest = objective.rest_state(at);
  ASSERT_TRUE(rest.ok) << rest.message;
  const std::vector<yarn::YarnParam> wanted{yarn::YarnParam::ks1, yarn::YarnParam::kb, yarn::YarnParam::r1,
                                            yarn::YarnParam::kc1};
  AtRestOptions with;
  with.wanted = wanted;
  const ObjectiveResult r = objective.evaluate_at_rest(rest, at, with);
  ASSERT_TRUE(r.ok) << r.message;
  const Eigen::VectorXd res = residual_vector(r);
  EXPECT_NEAR(res.squaredNorm(), r.value, 1e-12 * r.value);
  const Eigen::MatrixXd j = residual_jacobian(r);
  EXPECT_EQ(j.rows(), res.size());
  EXPECT_EQ(j.cols(), 4);
  EXPECT_EQ(r.held_compressions, 0);

  const JacobianCheck c = check_residual_jacobian(objective, rest, at, wanted);
  ASSERT_TRUE(c.ok) << c.message;
  for (const auto& col : c.columns) {
    std::cout << "[ jacobian ] " << yarn::to_string(col.param) << ": |dr/dlog p| " << col.column_norm
              << ", relative error " << col.relative_error << " at step " << col.step << "\n";
    EXPECT_GT(col.column_norm, 0.0) << yarn::to_string(col.param);
  }
  EXPECT_LE(c.worst, 1e-4);
}

// The bending term (issue 48): its rows of the Jacobian, dΔσ_κ/dθ from the energy's exact
// parameter derivatives at the two bent equilibria, against central differences of the
// residuals (re-solved at every step), and its share of g.
TEST(ResidualJacobian, TheBendingRowsMatchCentralDifferences) {
  YARNFIT_REQUIRE_SHARED(testcase::stockinette_pattern());
  const testcase::Stockinette st = testcase::load_stockinette();
  yarn::YarnParams truth = st.soft_toe_params();
  truth.eps_s = 0.05;
  auto targets = st.synthesise(truth, {db::Direction::weft}, 0.2, 5).targets;
  for (auto& point : targets[0].stretch) point.compression += 2e-3;
  const double ktheta = 2e-5;  // [N·m]
  for (const double kappa : {0.0, 40.0, 80.0}) targets[0].bending.push_back({kappa, 2.0 * ktheta * kappa});
  ObjectiveOptions o = tight_options(st);
  o.bending_samples = 2;
  const YarnObjective objective(st.yarn_tile(), targets, o);
  yarn::YarnParams at = truth;
  at.kb *= 1.3;
  at.kc1 *= 0.8;
  const RestState rest = objective.rest_state(at);
  ASSERT_TRUE(rest.ok) << rest.message;
  const std::vector<yarn::YarnParam> wanted{yarn::YarnParam::kb, yarn::YarnParam::r1, yarn::YarnParam::kc1};
  AtRestOptions with;
  with.wanted = wanted;
  const ObjectiveResult r = objective.evaluate_at_rest(rest, at, with);
  ASSERT_TRUE(r.ok) << r.message;
  ASSERT_EQ(r.directions.size(), 1u);
  const DirectionError& d = r.directions[0];
  ASSERT_EQ(d.bending_sim.size(), 2u);
  EXPECT_DOUBLE_EQ(d.bending_curvature[1], 80.0);
  EXPECT_GT(d.bending_sim[1], d.bending_sim[0]);
  const Eigen::VectorXd res = residual_vector(r);
  EXPECT_NEAR(res.squaredNorm(), r.value, 1e-12 * r.value);
  EXPECT_EQ(residual_jacobian(r).rows(), res.size());
  // Without bending in the objective the term is gone.
  ObjectiveOptions off = o;
  off.bending_weight = 0.0;
  const YarnObjective without(st.yarn_tile(), targets, off);
  const ObjectiveResult r0 = without.evaluate_at_rest(rest, at, with);
  ASSERT_TRUE(r0.ok) << r0.message;
  EXPECT_TRUE(r0.directions[0].bending_sim.empty());
  EXPECT_LT(r0.value, r.value);

  const JacobianCheck c = check_residual_jacobian(objective, rest, at, wanted);
  ASSERT_TRUE(c.ok) << c.message;
  for (const auto& col : c.columns)
    std::cout << "[ jacobian ] with bending, " << yarn::to_string(col.param) << ": relative error " << col.relative_error
              << "\n";
  EXPECT_LE(c.worst, 1e-4);
}

}  // namespace
}  // namespace yarnfit::yarn
