// A fit as a plan of stages (pipeline/plan.hpp, pipeline/fit_request.hpp): every problem of a
// request refused at once before any work, and a plan that runs the same stages as the
// library call, writes each stage's files and tells its observer each stage in order.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include <nlohmann/json.hpp>

#include "pipeline/fit_request.hpp"
#include "pipeline/plan.hpp"
#include "tests/pipeline/plan_helpers.hpp"
#include "tests/example_fabric.hpp"
#include "tests/test_support.hpp"

namespace yarnfit::pipeline {
namespace {

namespace fs = std::filesystem;
using namespace yarnfit::testing;

// The bundled example with its weft stretch test only (a shell stage of about a second), as a
// record folder.
fs::path weft_only_record(const fs::path& dir) {
  const fs::path from = yarnfit::testing::bundled_example_folder();
  const fs::path to = dir / "weft_only";
  fs::create_directories(to);
  for (const char* f : {"stretch_weft.csv", "tile.pyp"}) fs::copy_file(from / f, to / f);
  write_file(to / "fabric.yaml",
             "id: weft_only\nfamily: single-jersey\nareal_density_gsm: 180\n"
             "yarns:\n  - {material: polyester, denier: 150, filaments: 48, mass_fraction: 1.0, stiffness_N: 120}\n"
             "pattern: {file: tile.pyp, weft_axis: x}\nswatch: {length_mm: 100, width_mm: 60}\n"
             "stretch_tests:\n  weft: {file: stretch_weft.csv}\n");
  return to;
}

// A yarn fit of a few evaluations.
FitRequest tiny(const fs::path& fabric, const fs::path& out) {
  FitRequest r;
  r.fabric = fabric;
  r.out = out;
  r.global_method = "swarm";
  r.particles = 2;
  r.iterations = 1;
  r.samples = 2;
  r.local_samples = 2;
  r.local_evaluations = 1;
  r.no_profile = true;
  r.threads = 2;
  return r;
}

using plan_helpers::fields;
using plan_helpers::run_in_memory;

bool has(const std::vector<std::string>& v, const std::string& s) { return std::find(v.begin(), v.end(), s) != v.end(); }

// A request run as the command line runs it: its plan, refused with the request's own problems.
PipelineResult run_request(const FitRequest& request, const PlanObserver& observer = {}) {
  db::Problems problems;
  const FitPlan plan = fit_plan(request, problems);
  return run_plan(plan, observer, std::move(problems));
}

TEST(Plan, EveryProblemOfARequestIsRefusedAtOnceBeforeAnyWork) {
  ScratchDir dir("plan_refused");
  FitRequest r = tiny(weft_only_record(dir.path()), dir / "out");
  r.budget = "lavish";
  r.local_method = "simplex";
  r.mesh_mm = -1.0;
  r.particles = 1;
  write_file(dir / "out" / "summary.txt", "mine\n");
  std::vector<StageEvent> events;
  const PipelineResult result = run_request(r, [&events](const StageEvent& e) { events.push_back(e); });
  EXPECT_EQ(result.status, PipelineStatus::invalid_input);
  const auto named = fields(result.problems);
  for (const char* f : {"budget", "local_method", "shell.mesh", "yarn.particles"})
    EXPECT_TRUE(has(named, f)) << f << "\n" << result.problems.to_string();
  EXPECT_TRUE(has(named, (dir / "out" / "summary.txt").string())) << result.problems.to_string();
  EXPECT_TRUE(events.empty());
  EXPECT_EQ(read_file(dir / "out" / "summary.txt"), "mine\n");  // nothing of the user's replaced
  EXPECT_FALSE(fs::exists(dir / "out" / "shell_fit.json"));

  // A yarn stage alone needs its targets; a batch-style plan of a missing record names it.
  FitRequest yarn = tiny(dir / "weft_only", dir / "yarn_out");
  yarn.stages = "yarn";
  EXPECT_TRUE(has(fields(run_request(yarn).problems), "targets"));
  yarn.stages = "most";
  EXPECT_TRUE(has(fields(run_request(yarn).problems), "stages"));
  FitPlan no_record;
  no_record.fabric = dir / "no_such_fabric";
  no_record.out = dir / "missing_out";
  const PipelineResult missing = run_plan(no_record);
  EXPECT_EQ(missing.status, PipelineStatus::invalid_input);
  EXPECT_FALSE(missing.problems.empty());
  EXPECT_FALSE(fs::exists(dir / "missing_out"));
}

TEST(Plan, ExportsAreWrittenBesideTheFitAfterItAndLinkedFromTheReport) {
  ScratchDir dir("plan_exports");
  FitRequest r = tiny(weft_only_record(dir.path()), dir / "out");
  r.stages = "shell";
  r.report = true;
  r.exports = {"u3m", "arcsim", "table"};
  std::vector<Stage> order;
  const PipelineResult result = run_request(r, [&order](const StageEvent& e) {
    if (order.empty() || order.back() != e.stage) order.push_back(e.stage);
  });
  ASSERT_TRUE(result.ok()) << result.message << result.write_error << result.problems.to_string();
  EXPECT_EQ(order, (std::vector<Stage>{Stage::shell, Stage::exports, Stage::report}));
  for (const char* f : {"exports/weft_only.u3ma", "exports/weft_only_arcsim.json", "exports/table/table.json"}) {
    EXPECT_TRUE(fs::exists(dir / "out" / f)) << f;
    EXPECT_TRUE(has(result.outputs.files, f)) << f;
  }
  EXPECT_NE(result.outputs.text.find("ARCSim material of weft_only"), std::string::npos) << result.outputs.text;
  EXPECT_NE(read_file(dir / "out/report/index.html").find("href=\"../exports/weft_only.u3ma\""), std::string::npos);

  // Refused before any work: a format that does not exist, the yarn stage alone (no shell law),
  // ARCSim for a record without an areal density, an export file in the way.
  FitRequest bad = tiny(dir / "weft_only", dir / "bad_out");
  bad.exports = {"obj"};
  EXPECT_TRUE(has(fields(run_request(bad).problems), "export"));
  bad.exports = {"table"};
  bad.stages = "yarn";
  bad.targets = dir / "out" / "uniform_targets.csv";
  EXPECT_TRUE(has(fields(run_request(bad).problems), "export"));
  std::string yaml = read_file(dir / "weft_only/fabric.yaml");
  yaml.replace(yaml.find("areal_density_gsm: 180\n"), 23, "");
  write_file(dir / "weft_only/fabric.yaml", yaml);
  FitRequest no_density = tiny(dir / "weft_only", dir / "density_out");
  no_density.stages = "shell";
  no_density.exports = {"arcsim"};
  const PipelineResult refused = run_request(no_density);
  EXPECT_EQ(refused.status, PipelineStatus::invalid_input);
  EXPECT_NE(refused.problems.to_string().find("arcsim: the record has no areal_density_gsm"), std::string::npos)
      << refused.problems.to_string();
  EXPECT_FALSE(fs::exists(dir / "density_out" / "shell_fit.json"));
  r.exports = {"table"};
  r.report = false;
  EXPECT_TRUE(has(fields(run_request(r).problems), (dir / "out" / "exports" / "table").string()));
}

TEST(Plan, AWholePlanRunsTheLibrarysStagesWritesEachStagesFilesAndReportsEachStageInOrder) {
  ScratchDir dir("plan_all");
  FitRequest r = tiny(weft_only_record(dir.path()), dir / "out");
  r.report = true;
  std::vector<Stage> order;
  const PipelineResult result = run_request(r, [&order](const StageEvent& e) {
    EXPECT_EQ(e.fabric_id, "weft_only");
    if (order.empty() || order.back() != e.stage) order.push_back(e.stage);
  });
  ASSERT_TRUE(result.ok()) << result.message << result.write_error;
  EXPECT_EQ(order, (std::vector<Stage>{Stage::shell, Stage::yarn, Stage::report}));
  EXPECT_EQ(result.outputs.files, output_files(Stage::all));
  for (const auto& f : output_files(Stage::all)) EXPECT_TRUE(fs::exists(dir / "out" / f)) << f;
  for (const auto& f : report_files()) EXPECT_TRUE(fs::exists(dir / "out" / f)) << f;
  EXPECT_EQ(result.report_index, dir / "out" / "report" / "index.html");
  EXPECT_NE(result.outputs.text.find("results in " + (dir / "out").string()), std::string::npos) << result.outputs.text;

  // The same stages as the library call with the request's options, to the last bit.
  db::Problems problems;
  const PipelineOptions options = pipeline_options(r, problems);
  ASSERT_TRUE(problems.empty()) << problems.to_string();
  const auto load = db::load_fabric(r.fabric);
  ASSERT_TRUE(load.ok());
  PipelineOptions in_memory = options;
  in_memory.tile_cache = dir / "out";
  const PipelineResult direct = run_in_memory(*load.fabric, in_memory);
  ASSERT_TRUE(direct.yarn && result.yarn);
  EXPECT_EQ(direct.yarn->params.ks1, result.yarn->params.ks1);
  EXPECT_EQ(direct.yarn->params.kb, result.yarn->params.kb);
  EXPECT_EQ(direct.yarn->params.r1, result.yarn->params.r1);
  EXPECT_EQ(direct.shell->params.inplane.kxx, result.shell->params.inplane.kxx);

  // Run again into the same folder: refused, naming the files, unless overwriting.
  const PipelineResult again = run_request(r);
  EXPECT_EQ(again.status, PipelineStatus::invalid_input);
  EXPECT_TRUE(has(fields(again.problems), (dir / "out" / "yarn_fit.json").string()));
  EXPECT_TRUE(has(fields(again.problems), (dir / "out" / "report/index.html").string()));
}

TEST(Plan, AShellPlanWritesTheShellStagesFilesOnly) {
  ScratchDir dir("plan_shell");
  FitRequest r = tiny(weft_only_record(dir.path()), dir / "out");
  r.stages = "shell";
  int yarn_events = 0;
  const PipelineResult result = run_request(r, [&yarn_events](const StageEvent& e) { yarn_events += e.stage != Stage::shell; });
  ASSERT_TRUE(result.ok()) << result.message;
  EXPECT_EQ(yarn_events, 0);
  EXPECT_FALSE(result.yarn);
  EXPECT_EQ(result.outputs.files, output_files(Stage::shell));
  EXPECT_FALSE(fs::exists(dir / "out" / "yarn_fit.json"));
  EXPECT_FALSE(fs::exists(dir / "out" / "report"));
}

}  // namespace
}  // namespace yarnfit::pipeline
