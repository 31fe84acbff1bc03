// `yarnfit tile make` (issue 20): a relaxed tile written and described in JSON with the
// fields SPEC §5 names, an existing file left alone without --force, and bad arguments named.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>

#include "fabrics_db/tile/periodic_tile.hpp"
#include "tests/fabrics_db/fabric_fixture.hpp"
#include "tests/test_support.hpp"

namespace yarnfit::testing {
namespace {

namespace fs = std::filesystem;

TEST(TileCli, MakesARelaxedTileAndSaysWhatItIs) {
  ScratchDir dir("tile_make");
  const fs::path out = dir / "rib.pyp";
  const auto r = run_cli("tile make --chart rib1x1 --stitch-length-mm 16.1 --yarn-radius-mm 1.18 --json --out " + quoted(out));
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* key : {"period_mm", "courses_per_cm", "wales_per_cm", "stitch_length_mm", "yarn_radius_mm",
                          "rest_stress_ratio", "converged", "seconds"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_TRUE(j["converged"].get<bool>());
  EXPECT_LE(j["rest_stress_ratio"].get<double>(), 0.01);
  EXPECT_NEAR(j["stitch_length_mm"].get<double>(), 16.1, 1e-9);
  EXPECT_DOUBLE_EQ(j["yarn_radius_mm"].get<double>(), 1.18);
  db::Problems problems;
  const auto tile = db::read_pyp(out, problems);
  ASSERT_TRUE(tile) << problems.to_string();
  EXPECT_EQ(tile->vertex_count(), 2 * 16);
  EXPECT_NEAR(1e3 * tile->period_x, j["period_mm"][0].get<double>(), 1e-9);
  EXPECT_NEAR(10.0 / (1e3 * tile->period_x / 2.0), j["wales_per_cm"].get<double>(), 1e-9);

  // Not replaced without --force.
  const std::string before = read_file(out);
  const auto again = run_cli("tile make --chart seed --stitch-length-mm 15.67 --yarn-radius-mm 1.2 --out " + quoted(out));
  EXPECT_EQ(again.exit_code, 2);
  EXPECT_NE(again.err.find("exists (pass --force to replace it)"), std::string::npos) << again.err;
  EXPECT_EQ(read_file(out), before);
}

TEST(TileCli, BadArgumentsAreNamed) {
  ScratchDir dir("tile_make_bad");
  const auto r = run_cli("tile make --chart kx/p --stitch-length-mm 0 --yarn-radius-mm 1 --out " + quoted(dir / "t.pyp"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--chart: unknown chart 'kx/p'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--stitch-length-mm: must be a positive length"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "t.pyp"));
  const auto tight = run_cli("tile make --chart seed --stitch-length-mm 3 --yarn-radius-mm 1 --out " + quoted(dir / "t.pyp"));
  EXPECT_EQ(tight.exit_code, 2);
  EXPECT_NE(tight.err.find("too short"), std::string::npos) << tight.err;
}

// A woven tile (issue 37): written as constructed, readable by the yarn commands, and the
// options of the other kind of tile (and a crimp share outside (0, 1)) refused.
TEST(TileCli, AWovenTileIsWrittenFromItsWeave) {
  ScratchDir dir("tile_make_weave");
  const fs::path out = dir / "basket.pyp";
  const auto r = run_cli("tile make --weave basket2x2 --yarn-spacing-mm 1.5 --yarn-radius-mm 0.5 --json --out " +
                         quoted(out));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("weave_rows"), "1100/1100/0011/0011");
  EXPECT_NEAR(j.at("period_mm")[0].get<double>(), 6.0, 1e-12);
  EXPECT_EQ(j.at("vertices").get<int>(), 8 * 4 * 6);
  EXPECT_EQ(j.at("weft_crimp_share").get<double>(), 0.6);
  db::Problems problems;
  EXPECT_TRUE(db::read_pyp(out, problems)) << problems.to_string();
  const auto bad = run_cli("tile make --weave 11/00 --chart seed --stitch-length-mm 3 --yarn-spacing-mm 0.8 "
                           "--yarn-radius-mm 0.5 --out " + quoted(dir / "bad.pyp"));
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--weave: weave '11/00': weft 1 lies on one side"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("--chart: give either a knit chart or --weave"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("--stitch-length-mm: a woven tile takes --yarn-spacing-mm"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("at least twice the yarn radius"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(dir / "bad.pyp"));
  const auto share = run_cli("tile make --weave plain --yarn-spacing-mm 1.5 --yarn-radius-mm 0.5 --weft-crimp-share 1 "
                             "--out " + quoted(dir / "share.pyp"));
  EXPECT_EQ(share.exit_code, 2);
  EXPECT_NE(share.err.find("weft_crimp_share: must be in (0, 1)"), std::string::npos) << share.err;
  EXPECT_FALSE(fs::exists(dir / "share.pyp"));
  const auto knit_share = run_cli("tile make --chart seed --stitch-length-mm 10 --yarn-radius-mm 0.5 "
                                  "--weft-crimp-share 0.6 --out " + quoted(dir / "knit.pyp"));
  EXPECT_EQ(knit_share.exit_code, 2);
  EXPECT_NE(knit_share.err.find("--weft-crimp-share: only for a woven tile"), std::string::npos) << knit_share.err;
  const auto neither = run_cli("tile make --yarn-radius-mm 0.5 --stitch-length-mm 10 --out " + quoted(dir / "n.pyp"));
  EXPECT_EQ(neither.exit_code, 2);
  EXPECT_NE(neither.err.find("--chart: a knit chart (or --weave) is required"), std::string::npos) << neither.err;
}

// A record naming a knit validates, and `db show` says what will be generated.
TEST(TileCli, ARecordNamingAKnitIsShownAsTheTileToGenerate) {
  ScratchDir dir("knit_record");
  write_base_fabric(dir / "K");
  add_pattern_line(dir / "K", "{knit: seed, stitch_length_mm: 15.67, yarn_radius_mm: 1.2}");
  const auto valid = run_cli("db validate " + quoted(dir / "K"));
  EXPECT_EQ(valid.exit_code, 0) << valid.err;
  const auto shown = run_cli("db show " + quoted(dir / "K"));
  ASSERT_EQ(shown.exit_code, 0) << shown.err;
  EXPECT_NE(shown.out.find("pattern: seed (kp/pk), stitch length 15.67 mm, yarn radius 1.2 mm: generated when a yarn "
                           "fit needs it"),
            std::string::npos)
      << shown.out;
}

}  // namespace
}  // namespace yarnfit::testing
