// The calibration driver when nothing works: every candidate failing is reported with the
// reason, not thrown, and no parameters are passed off as a fit.
#include <gtest/gtest.h>

#include "calibration/fit/yarn_calibration.hpp"
#include "calibration/synth/synthetic_yarn_fabric.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"
#include "tests/test_support.hpp"
#include "yarn_fit/periodic/yarn_tile.hpp"

namespace yarnfit::calibration {
namespace {

TEST(YarnCalibration, EveryCandidateFailingIsReportedWithItsReason) {
  const auto pattern = testing::shared_dir() / "data" / "patterns" / "stockinette.pyp";
  YARNFIT_REQUIRE_SHARED(pattern);
  db::Problems problems;
  const auto tile = db::read_pyp(pattern, problems);
  ASSERT_TRUE(tile) << problems.to_string();
  const yarn::ParameterScales scales{400.0, db::compute_tile_facts(*tile).r_est};
  SyntheticYarnOptions so;
  so.directions = {db::Direction::weft};
  so.max_stretch = 0.1;
  so.points = 3;
  const SyntheticYarnResult synth = simulate_yarn_targets(*tile, yarn::default_params(scales), so);

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
    const YarnFitResult r = fit_yarn_params(yarn::make_yarn_tile(*tile), synth.targets, scales, s);
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
