// yarnfit synth shell → yarnfit shell fit: the command line round trip and the stable output
// names of SPEC §5 (shell_fit.json, uniform_targets.csv).
#include <nlohmann/json.hpp>

#include "tests/test_support.hpp"

namespace yarnfit::testing {
namespace {

TEST(ShellCli, SynthThenFitWritesTheSpecifiedOutputs) {
  ScratchDir dir("shellcli");
  auto r = run_cli("synth shell --out " + quoted(dir / "syn") + " --weft 0.6 --bias 0 --warp 0.3 --refine 0");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Never replaces a record without --force.
  r = run_cli("synth shell --out " + quoted(dir / "syn"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("exists; pass --force"), std::string::npos) << r.err;

  r = run_cli("shell fit " + quoted(dir / "syn") + " --out " + quoted(dir / "fit") + " --full-range");
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const auto j = nlohmann::json::parse(read_file(dir / "fit" / "shell_fit.json"));
  for (const char* k : {"kxx", "kxy", "kyy", "kss", "kn1", "kn2", "ktheta_weft", "ktheta_bias", "ktheta_warp"})
    EXPECT_TRUE(j["params"].contains(k)) << k;
  for (const char* k : {"stretch_force_pct", "compression_pct", "bending_pct"}) EXPECT_TRUE(j["errors"].contains(k)) << k;
  EXPECT_TRUE(j.contains("identified") && j.contains("effects") && j.contains("timing_s"));
  // kss is held at its prior here (no bias test), so kxx absorbs some of the difference.
  EXPECT_NEAR(j["params"]["kxx"].get<double>(), 120.0, 12.0);
  // No bias test: kss is held and said so; no bending test: k_θ not fitted.
  const std::string not_identified = j["not_identified"].dump();
  EXPECT_NE(not_identified.find("kss: no bias test"), std::string::npos) << not_identified;
  EXPECT_NE(not_identified.find("no bending test"), std::string::npos) << not_identified;
  EXPECT_TRUE(j["params"]["ktheta_weft"].is_null());
  const std::string csv = read_file(dir / "fit" / "uniform_targets.csv");
  EXPECT_EQ(csv.rfind("direction,kind,stretch,compression,stress_s_N_per_m,curvature_per_m,stress_kappa_N\n", 0), 0u);
  EXPECT_NE(csv.find("warp,stretch,0.3,"), std::string::npos);
}

TEST(ShellCli, InvalidFabricIsInvalidInput) {
  ScratchDir dir("shellcli");
  write_file(dir / "bad" / "fabric.yaml", "id: x\n");
  const auto r = run_cli("shell fit " + quoted(dir / "bad") + " --out " + quoted(dir / "out"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("family: missing required key"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

}  // namespace
}  // namespace yarnfit::testing
