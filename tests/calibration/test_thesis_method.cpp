// The thesis's method (6.5.3: one particle swarm over every parameter, then COBYLA) stays
// selectable in full (`--global swarm --local cobyla`) and reproduces, to the last bit, what
// the yarn fit gave before issue 33 changed the default: the figures below are those of
// commit 0734728 for these settings (the same program built against that commit's
// libraries and against this one printed them with 17 significant digits). It uses the
// objective of before issue 33 (root_correction is the Gauss–Newton step's).

#include <gtest/gtest.h>

#include "calibration/fit/yarn_calibration.hpp"
#include "tests/calibration/stockinette_case.hpp"
#include "tests/test_support.hpp"

namespace yarnfit::calibration {
namespace {

TEST(ThesisMethod, SwarmAndCobylaReproduceThePreviousResultBitwise) {
  YARNFIT_REQUIRE_SHARED(testcase::stockinette_pattern());
  const testcase::Stockinette st = testcase::load_stockinette();
  yarn::YarnParams truth = yarn::default_params(st.scales);
  truth.ks1 = 0.05 * st.scales.ks2;
  const auto targets = st.synthesise(truth, {db::Direction::weft}, 0.15, 4).targets;
  YarnFitSettings s;
  s.global_method = GlobalMethod::swarm;
  s.local_method = LocalMethod::cobyla;
  s.particles = 6;
  s.iterations = 3;
  s.swarm_samples = 3;
  s.local_samples = 3;
  s.local_evaluations = 20;
  s.threads = 2;
  s.bending_points = 0;
  s.profile_step = 0.0;
  const YarnFitResult r = fit_yarn_params(st.yarn_tile(), targets, st.scales, s);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.params.ks1, 3.8958253770685709);
  EXPECT_EQ(r.params.eps_s, 0.00019301326868193658);
  EXPECT_EQ(r.params.kb, 1.6218509492403273e-06);
  EXPECT_EQ(r.params.r1, 0.0010035623088827162);
  EXPECT_EQ(r.params.kc1, 200295.30188541586);
  EXPECT_EQ(r.final.value, 0.19646609357298772);
  EXPECT_EQ(r.swarm.best_value, 0.27037733350360632);
  EXPECT_EQ(r.local.best_value, 0.19646609357298772);
  EXPECT_EQ(r.evaluations, 39);
  // One global stage (the swarm), one local run (COBYLA from its best).
  ASSERT_EQ(r.global.size(), 1u);
  EXPECT_EQ(r.global.front().name, "swarm");
  ASSERT_EQ(r.local_runs.size(), 1u);
  EXPECT_EQ(r.local.method, LocalMethod::cobyla);
}

}  // namespace
}  // namespace yarnfit::calibration
