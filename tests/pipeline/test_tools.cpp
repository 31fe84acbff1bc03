// The commands without a fit as library calls (pipeline/tools/): each takes a request in the
// user's units, names the fields of every problem before any work, and makes what the command
// line's version makes, without a command line.
#include <gtest/gtest.h>

#include <filesystem>

#include "fabrics_db/tile/periodic_tile.hpp"
#include "pipeline/tools/make_tile.hpp"
#include "pipeline/tools/simulate_shell.hpp"
#include "tests/test_support.hpp"

namespace yarnfit::testing {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> fields_of(const db::Problems& problems) {
  std::vector<std::string> fields;
  for (const auto& p : problems.items()) fields.push_back(p.field);
  return fields;
}

TEST(PipelineTools, AWovenTileIsMadeAndWrittenByOneCallAndAnExistingOneIsLeftAlone) {
  ScratchDir dir("tools_tile");
  pipeline::TileRequest r;
  r.weave = "basket2x2";
  r.yarn_spacing_mm = 1.5;
  r.yarn_radius_mm = 0.5;
  r.out = (dir / "basket.pyp").string();
  db::Problems problems;
  const pipeline::MadeTile made = pipeline::make_tile(r, problems);
  ASSERT_TRUE(problems.empty()) << problems.to_string();
  ASSERT_TRUE(made.written);
  EXPECT_EQ(made.facts.at("weave_rows"), "1100/1100/0011/0011");
  const auto tile = db::read_pyp(r.out, problems);
  ASSERT_TRUE(tile) << problems.to_string();
  EXPECT_EQ(static_cast<long long>(tile->vertex_count()), made.facts.at("vertices").get<long long>());
  EXPECT_NE(made.summary.find("wrote " + r.out), std::string::npos) << made.summary;

  // The same request again: the file is named and kept; with force it is made again.
  const std::string before = read_file(r.out);
  const pipeline::MadeTile again = pipeline::make_tile(r, problems);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems.items()[0].file, r.out);
  EXPECT_FALSE(again.written);
  EXPECT_EQ(read_file(r.out), before);
  problems = {};
  r.force = true;
  EXPECT_TRUE(pipeline::make_tile(r, problems).written) << problems.to_string();
}

TEST(PipelineTools, EveryProblemOfARequestIsNamedByItsFieldBeforeAnyWork) {
  ScratchDir dir("tools_problems");
  pipeline::TileRequest tile;
  tile.chart = "seed";
  tile.weave = "plain";
  tile.stitch_length_mm = 3.0;
  tile.yarn_radius_mm = 0.5;
  tile.yarn_spacing_mm = 1.5;
  tile.out = (dir / "never.pyp").string();
  db::Problems problems;
  EXPECT_FALSE(pipeline::make_tile(tile, problems).written);
  EXPECT_EQ(fields_of(problems), (std::vector<std::string>{"chart", "stitch_length_mm"})) << problems.to_string();
  EXPECT_FALSE(fs::exists(tile.out));

  pipeline::ShellSimRequest sim;
  sim.scene = "pear";
  sim.stretch = {0.1};
  sim.values.kxx = -1.0;
  sim.values.mesh_mm = 0.0;
  problems = {};
  const auto outcome = pipeline::simulate_shell_scene(sim, problems);
  EXPECT_TRUE(outcome.json.is_null());
  EXPECT_EQ(fields_of(problems), (std::vector<std::string>{"distance", "stretch", "kxx", "ktheta_weft", "ktheta_bias",
                                                           "ktheta_warp", "mesh"}))
      << problems.to_string();
}

TEST(PipelineTools, AShellSceneTakesTheFilesParametersExceptThoseGiven) {
  ScratchDir dir("tools_shell");
  write_file(dir / "shell_fit.json", R"({"params": {"kxx": 80, "kxy": 10, "kyy": 200, "kss": 15, "kn1": 3, "kn2": 2}})");
  pipeline::ShellSimRequest sim;
  sim.params_file = (dir / "shell_fit.json").string();
  sim.stretch = {0.1};
  sim.values.refine = 0;
  sim.values.kyy = 210.0;
  sim.given_parameters = {"kyy"};
  db::Problems problems;
  const auto outcome = pipeline::simulate_shell_scene(sim, problems);
  ASSERT_TRUE(problems.empty()) << problems.to_string();
  EXPECT_TRUE(outcome.converged) << outcome.failure;
  EXPECT_EQ(outcome.json.at("params").at("kxx").get<double>(), 80.0);
  EXPECT_EQ(outcome.json.at("params").at("kyy").get<double>(), 210.0);
  EXPECT_EQ(outcome.json.at("direction"), "weft");
}

}  // namespace
}  // namespace yarnfit::testing
