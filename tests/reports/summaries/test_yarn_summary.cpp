// Text reports of a yarn fit from its yarn_fit.json alone (reports/summaries/yarn_summary.hpp):
// the tables keep the parameter order of the fit's space although JSON sorts its keys.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "tests/test_support.hpp"

#include "reports/summaries/yarn_summary.hpp"

namespace yarnfit::reports {
namespace {

using nlohmann::json;

using namespace yarnfit::testing;

json yarn_fit() {
  json profile_entry = {{"value", 1.0}, {"objective_lower", 2.0}, {"objective_upper", 3.0},
                        {"range_factor", 1.1},  {"range_alone_factor", 1.05}, {"free", false}, {"free_alone", false}};
  json free_entry = profile_entry;
  free_entry["range_factor"] = nullptr;  // unbounded: written null with free
  free_entry["free"] = true;
  free_entry["range_alone_factor"] = nullptr;  // a failed side: null without free_alone
  free_entry["objective_lower"] = nullptr;     // g was +inf
  json downhill = profile_entry;
  downhill["objective_upper"] = 0.5;
  downhill["range_factor"] = 500.0;
  return json{
      {"ok", true},
      {"fabric", "demo"},
      {"targets", "t.csv"},
      {"settings",
       {{"swarm", true}, {"particles", 16}, {"iterations", 6}, {"swarm_samples", 5}, {"local_method", "implicit-filtering"},
        {"local_evaluations", 40}, {"local_samples", 12}, {"seed", 1}, {"linear_stretch", false}, {"rest_shape", true},
        {"local_compression_nodes", 0}}},
      {"curves", json::array({json{{"direction", "weft"},
                                   {"stretch", {0.0, 0.1}},
                                   {"target_S_N_per_m", {0.0, 5.0}},
                                   {"simulated_S_N_per_m", {0.0, 4.0}},
                                   {"target_compression", {0.0, 0.05}},
                                   {"simulated_compression", {0.0}},
                                   {"weight", {1.0, 1.0}}},
                              json{{"direction", "warp"},
                                   {"stretch", {0.0}},
                                   {"target_S_N_per_m", {0.0}},
                                   {"simulated_S_N_per_m", {0.0}},
                                   {"target_compression", {0.0}},
                                   {"simulated_compression", {0.0}},
                                   {"weight", {1.0}}}})},
      {"errors_by_direction",
       {{"weft", {{"stress_comfort_pct", 10.0}, {"stress_full_pct", 20.0}, {"compression_pct", 5.0}, {"bending_pct", 7.0}}},
        {"warp", {{"stress_comfort_pct", 1.0}, {"stress_full_pct", 2.0}, {"compression_pct", 3.0}}}}},
      {"params", {{"ks1", 1.2592}, {"eps_s", 0.003832}, {"kb", 1.13e-8}, {"R1", 0.00039604}, {"kc1", 11112.0},
                  {"ks2", 120.0}, {"kc2", 4.545e8}, {"R2", 6.6006e-5}}},
      {"bounds", {{"ks1", {{"lower", 0.12}, {"upper", 120.0}, {"log", true}}},
                  {"eps_s", {{"lower", 1e-4}, {"upper", 0.15}, {"log", true}}},
                  {"kb", {{"lower", 2.091e-9}, {"upper", 2.091e-5}, {"log", true}}},
                  {"R1", {{"lower", 0.000132}, {"upper", 0.000396}, {"log", false}}},
                  {"kc1", {{"lower", 4545.0}, {"upper", 4.545e7}, {"log", true}}}}},
      {"on_bound", {"R1"}},
      {"identifiability",
       {{"computed", true}, {"step", 0.1}, {"objective", 1.31},
        {"parameters", {{"ks1", free_entry}, {"eps_s", profile_entry}, {"kb", downhill}, {"R1", profile_entry},
                        {"kc1", profile_entry}}}}},
      {"evaluations", 144},
      {"timing_s", {{"swarm", 35.2}, {"local", 16.8}, {"profile", 3.81}, {"total", 56.3}}},
      {"swarm", {{"history", {json{{"iteration", 1}}}}, {"report", "swarm completed"}, {"stopped_at_cutoff", 16}}},
      {"local", {{"report", "implicit filtering converged"}}}};
}

// The summary of a yarn_fit.json as the file holds it (read through its type).
std::string summary_of(const json& file) { return yarn_summary(results::yarn_fit_file_from_json(file)); }

TEST(YarnSummary, ErrorsPerDirectionInTheFitsOrder) {
  const std::string s = summary_of(yarn_fit());
  EXPECT_EQ(s.rfind("yarn fit: ok\n", 0), 0u) << s;
  EXPECT_TRUE(contains(s, "  settings: swarm 16 particles x 6 iterations, 5 samples per direction; local step implicit-filtering, "
                     "at most 40 evaluations, 12 samples per direction; seed 1; c* at every sample\n"))
      << s;
  json generated = yarn_fit();
  generated["settings"]["rest_period"] = true;
  EXPECT_TRUE(contains(summary_of(generated), "seed 1; period relaxed per candidate; c* at every sample\n"))
      << summary_of(generated);
  // weft before warp (the curves' order), warp without a bending figure.
  const auto weft = s.find("    weft                 10 %         20 %          5 %       7 %\n");
  const auto warp = s.find("    warp                  1 %          2 %          3 %         -\n");
  ASSERT_NE(weft, std::string::npos) << s;
  ASSERT_NE(warp, std::string::npos) << s;
  EXPECT_LT(weft, warp);
}

TEST(YarnSummary, ParametersWithBoundsInTheSpacesOrderAndTheFixedOnes) {
  const std::string s = summary_of(yarn_fit());
  const auto ks1 = s.find("    ks1    =       1.2592   in [0.12, 120] log\n");
  const auto r1 = s.find("    R1     =   0.00039604   in [0.000132, 0.000396]   ON A BOUND\n");
  const auto kc1 = s.find("    kc1    =        11112   in [4545, 4.545e+07] log\n");
  ASSERT_NE(ks1, std::string::npos) << s;
  ASSERT_NE(r1, std::string::npos) << s;
  ASSERT_NE(kc1, std::string::npos) << s;
  EXPECT_LT(ks1, r1);
  EXPECT_LT(r1, kc1);
  EXPECT_TRUE(contains(s, "    ks2    =          120   fixed\n")) << s;
  EXPECT_FALSE(contains(s, "    ks1    =       1.2592   fixed")) << s;  // fitted here
  // With linear stretch ks1 and eps_s are fixed instead.
  json linear = yarn_fit();
  linear["bounds"].erase("ks1");
  linear["bounds"].erase("eps_s");
  EXPECT_TRUE(contains(summary_of(linear), "    ks1    =       1.2592   fixed\n"));
}

TEST(YarnSummary, IdentifiabilityRangesFreeFailedAndDownhill) {
  const std::string s = summary_of(yarn_fit());
  EXPECT_TRUE(contains(s, "  identifiability (g = 1.31 at the fit;")) << s;
  EXPECT_TRUE(contains(s, "    ks1        inf / 3                         unbounded               -\n")) << s;
  EXPECT_TRUE(contains(s, "    eps_s      2 / 3                              ±10 %           ±5 %\n")) << s;
  EXPECT_TRUE(contains(s, "    kb         2 / 0.5                       ÷/× > 100")) << s;
  EXPECT_TRUE(contains(s, "g falls by more than 1 % with kb moved")) << s;
  EXPECT_TRUE(contains(s, "  evaluations: 144\n")) << s;
  EXPECT_TRUE(contains(s, "  time: global 35.2 s, local 16.8 s, profile 3.81 s, total 56.3 s\n")) << s;
  EXPECT_TRUE(contains(s, "  swarm: swarm completed; 16 candidates stopped once they could not beat their particle's best\n"))
      << s;
  EXPECT_TRUE(contains(s, "  local: implicit filtering converged\n")) << s;
}

TEST(YarnSummary, AFailedFitHasNoErrorRowsAndSaysWhy) {
  json r = yarn_fit();
  r["ok"] = false;
  r["message"] = "the best parameters failed on re-evaluation: rest shape";
  r["curves"] = json::array();
  r["errors_by_direction"] = json::object();
  r["errors_reason"] = r["message"];
  r.erase("identifiability");
  const std::string s = summary_of(r);
  EXPECT_EQ(s.rfind("yarn fit: FAILED: the best parameters failed on re-evaluation: rest shape\n", 0), 0u) << s;
  EXPECT_FALSE(contains(s, "    weft")) << s;
  EXPECT_TRUE(contains(s, "  no errors: the best parameters failed")) << s;
  EXPECT_FALSE(contains(s, "identifiability")) << s;
  EXPECT_FALSE(contains(s, ", profile ")) << s;
}

TEST(YarnSummary, CurvesCsvWritesEverySampleAndNanWhereAValueIsMissing) {
  EXPECT_EQ(yarn_curves_csv(results::yarn_fit_file_from_json(yarn_fit())),
            "direction,sample,stretch,target_S_N_per_m,simulated_S_N_per_m,target_compression,simulated_compression,"
            "weight\n"
            "weft,0,0,0,0,0,0,1\n"
            "weft,1,0.1,5,4,0.05,nan,1\n"
            "warp,0,0,0,0,0,0,1\n");
}

}  // namespace
}  // namespace yarnfit::reports
