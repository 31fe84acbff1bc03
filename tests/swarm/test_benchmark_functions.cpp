// The benchmark table itself: each known minimiser lies inside the bounds, gives the known
// minimum, and no nearby point is lower (so a typo in a formula or a quoted minimiser
// cannot make the optimiser tests pass or fail for the wrong reason).

#include <gtest/gtest.h>

#include <cmath>

#include "tests/swarm/benchmark_functions.hpp"

namespace yarnfit::swarm::testing {
namespace {

TEST(BenchmarkTable, KnownMinimisersAreLocalMinimaInsideTheBounds) {
  for (const auto& b : benchmark_table()) {
    SCOPED_TRACE(b.name);
    const ParameterSpace space = b.space();
    ASSERT_TRUE(space.contains(b.minimiser));
    EXPECT_NEAR(b.f(b.minimiser), b.minimum, 1e-12);
    for (int i = 0; i < space.dimension(); ++i) {
      for (double h : {-1e-4, 1e-4}) {
        Eigen::VectorXd x = b.minimiser;
        x[i] *= 1.0 + h;
        x[i] += h;
        EXPECT_GE(b.f(x), b.minimum) << "coordinate " << i;
      }
    }
  }
}

}  // namespace
}  // namespace yarnfit::swarm::testing
