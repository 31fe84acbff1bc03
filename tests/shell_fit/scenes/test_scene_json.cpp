// What `yarnfit shell sim` prints for a scene run (shell_fit/scenes/scene_json.hpp): per
// target its outputs, effects and mesh, and for a run that failed which target and why.
#include <gtest/gtest.h>

#include "shell_fit/scenes/scene_json.hpp"
#include "tests/shell_fit/known_materials.hpp"

namespace yarnfit::shell {
namespace {

using nlohmann::json;

using known::k_knit;

TEST(SceneJson, ParamsUnderTheKeysOfShellFitJson) {
  ShellParams p;
  p.inplane = k_knit;
  p.bending.ktheta = {1e-6, 2e-6, 3e-6};
  EXPECT_EQ(params_json(p), (json{{"kxx", 120.0}, {"kxy", 35.0}, {"kyy", 400.0}, {"kss", 30.0}, {"kn1", 5.0},
                                  {"kn2", 8.0}, {"ktheta_weft", 1e-6}, {"ktheta_bias", 2e-6}, {"ktheta_warp", 3e-6}}));
}

TEST(SceneJson, StretchRunPerTargetAndTheFailedOnes) {
  ClampedStretchSetup setup;
  setup.target_edge = 10e-3;
  const ClampedStretchScene scene(setup);
  const std::vector<double> stretches{0.1, 0.2};
  const ClampedStretchRun run = scene.run(k_knit, stretches);
  ASSERT_TRUE(run.ok) << run.message;
  json j = stretch_run_json(setup, scene, stretches, run);
  EXPECT_EQ(j["scene"], "stretch");
  EXPECT_EQ(j["effects"], json::array({"membrane"}));
  EXPECT_EQ(j["mesh"]["vertices"], scene.vertex_count());
  ASSERT_EQ(j["samples"].size(), 2u);
  EXPECT_EQ(j["samples"][1]["force_N"].get<double>(), run.samples[1].force);
  EXPECT_EQ(j["samples"][1]["line_force_N_per_m"].get<double>(), run.samples[1].force / setup.width);
  EXPECT_EQ(j["newton_iterations"], run.samples[0].newton_iterations + run.samples[1].newton_iterations);

  // A membrane pushed to half its length buckles in its plane: the first target fails and
  // the next is marked as not simulated.
  const std::vector<double> bad{-0.5, 0.1};
  const ClampedStretchRun failed = scene.run(k_knit, bad);
  ASSERT_FALSE(failed.ok);
  j = stretch_run_json(setup, scene, bad, failed);
  EXPECT_FALSE(j["converged"].get<bool>());
  ASSERT_EQ(j["samples"].size(), 2u);
  EXPECT_FALSE(j["samples"][0]["converged"].get<bool>());
  EXPECT_EQ(j["samples"][0]["message"], failed.message);
  EXPECT_EQ(j["samples"][1]["message"], "not simulated: an earlier stretch failed");
}

TEST(SceneJson, PearRunWithItsGoverningStiffnessAndBendingLength) {
  PearLoopSetup setup;
  setup.target_edge = 5e-3;
  const PearLoopScene scene(setup);
  ShellParams p;
  p.inplane = k_knit;
  p.bending.ktheta = {2e-6, 2e-6, 2e-6};
  const PearLoopRun run = scene.run(p, {20e-3});
  const json j = pear_run_json(setup, scene, p.bending, run);
  EXPECT_EQ(j["scene"], "pear");
  EXPECT_EQ(j["effects"], json::array({"membrane", "bending", "gravity"}));
  EXPECT_EQ(j["governing_ktheta"], "ktheta_weft");
  EXPECT_EQ(j["bending_length_m"].get<double>(),
            bending_length(scene.effective_ktheta(p.bending), setup.areal_density, setup.gravity));
  ASSERT_EQ(j["samples"].size(), 1u);
  EXPECT_EQ(j["samples"][0]["aspect_ratio"].get<double>(), run.samples[0].aspect_ratio);
  EXPECT_EQ(j["converged"].get<bool>(), run.ok);
}

}  // namespace
}  // namespace yarnfit::shell
