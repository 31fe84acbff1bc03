// Reading a valid record: types, SI units, per-test swatches and gauges, summaries.
#include <cmath>

#include "fabrics_db/records/fabric_reader.hpp"
#include "fabrics_db/records/fabric_summary.hpp"
#include "tests/fabrics_db/fabric_fixture.hpp"

namespace yarnfit::testing {
namespace {

TEST(FabricReader, ReadsTheBaseRecordInSiUnits) {
  ScratchDir dir("reader");
  write_base_fabric(dir / "T1");
  const auto load = db::load_fabric(dir / "T1");
  ASSERT_TRUE(load.ok()) << load.problems.to_string();
  const db::Fabric& f = *load.fabric;
  EXPECT_EQ(f.id, "T1");
  EXPECT_EQ(f.family, "test-family");
  ASSERT_TRUE(f.areal_density);
  EXPECT_DOUBLE_EQ(*f.areal_density, 0.2);  // 200 g/m² = 0.2 kg/m²
  ASSERT_EQ(f.yarns.size(), 2u);
  EXPECT_EQ(f.yarns[0].material, "polyester");
  EXPECT_EQ(f.yarns[0].filaments, 75);
  EXPECT_DOUBLE_EQ(f.yarns[0].linear_density(), 72e-3 / 9000.0);  // 8 mg/m
  EXPECT_FALSE(f.yarns[1].filaments);
  EXPECT_FALSE(f.yarns[1].stiffness);
  ASSERT_TRUE(f.stiffest_yarn_stiffness());
  EXPECT_DOUBLE_EQ(*f.stiffest_yarn_stiffness(), 85.0);

  ASSERT_EQ(f.stretch_tests.size(), 2u);
  const auto& weft = f.stretch_tests.at(db::Direction::weft);
  EXPECT_DOUBLE_EQ(weft.swatch.length, 0.1);  // the fabric's swatch
  EXPECT_DOUBLE_EQ(weft.swatch.width, 0.06);
  EXPECT_TRUE(weft.gauge.empty());
  const auto& warp = f.stretch_tests.at(db::Direction::warp);
  EXPECT_DOUBLE_EQ(warp.swatch.length, 0.0692);  // its own swatch
  EXPECT_DOUBLE_EQ(warp.swatch.width, 0.0666);
  ASSERT_TRUE(warp.gauge.length && warp.gauge.width);
  EXPECT_DOUBLE_EQ(*warp.gauge.length, 0.0594);
  EXPECT_DOUBLE_EQ(*warp.gauge.width, 0.0315);
  ASSERT_EQ(weft.curve.size(), 4u);
  EXPECT_EQ(weft.curve.source_lines, (std::vector<int>{2, 3, 4, 5}));
  EXPECT_DOUBLE_EQ(weft.curve.force[3], 2.4);
  EXPECT_DOUBLE_EQ(weft.line_force(3), 40.0);  // 2.4 N over 6 cm
  EXPECT_TRUE(weft.curve.has_compression());

  const auto& bend = f.bending_tests.at(db::Direction::weft);
  ASSERT_EQ(bend.curve.size(), 4u);
  EXPECT_DOUBLE_EQ(bend.curve.clamp_distance[0], 0.003);
  EXPECT_DOUBLE_EQ(bend.curve.aspect_ratio[3], 1.08);
  EXPECT_FALSE(f.pattern);
}

TEST(FabricReader, CompressionColumnIsOptionalAndExtraColumnsAreIgnored) {
  ScratchDir dir("reader");
  write_base_fabric(dir / "T1");
  write_file(dir / "T1" / "stretch_weft.csv",
             "# a comment line\nforce_N,note,stretch\n0,start,0\n1.5,\"a, b\",0.2\n");
  const auto load = db::load_fabric(dir / "T1");
  ASSERT_TRUE(load.ok()) << load.problems.to_string();
  const auto& c = load.fabric->stretch_tests.at(db::Direction::weft).curve;
  EXPECT_FALSE(c.has_compression());
  EXPECT_EQ(c.stretch, (std::vector<double>{0.0, 0.2}));
  EXPECT_EQ(c.source_lines, (std::vector<int>{3, 4}));
}

TEST(FabricReader, GroundTruthIsKeptAsJson) {
  ScratchDir dir("reader");
  write_base_fabric(dir / "T1");
  replace_in_file(dir / "T1" / "fabric.yaml", "bending_tests:",
                  "ground_truth: {kxx: 12.5, note: synthetic, list: [1, 2]}\nbending_tests:");
  const auto load = db::load_fabric(dir / "T1");
  ASSERT_TRUE(load.ok()) << load.problems.to_string();
  EXPECT_DOUBLE_EQ(load.fabric->ground_truth["kxx"].get<double>(), 12.5);
  EXPECT_EQ(load.fabric->ground_truth["note"], "synthetic");
  EXPECT_EQ(load.fabric->ground_truth["list"].size(), 2u);
}

TEST(FabricSummary, ComfortAndPowerStretchByLineForce) {
  db::StretchTest t;
  t.swatch = {0.1, 0.06};
  t.curve.stretch = {0.0, 0.2, 0.4, 0.6};
  t.curve.force = {0.0, 1.0, 3.0, 4.0};  // N over 6 cm: 0, 16.7, 50, 66.7 N/m
  const auto comfort = db::stretch_at_line_force(t, db::k_comfort_line_force);
  ASSERT_TRUE(comfort);
  EXPECT_NEAR(*comfort, 0.3, 1e-12);  // 2 N reached halfway between 1 N and 3 N
  EXPECT_FALSE(db::stretch_at_line_force(t, db::k_power_line_force));  // 5 N never reached
  t.swatch.width = 0.03;  // the same forces on a narrower swatch are larger line forces
  EXPECT_NEAR(*db::stretch_at_line_force(t, db::k_comfort_line_force), 0.2, 1e-12);
}

TEST(FabricSummary, DescribeFabricReportsRangesInSi) {
  ScratchDir dir("reader");
  write_base_fabric(dir / "T1");
  const auto load = db::load_fabric(dir / "T1");
  ASSERT_TRUE(load.ok());
  const auto j = db::describe_fabric(*load.fabric);
  EXPECT_EQ(j["id"], "T1");
  EXPECT_DOUBLE_EQ(j["stretch_tests"]["weft"]["stretch"][1].get<double>(), 0.3);
  EXPECT_DOUBLE_EQ(j["stretch_tests"]["weft"]["force_N"][1].get<double>(), 2.4);
  EXPECT_DOUBLE_EQ(j["stretch_tests"]["warp"]["gauge"]["length_m"].get<double>(), 0.0594);
  EXPECT_DOUBLE_EQ(j["bending_tests"]["weft"]["clamp_distance_m"][1].get<double>(), 0.034);
  EXPECT_TRUE(j["pattern"].is_null());
}

}  // namespace
}  // namespace yarnfit::testing
