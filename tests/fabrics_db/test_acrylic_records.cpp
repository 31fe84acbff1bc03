// The records built by scripts/build_acrylic_records.py from the real stitch-by-stitch
// acrylic measurements load, validate and carry the sample YAMLs' sizes; with --pattern the
// stockinette record carries the shared stockinette tile scaled to the acrylic stitch length.
#include <cmath>
#include <regex>

#include "fabrics_db/records/database.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"
#include "tests/test_support.hpp"

namespace yarnfit::testing {
namespace {

fs::path acrylic_dir() { return shared_dir() / "data/measured/stitch-by-stitch/acrylic"; }

double yaml_number(const fs::path& file, const std::string& key) {
  const std::string text = read_file(file);
  std::smatch m;
  if (!std::regex_search(text, m, std::regex("\\n\\s*" + key + ":\\s*([-0-9.eE+]+)")))
    throw std::runtime_error(key + " not in " + file.string());
  return std::stod(m[1]);
}

class AcrylicRecords : public ::testing::Test {
 protected:
  void SetUp() override {
    YARNFIT_REQUIRE_SHARED(acrylic_dir());
    const std::string cmd = "python3 " + quoted(fs::path(YARNFIT_SOURCE_DIR) / "scripts/build_acrylic_records.py") +
                            " " + quoted(m_dir.path() / "db") + " --shared " + quoted(shared_dir()) + " >/dev/null";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  }
  ScratchDir m_dir{"acrylic"};
};

TEST_F(AcrylicRecords, FourValidFabricsWithWeftAndWarpTests) {
  const auto db = db::load_database(m_dir.path() / "db");
  ASSERT_TRUE(db.all_problems().empty()) << db.all_problems().to_string();
  ASSERT_EQ(db.fabrics.size(), 4u);
  const char* knits[] = {"garter", "rib", "seed", "stockinette"};
  for (std::size_t i = 0; i < 4; ++i) {
    const db::Fabric& f = *db.fabrics[i].fabric;
    const std::string knit = knits[i];
    EXPECT_EQ(f.id, "acrylic_" + knit);
    EXPECT_EQ(f.family, knit);
    ASSERT_EQ(f.stretch_tests.size(), 2u);
    for (const auto& [dir, axis] : {std::pair{db::Direction::weft, "x"}, std::pair{db::Direction::warp, "y"}}) {
      const fs::path yaml = acrylic_dir() / (knit + "_" + axis + ".yaml");
      const auto& t = f.stretch_tests.at(dir);
      SCOPED_TRACE(knit + " " + axis);
      EXPECT_NEAR(t.swatch.length, 1e-3 * yaml_number(yaml, "undeformed_clamp_separation_mm"), 1e-9);
      EXPECT_NEAR(*t.gauge.length, 1e-3 * yaml_number(yaml, "undeformed_gauge_length_mm"), 1e-9);
      EXPECT_NEAR(*t.gauge.width, 1e-3 * yaml_number(yaml, "undeformed_gauge_width_mm"), 1e-9);
      EXPECT_GE(t.swatch.width, *t.gauge.width);
      const double recorded = 1e-3 * yaml_number(yaml, "fabric_width_at_clamp_mm");
      if (recorded >= *t.gauge.width) {
        EXPECT_NEAR(t.swatch.width, recorded, 1e-9);
      }
      EXPECT_EQ(t.curve.size(), 25u);
      EXPECT_TRUE(t.curve.has_compression());
      EXPECT_DOUBLE_EQ(t.curve.stretch.front(), 0.0);
      EXPECT_GT(t.curve.force.back(), 10.0);  // tests ran to about 30 N
    }
  }
  // garter X and seed Y record a width at the clamp narrower than the pins: estimated, and said so.
  EXPECT_NE(db.fabrics[0].fabric->description.find("Weft swatch width estimated"), std::string::npos);
  EXPECT_NE(db.fabrics[2].fabric->description.find("Warp swatch width estimated"), std::string::npos);
}

TEST_F(AcrylicRecords, ValidateAndListAcceptThem) {
  auto r = run_cli("db validate " + quoted(m_dir.path() / "db"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("4 fabrics: 4 valid, 0 invalid; 0 problems"), std::string::npos) << r.out;
  r = run_cli("db list " + quoted(m_dir.path() / "db"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::cout << r.out;
  for (const char* id : {"acrylic_garter", "acrylic_rib", "acrylic_seed", "acrylic_stockinette"})
    EXPECT_NE(r.out.find(id), std::string::npos) << r.out;
  r = run_cli("db show " + quoted(m_dir.path() / "db/acrylic_rib"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST_F(AcrylicRecords, ScriptRefusesToOverwriteAndToWriteIntoTheSourceTree) {
  const std::string script = quoted(fs::path(YARNFIT_SOURCE_DIR) / "scripts/build_acrylic_records.py");
  EXPECT_NE(std::system(("python3 " + script + " " + quoted(m_dir.path() / "db") + " --shared " +
                         quoted(shared_dir()) + " 2>/dev/null").c_str()), 0);
  EXPECT_NE(std::system(("python3 " + script + " " + quoted(fs::path(YARNFIT_SOURCE_DIR) / "scratch") +
                         " --shared " + quoted(shared_dir()) + " 2>/dev/null").c_str()), 0);
  EXPECT_FALSE(fs::exists(fs::path(YARNFIT_SOURCE_DIR) / "scratch"));
}

// --pattern: the stockinette record gets tile.pyp, the shared stockinette tile scaled
// uniformly so that its yarn length per stitch (rest lengths) is 11.28 mm (data README,
// "Yarn and stitch facts"). The shared tile holds 4 stitches: 2 course yarns along x, each
// making 2 loops per period.
class AcrylicStockinetteTile : public ::testing::Test {
 protected:
  void SetUp() override {
    YARNFIT_REQUIRE_SHARED(acrylic_dir());
    YARNFIT_REQUIRE_SHARED(pattern());
    const std::string cmd = "python3 " + quoted(fs::path(YARNFIT_SOURCE_DIR) / "scripts/build_acrylic_records.py") +
                            " " + quoted(m_dir.path() / "db") + " --shared " + quoted(shared_dir()) +
                            " --pattern " + quoted(pattern()) + " >" + quoted(m_dir.path() / "out.txt");
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  }
  static fs::path pattern() { return shared_dir() / "data/patterns/stockinette.pyp"; }
  ScratchDir m_dir{"acrylic_tile"};
};

TEST_F(AcrylicStockinetteTile, StockinetteTileIsScaledToTheAcrylicStitchLength) {
  const auto db = db::load_database(m_dir.path() / "db");
  ASSERT_TRUE(db.all_problems().empty()) << db.all_problems().to_string();
  ASSERT_EQ(db.fabrics.size(), 4u);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_FALSE(db.fabrics[i].fabric->pattern.has_value());
  const db::Fabric& f = *db.fabrics[3].fabric;
  ASSERT_EQ(f.id, "acrylic_stockinette");
  ASSERT_TRUE(f.pattern.has_value());
  EXPECT_EQ(f.pattern->file.filename(), "tile.pyp");
  EXPECT_EQ(f.pattern->weft_axis, db::Axis::x);

  db::Problems problems;
  const auto original = db::read_pyp(pattern(), problems);
  ASSERT_TRUE(original.has_value()) << problems.to_string();
  const db::PeriodicTile& a = *original;
  const db::PeriodicTile& b = f.pattern->tile;
  const db::TileFacts fa = db::compute_tile_facts(a);
  const db::TileFacts& fb = f.pattern->facts;
  // Course yarns run along the weft axis x.
  ASSERT_EQ(fb.yarns.size(), 2u);
  for (const auto& y : fb.yarns) {
    EXPECT_EQ(y.offset_x, 1);
    EXPECT_EQ(y.offset_y, 0);
  }
  constexpr int stitches = 4;
  const double per_stitch = fb.total_rest_length / stitches;
  EXPECT_NEAR(per_stitch, 11.28e-3, 11.28e-3 * 1e-3);
  const double s = per_stitch / (fa.total_rest_length / stitches);
  EXPECT_NEAR(s, 0.4294, 1e-4);
  // Uniform scale: lengths scale, twists, curvatures (integrated) and directors do not.
  EXPECT_NEAR(b.period_x, s * a.period_x, 1e-9 * a.period_x);
  EXPECT_NEAR(b.period_y, s * a.period_y, 1e-9 * a.period_y);
  EXPECT_NEAR(b.radius, s * a.radius, 1e-9 * a.radius);
  ASSERT_EQ(b.vertex_count(), a.vertex_count());
  for (int v = 0; v < a.vertex_count(); ++v) {
    const auto k = static_cast<std::size_t>(v);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(b.positions[k][c], s * a.positions[k][c], 1e-11);
    EXPECT_EQ(b.twists[k], a.twists[k]);
    EXPECT_NEAR(b.rest_lengths[k], s * a.rest_lengths[k], 1e-8 * a.rest_lengths[k]);
    EXPECT_EQ(b.rest_curvatures[k], a.rest_curvatures[k]);
    EXPECT_EQ(b.rest_twists[k], a.rest_twists[k]);
    EXPECT_EQ(b.reference_directors[k], a.reference_directors[k]);
    EXPECT_EQ(b.reference_twists[k], a.reference_twists[k]);
  }
  EXPECT_NEAR(fb.r_est, s * fa.r_est, 1e-6 * fa.r_est);
  // The stitch length is matched and the radius follows; the record says so next to the
  // reported effective radius, and the script prints the figures.
  EXPECT_NE(f.description.find("effective radius 0.74 mm"), std::string::npos) << f.description;
  EXPECT_NE(f.description.find("0.429 mm"), std::string::npos) << f.description;
  const std::string out = read_file(m_dir.path() / "out.txt");
  EXPECT_NE(out.find("-> 4 stitches"), std::string::npos) << out;
  EXPECT_NE(out.find("scale factor 0.4294"), std::string::npos) << out;
}

TEST_F(AcrylicStockinetteTile, ValidateReadsTheTile) {
  auto r = run_cli("db validate " + quoted(m_dir.path() / "db/acrylic_stockinette"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("1 fabric: 1 valid, 0 invalid; 0 problems"), std::string::npos) << r.out;
  r = run_cli("db validate " + quoted(m_dir.path() / "db"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  r = run_cli("db show " + quoted(m_dir.path() / "db/acrylic_stockinette"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("tile.pyp (weft along x)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("period 6.463 x 3.406 mm"), std::string::npos) << r.out;
}

TEST_F(AcrylicStockinetteTile, ScriptRejectsAnUnreadableTile) {
  const std::string script = quoted(fs::path(YARNFIT_SOURCE_DIR) / "scripts/build_acrylic_records.py");
  write_file(m_dir.path() / "bad.pyp", "*pattern\n1 1 0.1 2\n*Q\n0 0 0\n");
  EXPECT_NE(std::system(("python3 " + script + " " + quoted(m_dir.path() / "db2") + " --shared " +
                         quoted(shared_dir()) + " --pattern " + quoted(m_dir.path() / "bad.pyp") +
                         " 2>/dev/null >/dev/null").c_str()), 0);
  EXPECT_FALSE(fs::exists(m_dir.path() / "db2"));  // the tile is checked before any record is written
}

}  // namespace
}  // namespace yarnfit::testing
