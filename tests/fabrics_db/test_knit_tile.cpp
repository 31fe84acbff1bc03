// Knitting charts and the initial geometry of generated knit tiles (fabrics_db/tile/
// knit_chart.hpp, knit_tile.hpp; issue 20, acceptance 1): for every named chart at the four
// acrylic stitch lengths and radii and at R = 0.1 mm and 1 mm, the tile passes the pyp checks,
// every course is one yarn that closes through the period offsets, every stitch has the yarn
// length L within 1 %, and no two non-adjacent segments are closer than the inner contact
// radius R2 = R/4 (SPEC §3: R2 = R_est/4, and the generated tile's parameters take R_est = R).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "fabrics_db/tile/knit_chart.hpp"
#include "fabrics_db/tile/knit_tile.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"
#include "tests/expect_error.hpp"

namespace yarnfit::db {
namespace {

TEST(KnitChart, NamedChartsAreTheirFaceViews) {
  const std::vector<std::pair<std::string, std::string>> expected{
      {"stockinette", "k"}, {"garter", "k/p"}, {"rib1x1", "kp"}, {"rib2x2", "kkpp"}, {"seed", "kp/pk"}};
  ASSERT_EQ(named_knit_charts().size(), expected.size());
  for (const auto& [name, text] : expected) {
    const auto chart = parse_knit_chart(name);
    ASSERT_TRUE(chart) << name;
    EXPECT_EQ(chart->text(), text) << name;
    EXPECT_EQ(chart->name, name);
  }
}

TEST(KnitChart, FreeChartsAreRowsFromTheBottomAndRepeat) {
  const auto chart = parse_knit_chart("KP p/pk K");
  ASSERT_TRUE(chart);
  EXPECT_EQ(chart->courses(), 2);
  EXPECT_EQ(chart->wales(), 3);
  EXPECT_EQ(chart->text(), "kpp/pkk");
  EXPECT_EQ(chart->at(0, 0), Stitch::knit);
  EXPECT_EQ(chart->at(1, 0), Stitch::purl);
  EXPECT_EQ(chart->at(2, 3), Stitch::knit) << "periodic in both directions";
  EXPECT_EQ(chart->face_sign(-1, -1), chart->face_sign(1, 2));
}

TEST(KnitChart, BadChartsSayWhatIsWrong) {
  std::string why;
  EXPECT_FALSE(parse_knit_chart("kx", &why));
  EXPECT_NE(why.find("unknown chart 'kx'"), std::string::npos) << why;
  EXPECT_NE(why.find("rib2x2"), std::string::npos) << "lists the named charts: " << why;
  EXPECT_FALSE(parse_knit_chart("kp/p", &why));
  EXPECT_NE(why.find("row 2 has 1 stitches, row 1 has 2"), std::string::npos) << why;
  EXPECT_FALSE(parse_knit_chart("k//p", &why));
  EXPECT_NE(why.find("row 2 has no stitches"), std::string::npos) << why;
  EXPECT_FALSE(parse_knit_chart("", &why));
}

struct Case {
  std::string chart;
  double stitch_length_mm;
  double radius_mm;
};

// The acrylic knits of ../shared/data/measured/stitch-by-stitch/README.md.
const std::vector<Case> kAcrylic{
    {"stockinette", 11.28, 0.74}, {"garter", 10.55, 0.54}, {"rib1x1", 16.10, 1.18}, {"seed", 15.67, 1.20}};

std::vector<Case> all_cases() {
  std::vector<Case> cases;
  for (const auto& chart : named_knit_charts()) {
    for (const Case& a : kAcrylic) {
      cases.push_back({chart, a.stitch_length_mm, a.radius_mm});
      if (&a == &kAcrylic.front()) {
        cases.push_back({chart, a.stitch_length_mm, 0.1});
        cases.push_back({chart, a.stitch_length_mm, 1.0});
      }
    }
  }
  return cases;
}

TEST(KnitTile, EveryChartAtEveryScaleIsAClosedCollisionFreeTileWithItsStitchLength) {
  for (const Case& c : all_cases()) {
    SCOPED_TRACE(c.chart + " L " + std::to_string(c.stitch_length_mm) + " mm, R " + std::to_string(c.radius_mm) + " mm");
    const auto chart = parse_knit_chart(c.chart);
    ASSERT_TRUE(chart);
    KnitTileOptions options;
    options.stitch_length = 1e-3 * c.stitch_length_mm;
    options.yarn_radius = 1e-3 * c.radius_mm;
    const KnitTile k = make_knit_tile(*chart, options);
    // The pyp checks: written and read back without a problem.
    Problems problems;
    const auto read = parse_pyp(format_pyp(k.tile), "generated.pyp", problems);
    ASSERT_TRUE(read) << problems.to_string();
    EXPECT_EQ(read->vertex_count(), chart->courses() * chart->wales() * options.vertices_per_stitch);
    // One yarn per course, each advancing one period along x.
    const TileFacts facts = compute_tile_facts(*read);
    ASSERT_EQ(static_cast<int>(facts.yarns.size()), chart->courses());
    for (const PeriodicYarn& y : facts.yarns) {
      EXPECT_EQ(y.offset_x, 1);
      EXPECT_EQ(y.offset_y, 0);
      EXPECT_NEAR(y.length / chart->wales(), options.stitch_length, 0.01 * options.stitch_length);
    }
    ASSERT_EQ(static_cast<int>(k.stitch_lengths.size()), chart->courses() * chart->wales());
    for (const double l : k.stitch_lengths) EXPECT_NEAR(l, options.stitch_length, 0.01 * options.stitch_length);
    EXPECT_NEAR(facts.total_rest_length / (chart->courses() * chart->wales()), options.stitch_length,
                0.01 * options.stitch_length);
    // Not inside the inner contact radius anywhere.
    EXPECT_GT(facts.min_contact_distance, 0.25 * options.yarn_radius);
    EXPECT_EQ(k.min_distance, facts.min_contact_distance);
    std::printf("  %-11s L %5.2f mm R %4.2f mm: w %.3f mm, p %.3f mm, crossings %.2f R apart, min distance %.2f R\n",
                c.chart.c_str(), c.stitch_length_mm, c.radius_mm, 1e3 * k.wale_spacing, 1e3 * k.course_spacing,
                k.crossing_gap / options.yarn_radius, facts.min_contact_distance / options.yarn_radius);
  }
}

// A purl course is the knit course mirrored in z: stockinette and reverse stockinette ("p")
// are mirror images.
TEST(KnitTile, PurlIsKnitMirroredThroughTheFabricPlane) {
  KnitTileOptions options;
  options.stitch_length = 11.28e-3;
  options.yarn_radius = 0.74e-3;
  const KnitTile knit = make_knit_tile(*parse_knit_chart("k"), options);
  const KnitTile purl = make_knit_tile(*parse_knit_chart("p"), options);
  ASSERT_EQ(knit.tile.vertex_count(), purl.tile.vertex_count());
  for (int v = 0; v < knit.tile.vertex_count(); ++v) {
    const auto& a = knit.tile.positions[static_cast<std::size_t>(v)];
    const auto& b = purl.tile.positions[static_cast<std::size_t>(v)];
    EXPECT_DOUBLE_EQ(a[0], b[0]);
    EXPECT_DOUBLE_EQ(a[1], b[1]);
    EXPECT_DOUBLE_EQ(a[2], -b[2]);
  }
  // Stockinette: the legs on the face one radius out, heads and sinkers one radius behind.
  const auto z_at = [&](int i) { return knit.tile.positions[static_cast<std::size_t>(i)][2]; };
  const int n = options.vertices_per_stitch;
  EXPECT_DOUBLE_EQ(z_at(n / 4), options.yarn_radius);
  EXPECT_DOUBLE_EQ(z_at(3 * n / 4), options.yarn_radius);
  EXPECT_DOUBLE_EQ(z_at(n / 2), -options.yarn_radius);
  EXPECT_DOUBLE_EQ(z_at(0), -options.yarn_radius);
}

// Garter and seed loops tilt: legs in the middle plane, the sinker a crossing gap behind
// (knit) or in front (purl), the head on the other side.
TEST(KnitTile, GarterLoopsTiltAndSeedWalesMeetInTheMiddlePlane) {
  KnitTileOptions options;
  options.stitch_length = 10.55e-3;
  options.yarn_radius = 0.54e-3;
  const double gap = 2.0 * options.yarn_radius;
  const int n = options.vertices_per_stitch;
  const KnitTile garter = make_knit_tile(*parse_knit_chart("garter"), options);
  const auto z = [&](const KnitTile& t, int loop, int i) {
    return t.tile.positions[static_cast<std::size_t>(loop * n + i)][2];
  };
  // Course 0 knit (purl above and below), course 1 purl.
  EXPECT_NEAR(z(garter, 0, n / 4), 0.0, 1e-18);
  EXPECT_DOUBLE_EQ(z(garter, 0, 0), -gap);
  EXPECT_DOUBLE_EQ(z(garter, 0, n / 2), gap);
  EXPECT_DOUBLE_EQ(z(garter, 1, 0), gap);
  EXPECT_DOUBLE_EQ(z(garter, 1, n / 2), -gap);
  const KnitTile seed = make_knit_tile(*parse_knit_chart("seed"), options);
  EXPECT_NEAR(z(seed, 0, 0), 0.0, 1e-18) << "a knit and a purl wale meet";
  EXPECT_DOUBLE_EQ(z(seed, 0, n / 2), gap);
}

TEST(KnitTile, TooShortAStitchForItsYarnIsRefusedWithTheShortestLength) {
  KnitTileOptions options;
  options.stitch_length = 2e-3;
  options.yarn_radius = 1e-3;
  try {
    (void)make_knit_tile(*parse_knit_chart("stockinette"), options);
    FAIL() << "no error";
  } catch (const yarnfit::Error& e) {
    EXPECT_NE(std::string(e.what()).find("too short"), std::string::npos) << e.what();
  }
  options.vertices_per_stitch = 4;
  EXPECT_ERROR((void)make_knit_tile(*parse_knit_chart("stockinette"), options), yarnfit::ErrorCategory::input);
}

}  // namespace
}  // namespace yarnfit::db
