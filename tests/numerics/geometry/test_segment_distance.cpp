// Exact segment–segment distances (numerics/geometry/segment_distance.hpp), used by the
// tile facts' R_est and by the yarn contact's collision-free step.

#include <gtest/gtest.h>

#include <cmath>

#include "numerics/geometry/segment_distance.hpp"

namespace yarnfit::numerics {
namespace {

TEST(SegmentDistance, KnownConfigurations) {
  // Skew segments crossing at right angles, 0.3 apart in z.
  EXPECT_DOUBLE_EQ(segment_segment_distance({-1, 0, 0}, {1, 0, 0}, {0, -1, 0.3}, {0, 1, 0.3}), 0.3);
  // Parallel, overlapping in x: the line distance.
  EXPECT_DOUBLE_EQ(segment_segment_distance({0, 0, 0}, {2, 0, 0}, {1, 0.5, 0}, {3, 0.5, 0}), 0.5);
  // Parallel and anti-parallel without overlap: end to end.
  EXPECT_DOUBLE_EQ(segment_segment_distance({0, 0, 0}, {1, 0, 0}, {4, 4, 0}, {2, 4, 0}), std::hypot(1.0, 4.0));
  // Collinear with a gap.
  EXPECT_DOUBLE_EQ(segment_segment_distance({0, 0, 0}, {1, 0, 0}, {1.25, 0, 0}, {3, 0, 0}), 0.25);
  // Closest points of the lines outside both segments: an end point decides.
  EXPECT_DOUBLE_EQ(segment_segment_distance({0, 0, 0}, {1, 0, 0}, {2, 1, 0}, {2, 3, 0}), std::hypot(1.0, 1.0));
  // T: the end of one touches the middle of the other.
  EXPECT_DOUBLE_EQ(segment_segment_distance({0, 0, 0}, {2, 0, 0}, {1, 0, 0}, {1, 5, 0}), 0.0);
  // A degenerate segment is a point.
  EXPECT_DOUBLE_EQ(segment_segment_distance({1, 1, 1}, {1, 1, 1}, {0, 0, 0}, {2, 0, 0}), std::sqrt(2.0));
  // Nearly parallel: no worse than the exact answer (0.5 at the near end) by more than rounding.
  EXPECT_NEAR(segment_segment_distance({0, 0, 0}, {1, 0, 0}, {0, 0.5, 0}, {1, 0.5 + 1e-13, 0}), 0.5, 1e-15);
}

}  // namespace
}  // namespace yarnfit::numerics
