// The shell stage as one call (shell_fit/fit/shell_fit.hpp): options checked up front with
// every problem named, the sequence in-plane → bending → targets, shell_fit.json, and honest
// failures (null errors with the reason, no stale curves) when the final evaluation fails.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "shell_fit/fit/shell_fit.hpp"
#include "numerics/util/error.hpp"
#include "tests/example_fabric.hpp"
#include "tests/test_support.hpp"

namespace yarnfit::shell {
namespace {

using namespace yarnfit::testing;

TEST(ShellFitOptions, EveryInvalidFieldIsNamedBeforeAnyWork) {
  ShellFitOptions o;
  EXPECT_TRUE(o.problems().empty());
  o.mesh = -1e-3;
  o.refinements = 9;
  o.threads = 0;
  o.max_iterations = 0;
  const auto problems = o.problems();
  ASSERT_EQ(problems.size(), 4u) << problems.to_string();
  std::vector<std::string> fields;
  for (const auto& p : problems.items()) fields.push_back(p.field);
  EXPECT_EQ(fields, (std::vector<std::string>{"mesh", "refinements", "threads", "max_iterations"}));
  EXPECT_EQ(problems.items()[1].to_string(), "refinements: must be 0 to 4 (got 9)");
  try {
    (void)fit_shell(weft_only_example(), o);
    FAIL() << "invalid options ran";
  } catch (const yarnfit::Error& e) {
    for (const auto& f : fields) EXPECT_NE(std::string(e.what()).find(f + ":"), std::string::npos) << e.what();
  }
}

TEST(ShellFit, InplaneThenTargetsWithoutBendingTestsAndTheJsonSaysSo) {
  const db::Fabric fabric = weft_only_example();
  ShellFitOptions o;
  o.threads = 2;
  int events = 0;
  o.progress = [&events](const numerics::Progress& p) {
    ++events;
    EXPECT_EQ(p.best_label, "rms error");
  };
  const ShellFitResult r = fit_shell(fabric, o);
  ASSERT_TRUE(r.converged()) << r.failure();
  EXPECT_TRUE(r.failure().empty());
  EXPECT_GT(events, 0);
  EXPECT_FALSE(r.has_bending_tests);
  EXPECT_FALSE(r.bending);
  EXPECT_EQ(r.effects, (std::map<std::string, std::vector<std::string>>{{"stretch", {"membrane"}}}));
  // The targets are those of the fitted model, as the file stores them.
  EXPECT_EQ(db::uniform_targets_csv(r.targets), db::uniform_targets_csv(generate_uniform_targets(r.params, r.ranges)));
  ASSERT_EQ(r.targets.size(), 1u);
  EXPECT_EQ(r.targets[0].direction, db::Direction::weft);
  EXPECT_TRUE(r.targets[0].bending.empty());

  const nlohmann::json j = results::to_json(to_file(r));
  EXPECT_EQ(j["fabric"], "stockinette_demo");
  EXPECT_TRUE(j["params"]["ktheta_weft"].is_null());
  EXPECT_TRUE(j["errors"]["bending_pct"].is_null());
  EXPECT_TRUE(j["errors"]["stretch_force_pct"].is_number());
  EXPECT_EQ(j["errors"]["stretch_force_pct"].get<double>(), r.inplane.stretch_force_pct);
  EXPECT_TRUE(j["errors_reason"].is_null());
  EXPECT_NE(j["not_identified"].dump().find("no bending test (not fitted)"), std::string::npos);
  EXPECT_EQ(j["effects"], (nlohmann::json{{"stretch", {"membrane"}}}));
  EXPECT_EQ(j["inplane"]["timing_s"].get<double>(), r.inplane.seconds);
  EXPECT_FALSE(j.contains("bending"));
}

// A final evaluation that fails (here every scene gets one Newton iteration per target, so
// none reaches equilibrium: the real path of a fit whose last point does not simulate).
TEST(ShellFit, AFailedFinalEvaluationHasNullErrorsAndTheReasonNotStaleCurves) {
  InplaneFitOptions o;
  o.newton_budget_per_target = 1;
  ShellFitResult r;
  r.fabric_id = "x";
  r.inplane = fit_inplane(weft_only_example(), o);
  EXPECT_FALSE(r.inplane.converged);
  EXPECT_TRUE(std::isnan(r.inplane.stretch_force_pct));
  EXPECT_TRUE(std::isnan(r.inplane.compression_pct));
  EXPECT_NE(r.inplane.errors_reason.find("final evaluation failed"), std::string::npos) << r.inplane.errors_reason;
  ASSERT_FALSE(r.inplane.directions.empty());
  for (const auto& d : r.inplane.directions) {
    EXPECT_TRUE(d.simulated_force.empty());
    EXPECT_TRUE(d.simulated_compression.empty());
  }
  const nlohmann::json j = results::to_json(to_file(r));
  EXPECT_TRUE(j["errors"]["stretch_force_pct"].is_null()) << j["errors"];
  EXPECT_TRUE(j["errors"]["compression_pct"].is_null()) << j["errors"];
  ASSERT_TRUE(j["errors_reason"].is_string());
  EXPECT_NE(j["errors_reason"].get<std::string>().find("final evaluation failed"), std::string::npos);
  EXPECT_FALSE(j["converged"].get<bool>());
  EXPECT_TRUE(j["directions"][0]["simulated_force_N"].empty());
}

TEST(ShellFit, BendingFailureAndFallbackStartsReachTheJson) {
  ShellFitResult r;
  r.has_bending_tests = true;
  r.inplane.converged = true;
  r.inplane.stretch_force_pct = 1.0;
  BendingFitResult b;
  b.message = "final evaluation failed: a pear loop did not reach equilibrium";
  b.errors_reason = b.message;
  b.fallback_starts = {"weft test (ktheta_weft): start search failed"};
  r.bending = b;
  const nlohmann::json j = results::to_json(to_file(r));
  EXPECT_TRUE(j["errors"]["bending_pct"].is_null());
  EXPECT_EQ(j["errors_reason"], "bending: " + b.message);
  EXPECT_EQ(j["bending"]["errors_reason"], b.message);
  EXPECT_EQ(j["bending"]["fallback_starts"], nlohmann::json::array({b.fallback_starts[0]}));
  EXPECT_EQ(r.failure(), "bending fit did not converge: " + b.message);
  // Bending tests but no converged in-plane fit: nothing fitted, and the reason says why.
  r.bending.reset();
  r.inplane.converged = false;
  EXPECT_NE(results::to_json(to_file(r))["errors_reason"].get<std::string>().find("the in-plane fit did not converge"), std::string::npos);
}

TEST(ReadShellParams, ValuesOfAShellFitNullWhereNotFittedAndProblemsNamed) {
  yarnfit::testing::ScratchDir dir("shell_params");
  yarnfit::testing::write_file(dir / "fit.json", R"({"params": {"kxx": 80, "kyy": 200, "ktheta_weft": null}})");
  db::Problems problems;
  const auto v = read_shell_params(dir / "fit.json", problems);
  EXPECT_TRUE(problems.empty()) << problems.to_string();
  EXPECT_EQ(v[0], 80.0);
  EXPECT_EQ(v[2], 200.0);
  EXPECT_FALSE(v[1]);
  EXPECT_FALSE(v[6]);
  yarnfit::testing::write_file(dir / "bad.json", R"({"params": {"kxx": "stiff"}})");
  (void)read_shell_params(dir / "bad.json", problems);
  EXPECT_NE(problems.to_string().find((dir / "bad.json").string() + ": params.kxx: expected a number"), std::string::npos)
      << problems.to_string();
  yarnfit::testing::write_file(dir / "broken.json", "{not json");
  (void)read_shell_params(dir / "broken.json", problems);
  EXPECT_NE(problems.to_string().find("broken.json: file: not a JSON object"), std::string::npos) << problems.to_string();
}

}  // namespace
}  // namespace yarnfit::shell
