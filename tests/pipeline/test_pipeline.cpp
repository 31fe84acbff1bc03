// The whole fit of one fabric as a library call (run_plan without an output folder): every problem named
// before any work, and the yarn stage fitting the shell stage's targets in memory exactly as
// it fits them read back from uniform_targets.csv.
#include <gtest/gtest.h>

#include <memory>

#include "tests/example_fabric.hpp"
#include "pipeline/outputs.hpp"
#include "pipeline/plan.hpp"
#include "tests/pipeline/plan_helpers.hpp"
#include "tests/test_support.hpp"

namespace yarnfit::pipeline {
namespace {

namespace fs = std::filesystem;

using namespace yarnfit::testing;
const fs::path k_example = yarnfit::testing::bundled_example_folder();

// A yarn fit of a few evaluations.
PipelineOptions tiny() {
  PipelineOptions o;
  o.shell.threads = 2;
  o.yarn.particles = 2;
  o.yarn.iterations = 1;
  o.yarn.swarm_samples = 2;
  o.yarn.local_samples = 2;
  o.yarn.local_evaluations = 1;
  o.yarn.profile_step = 0.0;
  o.yarn.threads = 2;
  return o;
}

using plan_helpers::fields;
using plan_helpers::in_memory;
using plan_helpers::run_in_memory;

// The stages on the record in a folder, nothing written.
PipelineResult run_in_memory(const fs::path& folder, const PipelineOptions& options) {
  FitPlan plan;
  plan.fabric = folder;
  plan.options = options;
  return run_plan(plan);
}

TEST(PipelineOptions, EveryProblemOfBothStagesIsNamed) {
  PipelineOptions o;
  EXPECT_TRUE(o.problems().empty());
  o.shell.mesh = 0.0;
  o.yarn.particles = 1;
  o.yarn.swarm_samples = 1;
  EXPECT_EQ(fields(o.problems()), (std::vector<std::string>{"shell.mesh", "yarn.particles", "yarn.swarm_samples"}));
  // A start skips the swarm: its particles no longer matter.
  o.start = "start.yaml";
  EXPECT_EQ(fields(o.problems()), (std::vector<std::string>{"shell.mesh", "yarn.swarm_samples"}));
}

TEST(Pipeline, NothingRunsWhenAnythingIsWrongAndEveryProblemIsListed) {
  db::Fabric f = weft_only_example();
  f.pattern.reset();
  PipelineOptions o = tiny();
  o.yarn.particles = 1;
  const db::Problems before = check_plan(in_memory(f, o));
  EXPECT_EQ(fields(before), (std::vector<std::string>{"yarn.particles", "pattern"})) << before.to_string();
  const PipelineResult r = run_in_memory(f, o);
  EXPECT_EQ(r.status, PipelineStatus::invalid_input);
  EXPECT_EQ(r.problems.to_string(), before.to_string());
  EXPECT_FALSE(r.shell);
  EXPECT_FALSE(r.yarn);

  const PipelineResult missing = run_in_memory(k_example.parent_path() / "no_such_fabric", tiny());
  EXPECT_EQ(missing.status, PipelineStatus::invalid_input);
  EXPECT_NE(missing.problems.to_string().find("no_such_fabric/fabric.yaml: file:"), std::string::npos)
      << missing.problems.to_string();
  yarnfit::testing::ScratchDir dir("pipeline_invalid");
  EXPECT_TRUE(write_outputs(missing, dir / "out").files.empty());
  EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(Pipeline, TheYarnStageFitsTheShellTargetsInMemoryAsFromTheirFile) {
  const PipelineResult r = run_in_memory(weft_only_example(), tiny());
  ASSERT_EQ(r.status, PipelineStatus::ok) << r.message;
  ASSERT_TRUE(r.shell && r.yarn && r.yarn_problem);
  EXPECT_TRUE(r.shell->converged());
  EXPECT_EQ(db::uniform_targets_csv(r.yarn_problem->targets), db::uniform_targets_csv(r.shell->targets));
  EXPECT_GT(r.seconds_total, 0.0);
  EXPECT_GE(r.seconds_total, r.seconds_shell + r.seconds_yarn - 1e-6);

  yarnfit::testing::ScratchDir dir("pipeline");
  const PipelineOutputs written = write_outputs(r, dir / "out");
  EXPECT_EQ(written.files, output_files(Stage::all));
  for (const auto& f : output_files(Stage::all)) EXPECT_TRUE(fs::exists(dir / "out" / f)) << f;
  EXPECT_EQ(yarnfit::testing::read_file(dir / "out" / "summary.txt"), written.summary);
  const auto yarn_json = nlohmann::json::parse(yarnfit::testing::read_file(dir / "out" / "yarn_fit.json"));
  EXPECT_EQ(yarn_json["targets"], (dir / "out" / "uniform_targets.csv").string());
  EXPECT_EQ(yarn_json["effects"], nlohmann::json::array({"stretch", "bending", "contact"}));

  // The same yarn fit on the targets read back from the file: the same numbers, bit for bit.
  yarn::YarnFitProblem from_file = *r.yarn_problem;
  from_file.targets = db::read_uniform_targets(dir / "out" / "uniform_targets.csv");
  const yarn::YarnFitResult again = yarn::fit_yarn(from_file, tiny().yarn);
  ASSERT_TRUE(again.ok) << again.message;
  EXPECT_EQ(again.final.value, r.yarn->final.value);
  for (const double yarn::YarnParams::*field : {&yarn::YarnParams::ks1, &yarn::YarnParams::eps_s,
                                                &yarn::YarnParams::kb, &yarn::YarnParams::r1, &yarn::YarnParams::kc1})
    EXPECT_EQ(again.params.*field, r.yarn->params.*field);
}

}  // namespace
}  // namespace yarnfit::pipeline
