// uniform_targets.csv (fabrics_db/targets/uniform_targets.hpp): the writer and the reader
// round-trip, the in-memory copy equals what the file holds bit for bit, and the reader's
// problems name file:line: field.
#include <gtest/gtest.h>

#include <cstring>
#include <stdexcept>

#include "fabrics_db/targets/uniform_targets.hpp"
#include "tests/test_support.hpp"
#include "tests/expect_error.hpp"

namespace yarnfit::db {
namespace {

using testing::read_file;
using testing::ScratchDir;
using testing::write_file;

const char* k_header = "direction,kind,stretch,compression,stress_s_N_per_m,curvature_per_m,stress_kappa_N\n";

TEST(UniformTargets, WriterAndReaderRoundTrip) {
  ScratchDir dir("calib_reader");
  std::vector<DirectionTargets> in(2);
  in[0].direction = Direction::weft;
  in[0].stretch = {{0.0, 0.0, 0.0, true}, {0.1, 0.05, 3.5, true}, {0.2, 0.09, 9.25, true}};
  in[0].bending = {{10.0, 1e-5}, {20.0, 2e-5}};
  in[1].direction = Direction::warp;
  in[1].stretch = {{0.0, 0.0, 0.0, true}, {0.3, 0.1, 40.0, true}};
  write_uniform_targets_csv(in, dir / "t.csv");
  const auto out = read_uniform_targets(dir / "t.csv");
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].direction, Direction::weft);
  ASSERT_EQ(out[0].stretch.size(), 3u);
  EXPECT_DOUBLE_EQ(out[0].stretch[2].stress, 9.25);
  EXPECT_DOUBLE_EQ(out[0].stretch[1].compression, 0.05);
  ASSERT_EQ(out[0].bending.size(), 2u);
  EXPECT_DOUBLE_EQ(out[0].bending[1].stress, 2e-5);
  EXPECT_EQ(out[1].direction, Direction::warp);
  EXPECT_EQ(find_direction(out, Direction::bias), nullptr);
  ASSERT_NE(find_direction(out, Direction::warp), nullptr);
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Numbers the file cannot hold exactly (more than its 10 digits): as_stored gives the values
// the reader returns from the written file, bit for bit, so a fit on targets handed over in
// memory is the fit on the file. Writing the stored values again gives the same text.
TEST(UniformTargets, AsStoredEqualsTheFileReadBack) {
  ScratchDir dir("targets_stored");
  std::vector<DirectionTargets> in(1);
  in[0].direction = Direction::bias;
  in[0].stretch = {{0.0, 0.0, 1.234567890123e-17, true},
                   {1.0 / 3.0, 0.0123456789012345, 2.0 / 7.0, false},
                   {0.7, 0.1 + 0.2, 33.33333333333333, true}};
  in[0].bending = {{1.0 / 9.0, 4.4444444444444e-7}};
  write_uniform_targets_csv(in, dir / "t.csv");
  const auto back = read_uniform_targets(dir / "t.csv");
  const auto stored = as_stored(in);
  ASSERT_EQ(back.size(), 1u);
  ASSERT_EQ(stored.size(), 1u);
  ASSERT_EQ(back[0].stretch.size(), stored[0].stretch.size());
  for (std::size_t i = 0; i < back[0].stretch.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_TRUE(same_bits(stored[0].stretch[i].stretch, back[0].stretch[i].stretch));
    EXPECT_TRUE(same_bits(stored[0].stretch[i].compression, back[0].stretch[i].compression));
    EXPECT_TRUE(same_bits(stored[0].stretch[i].stress, back[0].stretch[i].stress));
    EXPECT_EQ(stored[0].stretch[i].converged, in[0].stretch[i].converged);
  }
  EXPECT_FALSE(same_bits(stored[0].stretch[1].stretch, in[0].stretch[1].stretch)) << "1/3 has more than 10 digits";
  EXPECT_TRUE(same_bits(stored[0].bending[0].curvature, back[0].bending[0].curvature));
  EXPECT_TRUE(same_bits(stored[0].bending[0].stress, back[0].bending[0].stress));
  EXPECT_EQ(uniform_targets_csv(stored), read_file(dir / "t.csv"));
}

std::string problems_of(const std::string& text, ScratchDir& dir) {
  const auto file = dir / "bad.csv";
  write_file(file, text);
  Problems problems;
  EXPECT_FALSE(read_uniform_targets(file, problems).has_value());
  EXPECT_ERROR((void)read_uniform_targets(file), yarnfit::ErrorCategory::input);
  return problems.to_string();
}

TEST(UniformTargets, ReaderProblemsNameFileLineAndField) {
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

  Problems problems;
  EXPECT_FALSE(read_uniform_targets(dir / "missing.csv", problems).has_value());
  EXPECT_NE(problems.to_string().find("missing.csv"), std::string::npos);
}

}  // namespace
}  // namespace yarnfit::db
