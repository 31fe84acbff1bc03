// The yarnfit command line: help, exit codes, JSON output (SPEC §5).
#include <nlohmann/json.hpp>

#include "tests/fabrics_db/fabric_fixture.hpp"

namespace yarnfit::testing {
namespace {

TEST(Cli, HelpOnEveryCommandExitsZero) {
  for (const char* cmd : {"--help", "db --help", "db validate --help", "db list --help",
                          "db show --help", "db import-tensile --help", "shell --help", "shell fit --help",
                          "shell sim --help", "synth --help", "synth shell --help", "yarn --help",
                          "yarn sim --help", "yarn curve --help"}) {
    const auto r = run_cli(cmd);
    EXPECT_EQ(r.exit_code, 0) << cmd << "\n" << r.err;
    EXPECT_NE(r.out.find("Usage") == std::string::npos ? r.out.find("usage") : 0, std::string::npos) << r.out;
  }
  EXPECT_NE(run_cli("--help").out.find("Exit codes: 0 success, 2 invalid input, 1 internal failure"),
            std::string::npos);
  const auto v = run_cli("--version");
  EXPECT_EQ(v.exit_code, 0);
  EXPECT_EQ(v.out.rfind("yarnfit ", 0), 0u) << v.out;
}

TEST(Cli, BadCommandLinesAreInvalidInput) {
  EXPECT_EQ(run_cli("").exit_code, 2);
  EXPECT_EQ(run_cli("frobnicate").exit_code, 2);
  EXPECT_EQ(run_cli("db").exit_code, 2);
  EXPECT_EQ(run_cli("db validate").exit_code, 2);
  EXPECT_EQ(run_cli("db list /tmp --colour").exit_code, 2);
}

TEST(Cli, ShowPrintsTextAndJson) {
  ScratchDir dir("show");
  write_base_fabric(dir / "T1");
  auto r = run_cli("db show " + quoted(dir / "T1"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* expected : {"fabric T1 (family test-family)", "polyester", "90 % of mass",
                               "weft  4 points", "stretch 0 to 0.3, force 0 to 2.4 N",
                               "gauge marks 59.4 mm along, 31.5 mm across", "bending tests:",
                               "pattern: none"})
    EXPECT_NE(r.out.find(expected), std::string::npos) << expected << "\n" << r.out;
  r = run_cli("db show " + quoted(dir / "T1") + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["id"], "T1");
  EXPECT_DOUBLE_EQ(j["swatch"]["width_m"].get<double>(), 0.06);
}

TEST(Cli, ShowOnBrokenOrMissingFabricIsInvalidInput) {
  ScratchDir dir("show");
  write_base_fabric(dir / "T1");
  replace_in_file(dir / "T1" / "stretch_weft.csv", "0.1,0.5,", "0.1,-0.5,");
  auto r = run_cli("db show " + quoted(dir / "T1"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("stretch_weft.csv:3: force_N: negative force"), std::string::npos) << r.err;
  r = run_cli("db show " + quoted(dir.path()));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("fabric.yaml: file: no fabric here"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace yarnfit::testing
