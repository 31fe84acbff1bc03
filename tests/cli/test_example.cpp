// The bundled example database is the project's own work: regenerating it reproduces the
// committed files byte for byte, and it validates and describes cleanly.
#include <nlohmann/json.hpp>

#include <sstream>
#include <string>
#include <vector>

#include "tests/test_support.hpp"

namespace yarnfit::testing {
namespace {

const fs::path k_example = fs::path(YARNFIT_SOURCE_DIR) / "examples/fabrics/stockinette_demo";

TEST(Example, RegeneratingReproducesTheCommittedFiles) {
  ScratchDir dir("example");
  const std::string cmd = quoted(YARNFIT_MAKE_EXAMPLE) + " --all " + quoted(dir / "db") + " >/dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  const fs::path committed = k_example.parent_path();
  std::size_t compared = 0, fabrics = 0;
  for (const auto& fabric : fs::directory_iterator(committed)) {
    ++fabrics;
    const fs::path regenerated = dir / "db" / fabric.path().filename();
    ASSERT_TRUE(fs::is_directory(regenerated)) << fabric.path();
    for (const auto& e : fs::directory_iterator(fabric.path())) {
      ASSERT_TRUE(fs::exists(regenerated / e.path().filename())) << e.path();
      EXPECT_EQ(read_file(e.path()), read_file(regenerated / e.path().filename())) << e.path();
      ++compared;
    }
    EXPECT_EQ(std::distance(fs::directory_iterator(fabric.path()), fs::directory_iterator{}),
              std::distance(fs::directory_iterator(regenerated), fs::directory_iterator{}))
        << fabric.path();
  }
  EXPECT_EQ(fabrics, 3u);
  EXPECT_EQ(static_cast<std::size_t>(std::distance(fs::directory_iterator(dir / "db"), fs::directory_iterator{})), fabrics);
  // stockinette_demo and interlock_demo: fabric.yaml, tile.pyp, 3 stretch and 3 bending curves;
  // stockinette_light: fabric.yaml, tile.pyp, weft and warp stretch curves.
  EXPECT_EQ(compared, 8u + 8u + 4u);
}

TEST(Example, ValidatesAndDescribesItsTile) {
  auto r = run_cli("db validate " + quoted(k_example.parent_path()));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  r = run_cli("db show " + quoted(k_example) + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["stretch_tests"].size(), 3u);
  EXPECT_EQ(j["bending_tests"].size(), 3u);
  const auto& p = j["pattern"];
  ASSERT_FALSE(p.is_null());
  EXPECT_EQ(p["yarn_count"], 1);
  const double ratio = p["r_est_over_radius"].get<double>();
  EXPECT_GT(ratio, 0.5);
  EXPECT_LT(ratio, 3.0);
  // Plausible for a light knit: tens of percent stretch at tenths of a newton to a few newtons.
  for (const auto& [dir, t] : j["stretch_tests"].items()) {
    EXPECT_GE(t["stretch"][1].get<double>(), 0.25) << dir;
    EXPECT_GE(t["force_N"][1].get<double>(), 0.1) << dir;
    EXPECT_LE(t["force_N"][1].get<double>(), 10.0) << dir;
  }
}

// The curves are the shell model's own at the homogenised law under ground_truth (so a fit on the
// example can recover them): `shell sim` with those parameters and the example's swatch
// reproduces the last point of a stretch curve and of a pear-loop curve to the digits written.
TEST(Example, CurvesAreTheShellModelAtItsGroundTruth) {
  ScratchDir dir("example");
  const auto shown = run_cli("db show " + quoted(k_example) + " --json");
  ASSERT_EQ(shown.exit_code, 0) << shown.err;
  const auto truth = nlohmann::json::parse(shown.out)["ground_truth"];
  for (const char* k : {"kxx", "kxy", "kyy", "kss", "kn1", "kn2", "ktheta_weft", "ktheta_bias", "ktheta_warp"})
    ASSERT_TRUE(truth.contains(k)) << k;
  write_file(dir / "truth.json", nlohmann::json{{"params", truth}}.dump());
  const auto last_row = [](const std::string& csv) {
    const std::string line = csv.substr(csv.rfind('\n', csv.size() - 2) + 1);
    std::vector<double> row;
    std::istringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) row.push_back(std::stod(cell));
    return row;
  };
  const auto stretch = last_row(read_file(k_example / "stretch_warp.csv"));  // read at gauge marks
  auto r = run_cli("shell sim --params " + quoted(dir / "truth.json") + " --direction warp --stretch " +
                   std::to_string(stretch[0]) + " --gauge-length-mm 80 --gauge-width-mm 40");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out)["samples"][0];
  EXPECT_NEAR(j["force_N"].get<double>(), stretch[1], 1e-5 * stretch[1]);
  EXPECT_NEAR(j["compression"].get<double>(), stretch[2], 1e-5 * stretch[2]);
  const auto bend = last_row(read_file(k_example / "bend_weft.csv"));
  r = run_cli("shell sim --scene pear --params " + quoted(dir / "truth.json") + " --direction weft --distance " +
              std::to_string(bend[0]));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  j = nlohmann::json::parse(r.out)["samples"][0];
  EXPECT_NEAR(j["aspect_ratio"].get<double>(), bend[1], 1e-5 * bend[1]);
}

}  // namespace
}  // namespace yarnfit::testing
