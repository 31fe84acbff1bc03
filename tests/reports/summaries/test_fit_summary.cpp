// summary.txt and yarn_summary.txt (reports/summaries/fit_summary.hpp): what each holds and in
// which order.
#include <gtest/gtest.h>

#include <string>

#include "tests/test_support.hpp"

#include "reports/summaries/fit_summary.hpp"

namespace yarnfit::reports {
namespace {

using nlohmann::json;

using namespace yarnfit::testing;

const results::YarnFitFile k_yarn = results::yarn_fit_file_from_json(
    {{"ok", true}, {"params", json::object()}, {"settings", {{"swarm", false}}}, {"timing_s", {{"total", 2.0}}}});

TEST(FitSummary, FabricThenShellThenYarnThenTheTimePerStage) {
  const json shell = {{"converged", true}, {"errors", {{"stretch_force_pct", 1.0}}}, {"params", {{"kxx", 1.0}}}};
  const std::string s = fit_summary("demo", "fabrics/demo", results::shell_fit_file_from_json(shell), k_yarn, {1.0, 2.0, 3.5});
  EXPECT_EQ(s.rfind("fabric demo (fabrics/demo)\n\nshell fit: converged\n", 0), 0u) << s;
  EXPECT_LT(s.find("shell fit:"), s.find("yarn fit: ok"));
  EXPECT_TRUE(contains(s, "\ntime per stage: shell 1 s, yarn 2 s, total 3.5 s\n")) << s;
  EXPECT_EQ(yarn_summary_file("demo", "t.csv", k_yarn).rfind("fabric demo, targets t.csv\nyarn fit: ok\n", 0), 0u);
}

}  // namespace
}  // namespace yarnfit::reports
