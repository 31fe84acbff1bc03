// A yarn scene loaded from files (yarn_fit/scenes/yarn_scene.hpp): the bundled example's
// tile with parameters from a file, problems named with file and key, and the fixed
// parameters derived from ks2 when the file leaves them out.
#include <gtest/gtest.h>

#include "tests/example_fabric.hpp"
#include "tests/test_support.hpp"
#include "yarn_fit/scenes/yarn_scene.hpp"

namespace yarnfit::yarn {
namespace {

namespace fs = std::filesystem;
using namespace yarnfit::testing;


YarnSceneSetup setup_with(const fs::path& params) {
  YarnSceneSetup s;
  s.pattern = k_example_tile;
  s.params = params;
  s.direction = "bias";
  s.rest_shape = false;
  return s;
}

TEST(YarnScene, LoadsTheTileAndParametersAlongTheDirection) {
  ScratchDir dir("yarn_scene");
  db::Problems problems;
  const auto tile = db::read_pyp(k_example_tile, problems);
  ASSERT_TRUE(tile) << problems.to_string();
  const YarnParams p = default_params(scales_of(*tile, 120.0));
  write_file(dir / "y.json", to_json(p).dump());
  const auto scene = load_yarn_scene(setup_with(dir / "y.json"), problems);
  ASSERT_TRUE(scene) << problems.to_string();
  EXPECT_EQ(scene->params.kc1, p.kc1);
  EXPECT_EQ(scene->angle, direction_angle("bias"));
  EXPECT_EQ(scene->g.size(), scene->system->dof_count());
  EXPECT_EQ(scene->pattern_file, k_example_tile.string());
  EXPECT_EQ(tile_json(*scene)["vertices"], scene->system->tile().vertex_count());
  EXPECT_EQ(rest_shape_json(*scene), (nlohmann::json{{"applied", false}}));
  EXPECT_EQ(units_json()["stress_kappa"], "N");
  EXPECT_STREQ(to_string(CompressionMethod::cobyla), "cobyla");
}

TEST(YarnScene, ProblemsNameTheFileAndKsTwoFillsTheFixedParameters) {
  ScratchDir dir("yarn_scene_bad");
  db::Problems problems;
  const auto tile = db::read_pyp(k_example_tile, problems);
  ASSERT_TRUE(tile);
  nlohmann::json p = to_json(default_params(scales_of(*tile, 120.0)));
  p.erase("kc2");
  write_file(dir / "no_kc2.json", p.dump());
  EXPECT_FALSE(load_yarn_scene(setup_with(dir / "no_kc2.json"), problems));
  ASSERT_FALSE(problems.empty());
  bool named = false;
  for (const auto& q : problems.items()) named = named || (q.field == "kc2" && q.message == "missing");
  EXPECT_TRUE(named) << problems.to_string();

  problems = {};
  YarnSceneSetup with_ks2 = setup_with(dir / "no_kc2.json");
  with_ks2.ks2 = 120.0;
  const auto scene = load_yarn_scene(with_ks2, problems);
  ASSERT_TRUE(scene) << problems.to_string();
  EXPECT_EQ(scene->params.kc2, scales_of(*tile, 120.0).kc2());

  problems = {};
  EXPECT_FALSE(load_yarn_scene(setup_with(dir / "missing.json"), problems));
  EXPECT_NE(problems.to_string().find((dir / "missing.json").string()), std::string::npos) << problems.to_string();
}

// Found by fuzz_yarn_params (tests/fuzz_regressions): a key that is itself a mapping escaped
// as yaml-cpp's bad conversion instead of a problem.
TEST(YarnScene, AKeyThatIsNotANameIsAProblemWithItsLine) {
  ScratchDir dir("yarn_params_key");
  write_file(dir / "p.yaml", "ks1: 12\n? [a, b]\n: 3\n{c: 1}: 2\n");
  db::Problems problems;
  EXPECT_FALSE(read_yarn_params(dir / "p.yaml", std::nullopt, problems));
  int named = 0;
  for (const auto& q : problems.items())
    named += q.message == "a key must be a parameter name, not a mapping or list" && (q.line == 2 || q.line == 4);
  EXPECT_EQ(named, 2) << problems.to_string();
}

}  // namespace
}  // namespace yarnfit::yarn
