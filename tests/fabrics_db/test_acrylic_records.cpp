// The records built by scripts/build_acrylic_records.py from the real stitch-by-stitch
// acrylic measurements load, validate and carry the sample YAMLs' sizes.
#include <cmath>
#include <regex>

#include "fabrics_db/records/database.hpp"
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

}  // namespace
}  // namespace yarnfit::testing
