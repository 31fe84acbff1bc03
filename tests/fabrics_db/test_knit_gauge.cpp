// The knitting gauge a tile shows (fabrics_db/tile/knit_gauge.hpp; issue 48): counted from the
// yarns of a tile it equals the chart the tile was built from, for every named chart, at any
// period; tiles that are not weft knits have no count; the registered stockinette tiles count
// as the stitches their descriptions say.
#include <gtest/gtest.h>

#include "fabrics_db/tile/knit_chart.hpp"
#include "fabrics_db/tile/knit_gauge.hpp"
#include "fabrics_db/tile/knit_tile.hpp"
#include "fabrics_db/tile/woven_tile.hpp"
#include "tests/test_support.hpp"

namespace yarnfit::db {
namespace {

KnitTile knit(const std::string& chart_text, double course_ratio = 0.716) {
  const auto chart = parse_knit_chart(chart_text);
  EXPECT_TRUE(chart) << chart_text;
  KnitTileOptions o;
  o.stitch_length = 11.28e-3;
  o.yarn_radius = 0.5e-3;
  o.course_ratio = course_ratio;
  return make_knit_tile(*chart, o);
}

TEST(KnitGauge, TheYarnsCountTheChartTheTileWasBuiltFrom) {
  for (const auto& name : {"stockinette", "garter", "rib1x1", "rib2x2", "seed", "kkp/ppk"}) {
    for (const double ratio : {0.55, 0.716, 0.9}) {
      const KnitTile k = knit(name, ratio);
      const auto g = count_knit_gauge(k.tile, compute_tile_facts(k.tile), Axis::x);
      ASSERT_TRUE(g) << name << " at " << ratio;
      EXPECT_EQ(g->wales, k.chart.wales()) << name << " at " << ratio;
      EXPECT_EQ(g->courses, k.chart.courses()) << name << " at " << ratio;
      EXPECT_NEAR(g->wale_spacing, k.wale_spacing, 1e-12) << name;
      EXPECT_NEAR(g->course_spacing, k.course_spacing, 1e-12) << name;
      EXPECT_NEAR(g->wales_per_10cm(), 0.1 / k.wale_spacing, 1e-9) << name;
    }
  }
}

TEST(KnitGauge, ATileTurnedAQuarterCountsAlongItsOtherAxis) {
  const KnitTile k = knit("rib2x2");
  PeriodicTile turned = k.tile;
  std::swap(turned.period_x, turned.period_y);
  for (auto& p : turned.positions) std::swap(p[0], p[1]);
  for (auto& e : turned.edges) std::swap(e.dx, e.dy);
  turned.reference_directors.clear();
  fill_tile_defaults(turned);
  const auto facts = compute_tile_facts(turned);
  EXPECT_FALSE(count_knit_gauge(turned, facts, Axis::x));  // its courses run along y
  const auto g = count_knit_gauge(turned, facts, Axis::y);
  ASSERT_TRUE(g);
  EXPECT_EQ(g->wales, 4);
  EXPECT_EQ(g->courses, 1);
}

TEST(KnitGauge, AWeaveIsNoWeftKnit) {
  WovenTileOptions o;
  o.yarn_spacing = 1e-3;
  o.yarn_radius = 0.2e-3;
  const auto woven = make_woven_tile(*parse_weave_chart("plain"), o);
  EXPECT_FALSE(count_knit_gauge(woven, compute_tile_facts(woven), Axis::x));
}

TEST(KnitGauge, TheRegisteredStockinetteTilesCountTheirStitches) {
  const auto file = testing::shared_dir() / "data/patterns/stockinette.pyp";
  YARNFIT_REQUIRE_SHARED(file);
  Problems problems;
  const auto tile = read_pyp(file, problems);
  ASSERT_TRUE(tile) << problems.to_string();
  const auto g = count_knit_gauge(*tile, compute_tile_facts(*tile), Axis::x);
  ASSERT_TRUE(g);
  // README: "4 stitches: 2 course yarns along x".
  EXPECT_EQ(g->courses, 2);
  EXPECT_EQ(g->wales, 2);
}

}  // namespace
}  // namespace yarnfit::db
