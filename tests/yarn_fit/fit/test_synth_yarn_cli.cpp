// `yarnfit synth yarn` writes targets the reader accepts and a fabric record that validates.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "fabrics_db/targets/uniform_targets.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"
#include "tests/test_support.hpp"
#include "yarn_fit/model/yarn_params.hpp"

namespace yarnfit::yarn {
namespace {

using testing::quoted;
using testing::run_cli;

TEST(SynthYarnCli, WritesTargetsAndAValidRecord) {
  const auto pattern = testing::shared_stockinette();
  YARNFIT_REQUIRE_SHARED(pattern);
  testing::ScratchDir dir("synth_yarn");
  db::Problems problems;
  const auto tile = db::read_pyp(pattern, problems);
  ASSERT_TRUE(tile);
  const yarn::YarnParams p = yarn::default_params({400.0, db::compute_tile_facts(*tile).r_est});
  testing::write_file(dir / "y.yaml", yarn::to_json(p).dump(2) + "\n");
  const auto out = dir / "out";
  const auto r = run_cli("synth yarn --pattern " + quoted(pattern) + " --params " + quoted(dir / "y.yaml") +
                         " --out " + quoted(out) + " --max-stretch 0.1 --directions weft --points 3");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto targets = db::read_uniform_targets(out / "uniform_targets.csv");
  ASSERT_EQ(targets.size(), 1u);
  ASSERT_EQ(targets[0].stretch.size(), 3u);
  EXPECT_DOUBLE_EQ(targets[0].stretch[2].stretch, 0.1);
  EXPECT_GT(targets[0].stretch[2].stress, 0.0);

  const auto v = run_cli("db validate " + quoted(out / "fabric"));
  EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
  const std::string yaml = testing::read_file(out / "fabric" / "fabric.yaml");
  EXPECT_NE(yaml.find("ground_truth"), std::string::npos);

  // A second run refuses to overwrite; bad input exits 2 naming the option.
  const auto again = run_cli("synth yarn --pattern " + quoted(pattern) + " --params " + quoted(dir / "y.yaml") +
                             " --out " + quoted(out) + " --directions weft --points 3");
  EXPECT_EQ(again.exit_code, 2) << again.err;
  const auto bad = run_cli("synth yarn --pattern " + quoted(pattern) + " --params " + quoted(dir / "y.yaml") +
                           " --out " + quoted(dir / "o2") + " --directions diagonal");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--directions: diagonal"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace yarnfit::yarn
