// uniform_targets.csv reader: round trip with shell_fit's writer, and problems that name
// file:line: field.
#include <gtest/gtest.h>

#include <stdexcept>

#include "calibration/targets/uniform_targets_reader.hpp"
#include "tests/test_support.hpp"

namespace yarnfit::calibration {
namespace {

using testing::ScratchDir;
using testing::write_file;

const char* k_header = "direction,kind,stretch,compression,stress_s_N_per_m,curvature_per_m,stress_kappa_N\n";

TEST(UniformTargetsReader, RoundTripsShellWriter) {
  ScratchDir dir("calib_reader");
  std::vector<DirectionTargets> in(2);
  in[0].direction = db::Direction::weft;
  in[0].stretch = {{0.0, 0.0, 0.0, true}, {0.1, 0.05, 3.5, true}, {0.2, 0.09, 9.25, true}};
  in[0].bending = {{10.0, 1e-5}, {20.0, 2e-5}};
  in[1].direction = db::Direction::warp;
  in[1].stretch = {{0.0, 0.0, 0.0, true}, {0.3, 0.1, 40.0, true}};
  shell::write_uniform_targets_csv(in, dir / "t.csv");
  const auto out = read_uniform_targets(dir / "t.csv");
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].direction, db::Direction::weft);
  ASSERT_EQ(out[0].stretch.size(), 3u);
  EXPECT_DOUBLE_EQ(out[0].stretch[2].stress, 9.25);
  EXPECT_DOUBLE_EQ(out[0].stretch[1].compression, 0.05);
  ASSERT_EQ(out[0].bending.size(), 2u);
  EXPECT_DOUBLE_EQ(out[0].bending[1].stress, 2e-5);
  EXPECT_EQ(out[1].direction, db::Direction::warp);
  EXPECT_EQ(find_direction(out, db::Direction::bias), nullptr);
  ASSERT_NE(find_direction(out, db::Direction::warp), nullptr);
}

std::string problems_of(const std::string& text, ScratchDir& dir) {
  const auto file = dir / "bad.csv";
  write_file(file, text);
  db::Problems problems;
  EXPECT_FALSE(read_uniform_targets(file, problems).has_value());
  EXPECT_THROW((void)read_uniform_targets(file), std::invalid_argument);
  return problems.to_string();
}

TEST(UniformTargetsReader, ProblemsNameFileLineAndField) {
  ScratchDir dir("calib_reader_bad");
  const std::string f = (dir / "bad.csv").string();
  std::string p = problems_of(std::string(k_header) +
                                  "weft,stretch,0,0,0,,\n"
                                  "weft,stretch,0.1,nan,2,,\n"   // line 3
                                  "diagonal,stretch,0.1,0,2,,\n"  // line 4
                                  "weft,stretch,0,0.01,1,,\n"     // line 5: not increasing
                                  "weft,twist,0.3,0,1,,\n"        // line 6
                                  "warp,stretch,0.1,0,abc,,\n"    // line 7
                                  "bias,bending,,,,x,1\n",        // line 8
                              dir);
  EXPECT_NE(p.find(f + ":3: compression:"), std::string::npos) << p;
  EXPECT_NE(p.find(f + ":4: direction: unknown direction 'diagonal'"), std::string::npos) << p;
  EXPECT_NE(p.find(f + ":5: stretch:"), std::string::npos) << p;
  EXPECT_NE(p.find(f + ":6: kind: unknown kind 'twist'"), std::string::npos) << p;
  EXPECT_NE(p.find(f + ":7: stress_s_N_per_m:"), std::string::npos) << p;
  EXPECT_NE(p.find(f + ":8: curvature_per_m:"), std::string::npos) << p;

  p = problems_of("direction,kind,stretch,stress_s_N_per_m\nweft,stretch,0,0\n", dir);
  EXPECT_NE(p.find(f + ":1: compression: missing column"), std::string::npos) << p;

  p = problems_of(std::string(k_header) + "weft,stretch,0,0,0,,\n", dir);
  EXPECT_NE(p.find("at least 2"), std::string::npos) << p;

  db::Problems problems;
  EXPECT_FALSE(read_uniform_targets(dir / "missing.csv", problems).has_value());
  EXPECT_NE(problems.to_string().find("missing.csv"), std::string::npos);
}

}  // namespace
}  // namespace yarnfit::calibration
