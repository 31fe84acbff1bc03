// The bundled example is the project's own work: regenerating it reproduces the committed
// files byte for byte, and it validates and describes cleanly.
#include <nlohmann/json.hpp>

#include "tests/test_support.hpp"

namespace yarnfit::testing {
namespace {

const fs::path k_example = fs::path(YARNFIT_SOURCE_DIR) / "examples/fabrics/stockinette_demo";

TEST(Example, RegeneratingReproducesTheCommittedFiles) {
  ScratchDir dir("example");
  const std::string cmd = quoted(YARNFIT_MAKE_EXAMPLE) + " " + quoted(dir / "demo") + " >/dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  std::size_t compared = 0;
  for (const auto& e : fs::directory_iterator(k_example)) {
    const fs::path regenerated = dir / "demo" / e.path().filename();
    ASSERT_TRUE(fs::exists(regenerated)) << e.path();
    EXPECT_EQ(read_file(e.path()), read_file(regenerated)) << e.path();
    ++compared;
  }
  EXPECT_EQ(compared, 8u);  // fabric.yaml, tile.pyp, 3 stretch and 3 bending curves
  EXPECT_EQ(static_cast<std::size_t>(std::distance(fs::directory_iterator(dir / "demo"),
                                                   fs::directory_iterator{})), compared);
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
  // Plausible for a knit: tens of percent stretch at a few newtons.
  for (const auto& [dir, t] : j["stretch_tests"].items()) {
    EXPECT_GE(t["stretch"][1].get<double>(), 0.3) << dir;
    EXPECT_GE(t["force_N"][1].get<double>(), 2.0) << dir;
    EXPECT_LE(t["force_N"][1].get<double>(), 10.0) << dir;
  }
}

}  // namespace
}  // namespace yarnfit::testing
