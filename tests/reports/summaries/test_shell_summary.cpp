// Text reports of a shell fit from its shell_fit.json alone, read as results::ShellFitFile (reports/summaries/shell_summary.hpp).
#include <gtest/gtest.h>

#include <string>

#include "tests/test_support.hpp"

#include "reports/summaries/shell_summary.hpp"

namespace yarnfit::reports {
namespace {

using nlohmann::json;

using namespace yarnfit::testing;

// The summaries read the type; these files are of schema version 1 (no per-direction errors
// stored), so reading them computes the per-direction figures from the curves.
results::ShellFitFile file(const json& j) { return results::shell_fit_file_from_json(j); }

json converged_fit() {
  return json{
      {"fabric", "demo"},
      {"converged", true},
      {"iterations", 12},
      {"restarts", 1},
      {"chosen_start", 1},
      {"starts", json::array({json{{"name", "balanced"}}, json{{"name", "mostly kxy"}}})},
      {"directions", json::array({json{{"direction", "weft"},
                                       {"fitted_max_stretch", 0.5},
                                       {"measured_max_stretch", 0.8},
                                       {"stretch", {0.25, 0.5}},
                                       {"measured_force_N", {1.0, 2.0}},
                                       {"simulated_force_N", {1.1, 2.2}},
                                       {"measured_compression", {0.1, 0.2}},
                                       {"simulated_compression", {0.1, 0.2}}}})},
      {"errors", {{"stretch_force_pct", 10.0}, {"compression_pct", 0.0}, {"bending_pct", 2.5}}},
      {"params", {{"kxx", 60.0}, {"kyy", 250.0}, {"ktheta_weft", nullptr}}},
      {"weakly_identified", {"kn2"}},
      {"inplane",
       {{"timing_s", 1.25}, {"not_identified", {"kss: no bias test"}}, {"at_bounds", {"kn1"}}, {"compression_measured", true}}},
      {"bending",
       {{"converged", true}, {"timing_s", 3.5}, {"at_bounds", {"ktheta_weft"}}, {"fallback_starts", {"weft test: start search failed"}}}},
      {"timing_s", 4.75}};
}

TEST(ShellSummary, ErrorsPerDirectionAndForAllWithTheParameters) {
  const std::string s = shell_summary(file(converged_fit()), 5.0);
  EXPECT_EQ(s.rfind("shell fit: converged\n", 0), 0u) << s;
  // The per-direction figures are the shell metric of each curve: 0.3 / 3 and 0.
  EXPECT_TRUE(contains(s, "    weft              10 %          0 %\n")) << s;
  EXPECT_TRUE(contains(s, "    all               10 %          0 %   bending (aspect ratio) 2.5 %\n")) << s;
  EXPECT_TRUE(contains(s, "kxx = 60 kyy = 250; not fitted: ktheta_weft\n")) << s;
  EXPECT_TRUE(contains(s, "  time: 5 s (fits 4.75 s,")) << s;
  EXPECT_FALSE(contains(s, "no errors")) << s;
}

TEST(ShellSummary, AFailedFitShowsNoFiguresAndSaysWhy) {
  json r = converged_fit();
  r["converged"] = false;
  r["errors"] = {{"stretch_force_pct", nullptr}, {"compression_pct", nullptr}, {"bending_pct", nullptr}};
  r["errors_reason"] = "final evaluation failed: a scene did not reach equilibrium";
  r["inplane"]["errors_reason"] = r["errors_reason"];
  r["directions"][0]["simulated_force_N"] = json::array();
  r["directions"][0]["simulated_compression"] = json::array();
  const std::string s = shell_summary(file(r), 1.0);
  EXPECT_TRUE(contains(s, "shell fit: NOT converged")) << s;
  EXPECT_TRUE(contains(s, "    weft                 -            -\n")) << s;
  EXPECT_TRUE(contains(s, "bending (aspect ratio) not fitted")) << s;
  EXPECT_TRUE(contains(s, "no errors where the fit failed: final evaluation failed")) << s;
  const std::string report = shell_fit_report(file(r));
  EXPECT_TRUE(contains(report, "  force error -, compression error -\n")) << report;
  EXPECT_TRUE(contains(report, "  no errors: final evaluation failed: a scene did not reach equilibrium\n")) << report;
}

TEST(ShellSummary, TheShellFitCommandsReport) {
  const std::string s = shell_fit_report(file(converged_fit()));
  EXPECT_EQ(s.rfind("shell fit of demo: converged after 12 iterations, 1.25 s\n", 0), 0u) << s;
  EXPECT_TRUE(contains(s, "  force error 10 %, compression error 0 %\n")) << s;
  EXPECT_TRUE(contains(s, "  best of 2 data-based starts: mostly kxy, 1 restart(s) after stalls\n")) << s;
  EXPECT_TRUE(contains(s, "  weft: fitted up to s = 0.5 of 0.8 measured\n")) << s;
  EXPECT_TRUE(contains(s, "  not identified: kss: no bias test\n")) << s;
  EXPECT_TRUE(contains(s, "  weakly identified: kn2\n")) << s;
  EXPECT_TRUE(contains(s, "  WARNING: kn1 ended on a search bound\n")) << s;
  EXPECT_TRUE(contains(s, "  bending: converged, aspect-ratio error 2.5 %, 3.5 s\n")) << s;
  EXPECT_TRUE(contains(s, "  WARNING: weft test: start search failed\n")) << s;
  EXPECT_TRUE(contains(s, "  WARNING: ktheta_weft ended on a search bound\n")) << s;
  // Without compression data the report says so rather than printing a figure.
  json r = converged_fit();
  r["inplane"]["compression_measured"] = false;
  r["errors"]["compression_pct"] = nullptr;
  EXPECT_TRUE(contains(shell_fit_report(file(r)), "compression error not measured"));
}

TEST(ShellSummary, CurvesCsvLeavesMissingValuesEmpty) {
  json r = converged_fit();
  r["directions"][0]["simulated_force_N"] = json::array();
  EXPECT_EQ(shell_curves_csv(file(r)),
            "direction,stretch,measured_force_N,simulated_force_N,measured_compression,simulated_compression\n"
            "weft,0.25,1,,0.1,0.1\n"
            "weft,0.5,2,,0.2,0.2\n");
}

}  // namespace
}  // namespace yarnfit::reports
