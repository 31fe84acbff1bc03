// Weave charts and the initial geometry of woven tiles (fabrics_db/tile/woven_tile.hpp;
// issue 37's slack reproducers): the named charts, chart errors, and for every named chart
// at two radii: the pyp checks pass, every yarn closes over one period in its direction, the
// yarn on top at a crossing lies 2·depth·R above the other, exactly as the chart says, and
// parallel neighbours are the spacing apart; the crimp is shared between weft and warp as asked.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "fabrics_db/problems.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"
#include "fabrics_db/tile/woven_tile.hpp"
#include "tests/expect_error.hpp"

namespace yarnfit::db {
namespace {

TEST(WeaveChart, NamedChartsAndFreeText) {
  const std::vector<std::pair<std::string, std::string>> expected{
      {"plain", "10/01"}, {"basket2x2", "1100/1100/0011/0011"}, {"twill2x2", "1100/0110/0011/1001"}};
  ASSERT_EQ(named_weave_charts().size(), expected.size());
  for (const auto& [name, text] : expected) {
    const auto chart = parse_weave_chart(name);
    ASSERT_TRUE(chart) << name;
    EXPECT_EQ(chart->text(), text);
  }
  const auto free = parse_weave_chart("10 0/0 11");
  ASSERT_TRUE(free);
  EXPECT_EQ(free->wefts(), 2);
  EXPECT_EQ(free->warps(), 3);
  EXPECT_TRUE(free->warp_on_top(0, 0));
  EXPECT_FALSE(free->warp_on_top(2, 1)) << "periodic: weft 2 is weft 0";
  EXPECT_TRUE(free->warp_on_top(-1, -1)) << "periodic: weft 1, warp 2";
}

TEST(WeaveChart, BadChartsSayWhatIsWrong) {
  std::string why;
  EXPECT_FALSE(parse_weave_chart("1x/01", &why));
  EXPECT_NE(why.find("unknown weave '1x/01'"), std::string::npos) << why;
  EXPECT_NE(why.find("basket2x2"), std::string::npos) << "lists the named charts: " << why;
  EXPECT_FALSE(parse_weave_chart("10/010", &why));
  EXPECT_NE(why.find("row 2 has 3 crossings, row 1 has 2"), std::string::npos) << why;
  EXPECT_FALSE(parse_weave_chart("10//01", &why));
  EXPECT_NE(why.find("row 2 has no crossings"), std::string::npos) << why;
  EXPECT_FALSE(parse_weave_chart("11/00", &why));
  EXPECT_NE(why.find("weft 1 lies on one side at every crossing"), std::string::npos) << why;
  EXPECT_FALSE(parse_weave_chart("10/10", &why));
  EXPECT_NE(why.find("warp 1 lies on one side"), std::string::npos) << why;
}

TEST(WovenTile, BadOptionsAreRefused) {
  const auto chart = parse_weave_chart("plain");
  ASSERT_TRUE(chart);
  WovenTileOptions o;
  o.yarn_radius = 0.5e-3;
  o.yarn_spacing = 0.9e-3;
  ASSERT_EQ(o.problems().size(), 1u) << o.problems().to_string();
  const auto problems = o.problems();
  ASSERT_FALSE(problems.empty());
  EXPECT_EQ(problems.items()[0].field, "yarn_spacing");
  EXPECT_NE(o.problems().to_string().find("at least twice the yarn radius"), std::string::npos) << o.problems().to_string();
  EXPECT_ERROR(make_woven_tile(*chart, o), yarnfit::ErrorCategory::input);
  o.yarn_spacing = 1.5e-3;
  o.vertices_per_crossing = 2;
  EXPECT_NE(o.problems().to_string().find("vertices_per_crossing: must be at least 3"), std::string::npos)
      << o.problems().to_string();
  o.vertices_per_crossing = 6;
  for (const double share : {0.0, 1.0, std::nan("")}) {
    o.weft_crimp_share = share;
    EXPECT_NE(o.problems().to_string().find("weft_crimp_share: must be in (0, 1)"), std::string::npos)
        << share << ": " << o.problems().to_string();
  }
}

// The gap at a crossing is the sum of the two yarns' crimp amplitudes, shared as asked: each
// yarn swings between ±its amplitude, the weft's 2·share·R, the warp's 2·(1 − share)·R.
TEST(WovenTile, TheCrimpIsSharedBetweenWeftAndWarpAsAsked) {
  const auto chart = parse_weave_chart("plain");
  ASSERT_TRUE(chart);
  for (const double share : {0.5, 0.6, 0.8}) {
    WovenTileOptions o;
    o.yarn_spacing = 1.5e-3;
    o.yarn_radius = 0.5e-3;
    o.weft_crimp_share = share;
    const PeriodicTile tile = make_woven_tile(*chart, o);
    const int weft_vertices = chart->wefts() * chart->warps() * o.vertices_per_crossing;
    double weft_swing = 0, warp_swing = 0;
    for (int v = 0; v < tile.vertex_count(); ++v) {
      double& swing = v < weft_vertices ? weft_swing : warp_swing;
      swing = std::max(swing, std::abs(tile.positions[static_cast<std::size_t>(v)][2]));
    }
    EXPECT_NEAR(weft_swing, 2 * share * o.yarn_radius, 1e-15) << share;
    EXPECT_NEAR(warp_swing, 2 * (1 - share) * o.yarn_radius, 1e-15) << share;
  }
}

TEST(WovenTile, EveryNamedWeaveIsAValidTileWithTheChartsCrossings) {
  for (const std::string& name : named_weave_charts()) {
    for (const double radius : {0.25e-3, 0.5e-3}) {
      SCOPED_TRACE(name + " R " + std::to_string(radius));
      const auto chart = parse_weave_chart(name);
      ASSERT_TRUE(chart);
      WovenTileOptions o;
      o.yarn_spacing = 1.5e-3;
      o.yarn_radius = radius;
      const PeriodicTile tile = make_woven_tile(*chart, o);
      Problems problems;
      const auto reread = parse_pyp(format_pyp(tile), "woven.pyp", problems);
      ASSERT_TRUE(reread) << problems.to_string();
      EXPECT_DOUBLE_EQ(tile.period_x, chart->warps() * o.yarn_spacing);
      EXPECT_DOUBLE_EQ(tile.period_y, chart->wefts() * o.yarn_spacing);
      const TileFacts facts = compute_tile_facts(tile);
      ASSERT_EQ(static_cast<int>(facts.yarns.size()), chart->wefts() + chart->warps());
      for (int y = 0; y < static_cast<int>(facts.yarns.size()); ++y) {
        const PeriodicYarn& yarn = facts.yarns[static_cast<std::size_t>(y)];
        const bool weft = y < chart->wefts();
        EXPECT_EQ(yarn.offset_x, weft ? 1 : 0) << "yarn " << y;
        EXPECT_EQ(yarn.offset_y, weft ? 0 : 1) << "yarn " << y;
      }
      // At each crossing (weft j, warp i) both yarns have a vertex over its centre; the one
      // the chart puts on top is 2R higher.
      const int n = o.vertices_per_crossing;
      const int weft_vertices = chart->warps() * n;
      const int warp_vertices = chart->wefts() * n;
      for (int j = 0; j < chart->wefts(); ++j) {
        for (int i = 0; i < chart->warps(); ++i) {
          const auto& w = tile.positions[static_cast<std::size_t>(j * weft_vertices + i * n)];
          const auto& v =
              tile.positions[static_cast<std::size_t>(chart->wefts() * weft_vertices + i * warp_vertices + j * n)];
          EXPECT_NEAR(w[0], v[0], 1e-15);
          EXPECT_NEAR(w[1], v[1], 1e-15);
          const double warp_above = v[2] - w[2];
          EXPECT_NEAR(warp_above, chart->warp_on_top(j, i) ? 2 * radius : -2 * radius, 1e-15)
              << "weft " << j << ", warp " << i;
        }
      }
    }
  }
}

}  // namespace
}  // namespace yarnfit::db
