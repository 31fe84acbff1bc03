// The bundled example database is the project's own work: regenerating it reproduces the
// committed files byte for byte (the records made from known yarn models by make_example, and
// the one real knit converted from ../shared by scripts/build_acrylic_records.py), and it
// validates and describes cleanly.
#include <nlohmann/json.hpp>

#include <sstream>
#include <string>
#include <vector>

#include "tests/test_support.hpp"

namespace yarnfit::testing {
namespace {

const fs::path k_example = fs::path(YARNFIT_SOURCE_DIR) / "examples/fabrics/stockinette_demo";
// The real knit SPEC section 6 allows the bundled example: converted, not made by make_example.
const std::string k_real_knit = "acrylic_stockinette";

void expect_same_folder(const fs::path& committed, const fs::path& regenerated, std::size_t& compared) {
  ASSERT_TRUE(fs::is_directory(regenerated)) << committed;
  for (const auto& e : fs::directory_iterator(committed)) {
    ASSERT_TRUE(fs::exists(regenerated / e.path().filename())) << e.path();
    EXPECT_EQ(read_file(e.path()), read_file(regenerated / e.path().filename())) << e.path();
    ++compared;
  }
  EXPECT_EQ(std::distance(fs::directory_iterator(committed), fs::directory_iterator{}),
            std::distance(fs::directory_iterator(regenerated), fs::directory_iterator{}))
      << committed;
}

TEST(Example, RegeneratingReproducesTheCommittedFiles) {
  ScratchDir dir("example");
  const std::string cmd = quoted(YARNFIT_MAKE_EXAMPLE) + " --all " + quoted(dir / "db") + " >/dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  const fs::path committed = k_example.parent_path();
  std::size_t compared = 0, fabrics = 0;
  for (const auto& fabric : fs::directory_iterator(committed)) {
    if (fabric.path().filename() == k_real_knit) continue;
    ++fabrics;
    expect_same_folder(fabric.path(), dir / "db" / fabric.path().filename(), compared);
  }
  EXPECT_EQ(fabrics, 3u);
  EXPECT_EQ(static_cast<std::size_t>(std::distance(fs::directory_iterator(dir / "db"), fs::directory_iterator{})), fabrics);
  // stockinette_demo and interlock_demo: fabric.yaml, tile.pyp, 3 stretch and 3 bending curves;
  // stockinette_light: fabric.yaml, tile.pyp, weft and warp stretch curves.
  EXPECT_EQ(compared, 8u + 8u + 4u);
}

// The real knit is the converter's output from the stitch-by-stitch data in ../shared, with
// its attribution and the source's licence beside it; nothing else is in its folder.
TEST(Example, TheRealKnitIsTheConvertedStitchByStitchStockinette) {
  YARNFIT_REQUIRE_SHARED(shared_dir() / "data/measured/stitch-by-stitch/acrylic");
  ScratchDir dir("example");
  const std::string cmd = "python3 " + quoted(fs::path(YARNFIT_SOURCE_DIR) / "scripts/build_acrylic_records.py") +
                          " " + quoted(dir / "db") + " --shared " + quoted(shared_dir()) +
                          " --only stockinette --generated-tiles --example >/dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::size_t compared = 0;
  const fs::path committed = k_example.parent_path() / k_real_knit;
  expect_same_folder(committed, dir / "db" / k_real_knit, compared);
  EXPECT_EQ(compared, 4u);  // fabric.yaml, weft and warp curves, the licence
  const std::string record = read_file(committed / "fabric.yaml");
  EXPECT_TRUE(contains(record, "github.com/sabetta/stitch-by-stitch (commit 0ed27f3), MIT licence")) << record;
  EXPECT_TRUE(contains(read_file(committed / "LICENSE-stitch-by-stitch.txt"), "Copyright (c) 2023 sabetta"));
  EXPECT_FALSE(contains(record, "ground_truth")) << "a real knit has no truth";
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
