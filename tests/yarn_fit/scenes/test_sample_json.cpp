// One sample of a yarn scene and what `yarn sim` / `yarn curve` print of it
// (yarn_fit/scenes/sample_json.hpp): read-outs and effects when it converges, nulls with the
// termination and reason when it does not.
#include <gtest/gtest.h>

#include "tests/example_fabric.hpp"
#include "tests/test_support.hpp"
#include "yarn_fit/scenes/sample_json.hpp"

namespace yarnfit::yarn {
namespace {

namespace fs = std::filesystem;
using namespace yarnfit::testing;

YarnScene example_scene(const yarnfit::testing::ScratchDir& dir, int max_iterations) {
  db::Problems problems;
  const auto tile = db::read_pyp(k_example_tile, problems);
  EXPECT_TRUE(tile) << problems.to_string();
  yarnfit::testing::write_file(dir / "y.json", to_json(default_params(scales_of(*tile, 120.0))).dump());
  YarnSceneSetup s;
  s.pattern = k_example_tile;
  s.params = dir / "y.json";
  s.rest_shape = false;
  s.max_iterations = max_iterations;
  auto scene = load_yarn_scene(s, problems);
  EXPECT_TRUE(scene) << problems.to_string();
  return std::move(*scene);
}

TEST(SceneSample, AConvergedSampleWithItsReadOutsAndEffects) {
  yarnfit::testing::ScratchDir dir("scene_sample");
  YarnScene scene = example_scene(dir, 200);
  const SceneSampleRequest request{0.05, 0.0, false, 0.0, false};
  const SceneSample s = simulate_scene_sample(scene, request);
  ASSERT_TRUE(s.ok) << s.message;
  EXPECT_EQ(s.termination, to_string(s.sample.last_solve.status));
  EXPECT_TRUE(s.termination == "converged" || s.termination == "converged_readout") << s.termination;
  EXPECT_GT(s.newton_iterations, 0);
  const nlohmann::json j = sample_json(scene, request, s, 1, 0.5);
  EXPECT_EQ(j["energy_density"].get<double>(), s.sample.energy_density);
  EXPECT_EQ(j["stress_s"].get<double>(), s.sample.stress_s);
  EXPECT_EQ(j["compression"].get<double>(), 0.0);
  EXPECT_EQ(j["compression_mode"], "fixed");
  EXPECT_TRUE(j["converged"].get<bool>());
  EXPECT_TRUE(j.contains("coarse_stress"));
  EXPECT_FALSE(j.contains("stress_kappa"));
  EXPECT_FALSE(j["effects"].empty());
  EXPECT_EQ(j["total_seconds"].get<double>(), 0.5);
  EXPECT_EQ(j["direction"], "weft");
}

TEST(SceneSample, ANonConvergedSampleIsAResultWithNullsAndItsReason) {
  yarnfit::testing::ScratchDir dir("scene_sample_fail");
  YarnScene scene = example_scene(dir, 1);
  const SceneSampleRequest request{0.1, 0.0, false, 0.0, false};
  const SceneSample s = simulate_scene_sample(scene, request);
  EXPECT_FALSE(s.ok);
  EXPECT_EQ(s.termination, "max_iterations");
  EXPECT_FALSE(s.message.empty());
  const nlohmann::json j = sample_json(scene, request, s, 1, 0.0);
  EXPECT_TRUE(j["energy_density"].is_null());
  EXPECT_TRUE(j["stress_s"].is_null());
  EXPECT_FALSE(j["converged"].get<bool>());
  EXPECT_EQ(j["termination"], "max_iterations");
}

TEST(SceneSample, SweepCsvLeavesAFailedPointsReadOutsEmpty) {
  StretchSweep sweep;
  Sample ok;
  ok.ok = true;
  ok.chi.stretch = 0.0;
  ok.chi.compression = 0.01;
  ok.energy_density = 1.5;
  ok.stress_s = 2.5;
  Sample settled = ok;  // ended by the stress read-out test: the CSV says so
  settled.chi.stretch = 0.05;
  settled.last_solve.status = Termination::converged_readout;
  settled.band_lower = 0.01;  // flat in c: c is the band's point of smallest |c|
  settled.band_upper = 0.5;
  settled.flat = true;
  Sample failed;
  failed.chi.stretch = 0.1;
  failed.last_solve.status = Termination::max_iterations;
  sweep.points = {ok, settled, failed};
  EXPECT_EQ(sweep_csv("warp", sweep),
            "direction,stretch,compression,energy_density_J_per_m2,stress_s_N_per_m,converged,newton_iterations,"
            "seconds,solves,stress_c_N_per_m,termination,compression_band_lower,compression_band_upper,flat\n"
            "warp,0,0.01,1.5,2.5,1,0,0,0,0,converged,,,0\n"
            "warp,0.05,0.01,1.5,2.5,1,0,0,0,0,converged_readout,0.01,0.5,1\n"
            "warp,0.1,,,,0,0,0,0,,max_iterations,,,0\n");
}

}  // namespace
}  // namespace yarnfit::yarn
