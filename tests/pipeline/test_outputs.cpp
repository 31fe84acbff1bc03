// The output folders of the fit commands (pipeline/outputs.hpp): what is refused before any
// work, and what each stage's result writes.
#include <gtest/gtest.h>

#include "pipeline/outputs.hpp"
#include "tests/test_support.hpp"

namespace yarnfit::pipeline {
namespace {

namespace fs = std::filesystem;
using namespace yarnfit::testing;

TEST(Outputs, ExistingFilesAreRefusedUnlessOverwriting) {
  ScratchDir dir("outputs");
  EXPECT_TRUE(output_problems(dir / "new", output_files(Stage::all), false).empty());
  write_file(dir / "out" / "yarn_fit.json", "mine\n");
  write_file(dir / "out" / "summary.txt", "mine\n");
  const auto problems = output_problems(dir / "out", output_files(Stage::all), false);
  EXPECT_EQ(problems.to_string(), (dir / "out" / "yarn_fit.json").string() + ": exists (use --force to replace it)\n" +
                                      (dir / "out" / "summary.txt").string() + ": exists (use --force to replace it)\n");
  EXPECT_TRUE(output_problems(dir / "out", output_files(Stage::all), true).empty());
  write_file(dir / "file", "x");
  EXPECT_EQ(output_problems(dir / "file", output_files(Stage::yarn), true).to_string(),
            (dir / "file").string() + ": exists and is not a folder\n");
}

TEST(Outputs, AShellStageThatFailedWritesItsTwoFilesOnly) {
  ScratchDir dir("outputs_shell");
  PipelineResult r;
  r.status = PipelineStatus::shell_failed;
  r.shell = shell::ShellFitResult{};
  r.shell->fabric_id = "x";
  const PipelineOutputs written = write_outputs(r, dir / "out");
  EXPECT_EQ(written.files, (std::vector<std::string>{"shell_fit.json", "uniform_targets.csv"}));
  EXPECT_TRUE(written.summary.empty());
  const auto j = nlohmann::json::parse(read_file(dir / "out" / "shell_fit.json"));
  EXPECT_EQ(j["fabric"], "x");
  EXPECT_TRUE(j["errors"]["stretch_force_pct"].is_null());  // nothing fitted: no figure, not 0
  EXPECT_FALSE(fs::exists(dir / "out" / "shell_curves.csv"));
}

TEST(Outputs, AYarnFitsFolderFromItsJson) {
  ScratchDir dir("outputs_yarn");
  results::YarnFitFile yarn;
  yarn.ok = true;
  yarn.fabric = "demo";
  yarn.targets = "t.csv";
  yarn.settings.swarm = false;
  const std::string summary = write_yarn_outputs(yarn, dir / "out");
  EXPECT_EQ(summary.rfind("yarn fit: ok\n", 0), 0u) << summary;
  EXPECT_EQ(read_file(dir / "out" / "yarn_summary.txt"), "fabric demo, targets t.csv\n" + summary);
  const auto written = nlohmann::json::parse(read_file(dir / "out" / "yarn_fit.json"));
  EXPECT_EQ(written, results::to_json(yarn));
  EXPECT_EQ(written["schema_version"], results::k_yarn_fit_schema_version);
  EXPECT_EQ(read_file(dir / "out" / "yarn_curves.csv").rfind("direction,sample,stretch,", 0), 0u);
}

}  // namespace
}  // namespace yarnfit::pipeline
