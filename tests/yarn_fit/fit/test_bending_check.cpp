// The bending check of fitted yarn parameters (yarn_fit/fit/objective/bending_check): the yarn
// model scores zero against bending targets made from its own response, and the stated
// error against targets twice as stiff; without bending targets nothing is checked.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "yarn_fit/fit/objective/bending_check.hpp"
#include "yarn_fit/fit/synth/synthetic_yarn_fabric.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"
#include "tests/yarn_fit/fit/stockinette_case.hpp"
#include "tests/test_support.hpp"
#include "yarn_fit/periodic/yarn_tile.hpp"

namespace yarnfit::yarn {
namespace {

TEST(BendingCheck, ZeroAgainstItsOwnResponseAndTheStatedErrorAgainstTwiceIt) {
  YARNFIT_REQUIRE_SHARED(testcase::stockinette_pattern());
  const testcase::Stockinette st = testcase::load_stockinette();
  const yarn::YarnTile ytile = st.yarn_tile();
  const yarn::YarnParams params = yarn::default_params(st.scales);
  // The fit passes its objective's options, whose loose tolerance is 1e-3 of the comfort
  // stress norm times the shorter period (about 3e-5 N here): a bent, barely touching tile
  // creeps with a residual below that for hundreds of iterations.
  ObjectiveOptions options;
  options.solve.loose_tolerance = 3e-5;

  // No bending targets: nothing to check, and that is not a failure.
  std::vector<db::DirectionTargets> targets(1);
  targets[0].direction = db::Direction::warp;
  targets[0].stretch = {{0.0, 0.0, 0.0, true}, {0.1, 0.02, 5.0, true}};
  const BendingCheck none = check_bending(ytile, targets, params, options);
  EXPECT_TRUE(none.ok) << none.message;
  EXPECT_TRUE(none.directions.empty());

  // Curvatures as a pear-loop fit gives them (0–120 1/m), targets 0 at first.
  for (int i = 0; i <= 6; ++i) targets[0].bending.push_back({20.0 * i, 0.0});
  const BendingCheck own = check_bending(ytile, targets, params, options, 4);
  ASSERT_TRUE(own.ok) << own.message;
  ASSERT_EQ(own.directions.size(), 1u);
  const auto& d = own.directions[0];
  ASSERT_EQ(d.curvature.size(), 4u);
  EXPECT_EQ(d.curvature.front(), 0.0);
  EXPECT_EQ(d.curvature.back(), 120.0);
  EXPECT_EQ(d.stress_sim.front(), 0.0);  // relative to the tile's own curl
  std::cout << "[ bending  ] warp: curl " << d.curl_stress << " N; dsigma_kappa at 40, 80, 120 1/m: " << d.stress_sim[1]
            << ", " << d.stress_sim[2] << ", " << d.stress_sim[3] << " N; " << own.solves << " solves, " << own.seconds
            << " s\n";
  EXPECT_GT(d.stress_sim.back(), 0.0);  // bending costs energy: stiffer with κ

  // Targets equal to the response at the checked curvatures (others interpolated), then twice it.
  double mean_abs = 0.0, largest = 0.0;
  for (std::size_t k = 0; k < 4; ++k) {
    mean_abs += std::abs(d.stress_sim[k]) / 4.0;
    largest = std::max(largest, std::abs(d.stress_sim[k]));
  }
  std::vector<db::DirectionTargets> same = targets, twice = targets;
  same[0].bending.clear();
  twice[0].bending.clear();
  for (std::size_t k = 0; k < 4; ++k) {
    same[0].bending.push_back({d.curvature[k], d.stress_sim[k]});
    twice[0].bending.push_back({d.curvature[k], 2.0 * d.stress_sim[k]});
  }
  const BendingCheck a = check_bending(ytile, same, params, options, 4);
  const BendingCheck b = check_bending(ytile, twice, params, options, 4);
  ASSERT_TRUE(a.ok && b.ok) << a.message << b.message;
  EXPECT_LT(a.bending_pct, 1e-6);
  EXPECT_NEAR(b.bending_pct, 100.0 * mean_abs / (2.0 * largest), 1e-6);
}

}  // namespace
}  // namespace yarnfit::yarn
