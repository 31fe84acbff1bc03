// The tile of a record whose pattern names a knit (calibration/problem/generated_pattern.hpp):
// generated into the cache folder under a name made of its inputs, read back from there the
// next time instead of generated again, and made into a yarn-fit problem whose bounds are
// centred on the knit's yarn radius; a knit too short for its yarn is a problem naming the
// record's pattern.knit, and a knit without its tile is refused by make_yarn_fit_problem.
#include <gtest/gtest.h>

#include <filesystem>

#include "calibration/problem/generated_pattern.hpp"
#include "calibration/problem/yarn_fit_problem.hpp"
#include "tests/example_fabric.hpp"
#include "tests/test_support.hpp"

namespace yarnfit::calibration {
namespace {

namespace fs = std::filesystem;
using yarnfit::testing::bundled_example;
using yarnfit::testing::ScratchDir;

db::Fabric knit_fabric(const std::string& chart, double stitch_length_mm, double radius_mm) {
  db::Fabric f = bundled_example();
  f.pattern = db::PatternRef{};
  f.pattern->knit = db::KnitSpec{*db::parse_knit_chart(chart), 1e-3 * stitch_length_mm, 1e-3 * radius_mm};
  return f;
}

TEST(GeneratedPattern, MadeOnceIntoTheCacheAndReadFromItAfterwards) {
  ScratchDir dir("generated_pattern");
  db::Fabric first = knit_fabric("stockinette", 11.28, 0.74);
  db::Problems problems;
  EXPECT_FALSE(make_yarn_fit_problem(first, problems)) << "no tile yet";
  EXPECT_NE(problems.to_string().find("pattern.knit: the tile of this knit is not made yet"), std::string::npos)
      << problems.to_string();
  problems = {};
  ASSERT_TRUE(make_generated_pattern(first, dir / "tiles", problems)) << problems.to_string();
  const fs::path file = dir / "tiles" / "knit_k_L11.28mm_R0.74mm.pyp";
  EXPECT_EQ(first.pattern->file, file);
  ASSERT_TRUE(fs::is_regular_file(file));
  EXPECT_TRUE(fs::is_regular_file(dir / "tiles" / "knit_k_L11.28mm_R0.74mm.json"));
  EXPECT_TRUE(first.pattern->has_tile());
  EXPECT_EQ(first.pattern->facts.yarns.size(), 1u);

  // The second fabric of the same knit reads the file instead of generating it again.
  const auto written = fs::last_write_time(file);
  db::Fabric second = knit_fabric("stockinette", 11.28, 0.74);
  ASSERT_TRUE(make_generated_pattern(second, dir / "tiles", problems)) << problems.to_string();
  EXPECT_EQ(fs::last_write_time(file), written) << "generated again";
  EXPECT_EQ(second.pattern->tile.positions, first.pattern->tile.positions);

  const auto problem = make_yarn_fit_problem(second, problems);
  ASSERT_TRUE(problem) << problems.to_string();
  EXPECT_DOUBLE_EQ(problem->scales.r_est, 0.74e-3) << "bounds centred on the knit's radius";
  EXPECT_LT(second.pattern->facts.r_est, 0.74e-3) << "the relaxed yarns rest pressed together";
}

TEST(GeneratedPattern, AStitchTooShortForItsYarnIsAProblemOfTheRecord) {
  ScratchDir dir("generated_pattern_short");
  db::Fabric f = knit_fabric("seed", 3.0, 1.0);
  db::Problems problems;
  EXPECT_FALSE(make_generated_pattern(f, dir / "tiles", problems));
  EXPECT_NE(problems.to_string().find("pattern.knit: make_knit_tile: a stitch length of 3"), std::string::npos)
      << problems.to_string();
  EXPECT_FALSE(fs::exists(dir / "tiles")) << "nothing written";
}

TEST(GeneratedPattern, AFabricWithATileIsLeftAlone) {
  ScratchDir dir("generated_pattern_file");
  db::Fabric f = bundled_example();
  const fs::path before = f.pattern->file;
  db::Problems problems;
  EXPECT_TRUE(make_generated_pattern(f, dir / "tiles", problems));
  EXPECT_EQ(f.pattern->file, before);
  EXPECT_FALSE(fs::exists(dir / "tiles"));
}

}  // namespace
}  // namespace yarnfit::calibration
