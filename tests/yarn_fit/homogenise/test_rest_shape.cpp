// The rest-shape heuristic (yarn_fit/homogenise/rest_shape.hpp) on the real stockinette tile:
// little coarse stress left at rest, rest lengths within their bound, and the period stage.

#include <gtest/gtest.h>

#include <Eigen/SparseCore>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "tests/yarn_fit/yarn_fixtures.hpp"

namespace yarnfit::yarn {
namespace {

using namespace fixtures;

TEST_F(StockinetteSystem, RestShapeLeavesLittleCoarseStressAndKeepsRestLengthsInBounds) {
  YarnSystem sys(make_yarn_tile(tile), params);
  Eigen::VectorXd rest = Eigen::VectorXd::Zero(sys.dof_count());
  const RestShapeResult r = relax_rest_shape(sys, rest);
  ASSERT_TRUE(r.converged) << r.last_solve.message;
  EXPECT_LE(r.max_length_change, 0.2 + 1e-12);
  for (std::size_t e = 0; e < sys.tile().edges.size(); ++e) {
    const double ratio = sys.tile().edges[e].rest_length / sys.tile().input_rest_lengths[e];
    ASSERT_LE(std::abs(ratio - 1.0), 0.2 + 1e-12) << "edge " << e;
  }
  std::printf("rest shape: %d rounds, %d Newton iterations, %.2f s, rest lengths moved up to %.1f %%;\n"
              "  period stretch E = (%.2f %%, %.2f %%, %.2f %%) took P = (%.3g, %.3g) to (%.3g, %.3g) N/m\n",
              r.rounds, r.newton_iterations, r.seconds, 100 * r.max_length_change,
              100 * r.period_stretch(0, 0), 100 * r.period_stretch(1, 1), 100 * r.period_stretch(0, 1),
              r.stress_before_period(0, 0), r.stress_before_period(1, 1), r.rest_stress(0, 0), r.rest_stress(1, 1));
  for (const double angle : {weft_angle(), bias_angle(), warp_angle()}) {
    Eigen::VectorXd g = rest;
    const Sample at10 = simulate_sample(sys, {0.1, 0.0, 0.0, angle}, g);
    ASSERT_TRUE(at10.ok) << at10.message;
    const Eigen::Vector2d u = CoarseDeformation{0.0, 0.0, 0.0, angle}.u();
    const double left = u.dot(r.rest_stress * u);
    EXPECT_LT(std::abs(left), 0.05 * at10.stress_s) << "angle " << angle;
    std::printf("  angle %.3f: rest stress %.4g N/m, sigma_s(10 %%) %.4g N/m (%.1f %%)\n", angle, left,
                at10.stress_s, 100 * std::abs(left) / at10.stress_s);
  }
}

// The period stage relaxes the normal rest stress by stretching the period, and leaves its
// shear alone unless asked (RestShapeOptions::period_shear): the tile is soft in shear at
// rest, and the E01 that zeroes that small stress followed every small change of it.

TEST_F(StockinetteSystem, PeriodStageRelaxesNormalStressAndTouchesShearOnlyWhenAsked) {
  for (const bool shear : {false, true}) {
    YarnSystem sys(make_yarn_tile(tile), params);
    Eigen::VectorXd rest;
    RestShapeOptions options;
    options.period_shear = shear;
    const RestShapeResult r = relax_rest_shape(sys, rest, options);
    ASSERT_TRUE(r.converged) << r.last_solve.message;
    std::printf("period shear %s: E = (%.3f %%, %.3f %%, %.3f %%), P from (%.3g, %.3g, %.3g) to (%.3g, %.3g, %.3g) N/m\n",
                shear ? "on " : "off", 100 * r.period_stretch(0, 0), 100 * r.period_stretch(1, 1),
                100 * r.period_stretch(0, 1), r.stress_before_period(0, 0), r.stress_before_period(1, 1),
                r.stress_before_period(0, 1), r.rest_stress(0, 0), r.rest_stress(1, 1), r.rest_stress(0, 1));
    EXPECT_DOUBLE_EQ(r.period_stretch(0, 1), r.period_stretch(1, 0));
    for (int k = 0; k < 2; ++k) {
      EXPECT_NE(r.period_stretch(k, k), 0.0) << "E" << k << k;
      EXPECT_LT(std::abs(r.rest_stress(k, k)), 0.25 * std::abs(r.stress_before_period(k, k))) << "P" << k << k;
    }
    if (shear) {
      EXPECT_NE(r.period_stretch(0, 1), 0.0);
      EXPECT_LT(std::abs(r.rest_stress(0, 1)), std::abs(r.stress_before_period(0, 1)));
    } else {
      EXPECT_EQ(r.period_stretch(0, 1), 0.0);
    }
    // The tile is what the stage says: its period is the input's times (I + E).
    const Eigen::Matrix2d expected = (Eigen::Matrix2d::Identity() + r.period_stretch) * make_yarn_tile(tile).lattice;
    EXPECT_LT((sys.tile().lattice - expected).norm(), 1e-12 * expected.norm());
  }
}

}  // namespace
}  // namespace yarnfit::yarn
