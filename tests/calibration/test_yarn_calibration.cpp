// The calibration driver when nothing works: every candidate failing is reported with the
// reason, not thrown, and no parameters are passed off as a fit.
#include <gtest/gtest.h>

#include "calibration/fit/yarn_calibration.hpp"
#include "calibration/synth/synthetic_yarn_fabric.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"
#include "tests/calibration/stockinette_case.hpp"
#include "tests/test_support.hpp"
#include "yarn_fit/periodic/yarn_tile.hpp"

namespace yarnfit::calibration {
namespace {

TEST(YarnCalibration, EveryCandidateFailingIsReportedWithItsReason) {
  YARNFIT_REQUIRE_SHARED(testcase::stockinette_pattern());
  const testcase::Stockinette st = testcase::load_stockinette();
  const yarn::ParameterScales& scales = st.scales;
  const SyntheticYarnResult synth = st.synthesise(yarn::default_params(scales), {db::Direction::weft}, 0.1, 3);

  YarnFitSettings s;
  s.particles = 3;
  s.iterations = 1;
  s.swarm_samples = 2;
  s.local_samples = 2;
  s.local_evaluations = 2;
  s.threads = 2;
  s.objective.solve.max_iterations = 1;  // no equilibrium can converge: every evaluation fails
  for (const bool swarm : {true, false}) {
    s.swarm = swarm;
    const YarnFitResult r = fit_yarn_params(st.yarn_tile(), synth.targets, scales, s);
    EXPECT_FALSE(r.ok) << "swarm " << swarm;
    EXPECT_FALSE(r.final.ok);
    EXPECT_NE(r.message.find(swarm ? "every swarm candidate failed" : "failed"), std::string::npos) << r.message;
    EXPECT_NE(r.message.find("max_iterations"), std::string::npos) << r.message;  // the solver's reason kept
    EXPECT_TRUE(r.bending.directions.empty());
    const nlohmann::json j = to_json(r, s);
    EXPECT_FALSE(j["ok"].get<bool>());
    EXPECT_TRUE(j["objective"].is_null());
  }
}

}  // namespace
}  // namespace yarnfit::calibration
