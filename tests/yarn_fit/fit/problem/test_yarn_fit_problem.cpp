// A fabric record turned into a yarn-fit problem (yarn_fit/fit/problem/yarn_fit_problem.hpp):
// ks2 from the stiffest yarn, R_est from the tile facts, the tile turned to its weft axis,
// the start parameters checked against the bounds, and every problem named with its file.
#include <gtest/gtest.h>

#include <cmath>

#include "yarn_fit/fit/problem/yarn_fit_problem.hpp"
#include "tests/example_fabric.hpp"
#include "tests/test_support.hpp"

namespace yarnfit::yarn {
namespace {

using namespace yarnfit::testing;

TEST(YarnFitProblem, ScalesFromTheStiffestYarnAndTheTileFacts) {
  const db::Fabric f = bundled_example();
  db::Problems problems;
  const auto p = make_yarn_fit_problem(f, problems);
  ASSERT_TRUE(p) << problems.to_string();
  EXPECT_TRUE(problems.empty());
  EXPECT_EQ(p->fabric_id, "stockinette_demo");
  EXPECT_EQ(p->scales.ks2, 120.0);  // stiffness_N of the record's yarn
  EXPECT_EQ(p->scales.r_est, f.pattern->facts.r_est);
  EXPECT_GT(p->scales.r_est, 0.0);
  EXPECT_EQ(p->tile.vertex_count(), yarn::make_yarn_tile(f.pattern->tile).vertex_count());
  EXPECT_TRUE(p->targets.empty());
  EXPECT_FALSE(p->start);
}

TEST(YarnFitProblem, ATileWhoseWeftRunsAlongYIsTurned) {
  db::Fabric f = bundled_example();
  f.pattern->weft_axis = db::Axis::y;
  db::Problems problems;
  const auto turned = make_yarn_fit_problem(f, problems);
  ASSERT_TRUE(turned) << problems.to_string();
  const yarn::YarnTile as_read = yarn::make_yarn_tile(f.pattern->tile);
  // Turned by −90°: the tile's y period now lies along x.
  EXPECT_NEAR(turned->tile.lattice.col(1).norm(), as_read.lattice.col(1).norm(), 1e-15);
  EXPECT_NEAR(std::abs(turned->tile.lattice(0, 1)), as_read.lattice.col(1).norm(), 1e-12);
}

TEST(YarnFitProblem, EveryProblemOfTheRecordNamesFabricYaml) {
  db::Fabric f = bundled_example();
  f.pattern.reset();
  for (auto& y : f.yarns) y.stiffness.reset();
  db::Problems problems;
  EXPECT_FALSE(make_yarn_fit_problem(f, problems));
  const std::string yaml = (f.folder / "fabric.yaml").string();
  const std::string text = problems.to_string();
  EXPECT_NE(text.find(yaml + ": pattern: missing"), std::string::npos) << text;
  EXPECT_NE(text.find(yaml + ": yarns.stiffness_N: missing"), std::string::npos) << text;
}

TEST(YarnFitProblem, StartInsideTheBoundsSkipsTheSwarmOutsideIsNamed) {
  yarnfit::testing::ScratchDir dir("yarn_problem");
  db::Problems problems;
  auto p = make_yarn_fit_problem(bundled_example(), problems);
  ASSERT_TRUE(p);
  const yarn::YarnParams mid = yarn::default_params(p->scales);
  yarnfit::testing::write_file(dir / "start.json", yarn::to_json(mid).dump());
  read_start(*p, dir / "start.json", false, problems);
  ASSERT_TRUE(problems.empty()) << problems.to_string();
  ASSERT_TRUE(p->start);
  EXPECT_EQ(p->start->kb, mid.kb);
  const YarnFitSettings s = settings_for(*p, YarnFitSettings{});
  EXPECT_FALSE(s.swarm);
  ASSERT_TRUE(s.start);
  EXPECT_EQ(s.start->r1, mid.r1);

  nlohmann::json outside = yarn::to_json(mid);
  outside["R1"] = 10.0 * mid.r1;
  yarnfit::testing::write_file(dir / "outside.json", outside.dump());
  read_start(*p, dir / "outside.json", false, problems);
  ASSERT_EQ(problems.size(), 1u) << problems.to_string();
  EXPECT_EQ(problems.items()[0].file, (dir / "outside.json").string());
  EXPECT_EQ(problems.items()[0].field, "R1");
  EXPECT_NE(problems.items()[0].message.find("is outside the search bounds"), std::string::npos);
  EXPECT_NE(problems.items()[0].message.find("of this fabric"), std::string::npos);
}

TEST(YarnFitProblem, JsonNamesTheFabricAndTheTargetsSource) {
  db::Problems problems;
  auto p = make_yarn_fit_problem(bundled_example(), problems);
  ASSERT_TRUE(p);
  p->targets_source = "somewhere/uniform_targets.csv";
  YarnFitResult r;
  r.message = "not run";
  const nlohmann::json j = results::to_json(to_file(*p, r, YarnFitSettings{}));
  EXPECT_EQ(j["fabric"], "stockinette_demo");
  EXPECT_EQ(j["targets"], "somewhere/uniform_targets.csv");
  EXPECT_TRUE(j["errors"]["stress_full_pct"].is_null());
  EXPECT_EQ(j["errors_reason"], "not run");
}

}  // namespace
}  // namespace yarnfit::yarn
