// The map between the caller's parameters and the optimisers' unit cube, and the messages
// for invalid bounds.

#include <gtest/gtest.h>

#include <cmath>

#include "swarm/parameter_space.hpp"
#include "tests/expect_error.hpp"

namespace yarnfit::swarm {
namespace {

std::string message_of(std::vector<Parameter> ps) {
  try {
    (void)ParameterSpace(std::move(ps));
  } catch (const yarnfit::Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(ParameterSpace, LinearAndLogCoordinatesMapToTheUnitCube) {
  const ParameterSpace space({{"ks1", 2.0, 6.0, false}, {"kb", 1e-3, 1e3, true}});
  const Eigen::VectorXd x = space.from_unit(Eigen::Vector2d(0.25, 0.5));
  EXPECT_DOUBLE_EQ(x[0], 3.0);
  EXPECT_NEAR(x[1], 1.0, 1e-14);  // halfway in log space: the geometric mean
  EXPECT_TRUE(space.to_unit(x).isApprox(Eigen::Vector2d(0.25, 0.5), 1e-14));
  // The ends of the unit cube give the bounds exactly, and outside it is clamped.
  EXPECT_EQ(space.from_unit(Eigen::Vector2d(0.0, 1.0)), Eigen::Vector2d(2.0, 1e3));
  EXPECT_EQ(space.from_unit(Eigen::Vector2d(-0.5, 1.5)), Eigen::Vector2d(2.0, 1e3));
  for (double u = 0.0; u <= 1.0; u += 1.0 / 64) {
    EXPECT_TRUE(space.contains(space.from_unit(Eigen::Vector2d(u, u))));
  }
  EXPECT_EQ(space.label(1), "'kb' (parameter 1)");
}

TEST(ParameterSpace, InvalidBoundsNameTheParameterAndField) {
  EXPECT_EQ(message_of({{"R1", 1.0, 1.0, false}}),
            "parameter space: 'R1' (parameter 0): lower (1) must be below upper (1)");
  EXPECT_EQ(message_of({{"a", 0.0, 1.0, false}, {"kc1", 0.0, 100.0, true}}),
            "parameter space: 'kc1' (parameter 1): log_space needs lower > 0 (lower is 0)");
  EXPECT_NE(message_of({{"", -INFINITY, 1.0, false}}).find("'x[0]' (parameter 0): lower is not finite"),
            std::string::npos);
  EXPECT_NE(message_of({{"", 0.0, NAN, false}}).find("upper is not finite"), std::string::npos);
  EXPECT_NE(message_of({}).find("no parameters"), std::string::npos);
}

TEST(ParameterSpace, PointsOutsideTheBoundsAreRejectedByName) {
  const ParameterSpace space({{"eps_s", 0.0, 0.15, false}});
  try {
    (void)space.to_unit(Eigen::VectorXd::Constant(1, 0.2));
    FAIL() << "no error";
  } catch (const yarnfit::Error& e) {
    EXPECT_STREQ(e.what(), "'eps_s' (parameter 0) = 0.2 is outside its bounds [0, 0.15]");
  }
  EXPECT_ERROR((void)space.to_unit(Eigen::VectorXd::Constant(1, NAN)), yarnfit::ErrorCategory::input);
  EXPECT_ERROR((void)space.to_unit(Eigen::VectorXd::Zero(2)), yarnfit::ErrorCategory::input);
}


// Each coordinate outside its bounds is named once, in order; a point inside gives nothing.
TEST(ParameterSpace, BoundsProblemsNameEveryCoordinateOutside) {
  const ParameterSpace space({{"ks1", 0.1, 10.0, true}, {"", 0.0, 1.0, false}, {"R1", 1.0, 2.0, false}});
  EXPECT_TRUE(space.bounds_problems(Eigen::Vector3d(1.0, 0.5, 1.5)).empty());
  const auto p = space.bounds_problems(Eigen::Vector3d(20.0, 0.5, 0.5));
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[0], "ks1: 20 is outside the search bounds [0.1, 10]");
  EXPECT_EQ(p[1], "R1: 0.5 is outside the search bounds [1, 2]");
  EXPECT_EQ(space.bounds_problems(Eigen::Vector3d(0.5, -1.0, 1.0)).front(), "x[1]: -1 is outside the search bounds [0, 1]");
  EXPECT_ERROR((void)space.bounds_problems(Eigen::Vector2d(1.0, 0.5)), yarnfit::ErrorCategory::input);
}

}  // namespace
}  // namespace yarnfit::swarm
