// Chord Newton for a few costly unknowns (the rest-shape heuristic's period chord steps).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <stdexcept>

#include "numerics/roots/chord_newton.hpp"
#include "tests/expect_error.hpp"

namespace yarnfit::numerics {
namespace {

// F(x) = A x + c x³ (componentwise) − b, counting evaluations and the kept points.
class CubicProblem final : public ChordNewtonProblem {
 public:
  bool evaluate(const Eigen::VectorXd& x, Eigen::VectorXd& f) override {
    ++evaluations;
    last = x;
    if (fail_beyond > 0 && x.cwiseAbs().maxCoeff() > fail_beyond) return false;
    f = a * x + c * x.array().cube().matrix() - b;
    return true;
  }
  void keep() override {
    ++kept;
    best = last;
  }
  Eigen::Matrix2d a = (Eigen::Matrix2d() << 2.0, 0.5, 0.3, 1.0).finished();
  Eigen::Vector2d b = Eigen::Vector2d(0.02, -0.01);
  double c = 5.0;
  double fail_beyond = 0.0;
  int evaluations = 0, kept = 0;
  Eigen::VectorXd last, best;
};

TEST(ChordNewton, StepsTowardsTheRootAndReturnsTheBestPoint) {
  CubicProblem problem;
  ChordNewtonOptions options;
  options.steps = 6;
  const Eigen::VectorXd x0 = Eigen::VectorXd::Zero(2);
  Eigen::VectorXd f0;
  ASSERT_TRUE(problem.evaluate(x0, f0));
  problem.evaluations = 0;
  const ChordNewtonResult r = chord_newton(problem, x0, f0, options);
  EXPECT_EQ(r.status, ChordNewtonStatus::done);
  EXPECT_EQ(r.evaluations, 2 + 6);
  EXPECT_EQ(problem.evaluations, 8);
  EXPECT_GT(problem.kept, 0);
  EXPECT_EQ(problem.best, r.x);
  // A chord step contracts the residual linearly: six steps from 0.02 leave far less.
  EXPECT_LT(r.f.cwiseAbs().maxCoeff(), 1e-6 * f0.cwiseAbs().maxCoeff());
  Eigen::VectorXd check;
  ASSERT_TRUE(problem.evaluate(r.x, check));
  EXPECT_EQ(check, r.f);
}

TEST(ChordNewton, ClampsToTheBoxAndStopsAtAFailedEvaluation) {
  CubicProblem problem;
  problem.b = Eigen::Vector2d(10.0, 0.0);  // the root lies far outside the box
  ChordNewtonOptions options;
  options.max_abs = 0.1;
  const Eigen::VectorXd x0 = Eigen::VectorXd::Zero(2);
  Eigen::VectorXd f0;
  ASSERT_TRUE(problem.evaluate(x0, f0));
  const ChordNewtonResult r = chord_newton(problem, x0, f0, options);
  EXPECT_LE(r.x.cwiseAbs().maxCoeff(), 0.1);
  EXPECT_DOUBLE_EQ(r.x.cwiseAbs().maxCoeff(), 0.1);

  CubicProblem failing;
  failing.fail_beyond = 0.05;  // the differences work, every step fails
  failing.b = Eigen::Vector2d(10.0, 0.0);
  ASSERT_TRUE(failing.evaluate(x0, f0));
  failing.evaluations = 0;
  const ChordNewtonResult s = chord_newton(failing, x0, f0, options);
  EXPECT_EQ(s.status, ChordNewtonStatus::done);
  EXPECT_EQ(failing.evaluations, 3) << "two differences, then the first step fails and ends it";
  EXPECT_EQ(failing.kept, 0);
  EXPECT_EQ(s.x, x0);
  EXPECT_EQ(s.f, f0);
}

TEST(ChordNewton, ASingularOrFailedJacobianReturnsTheStart) {
  CubicProblem problem;
  problem.a.setZero();
  problem.c = 0.0;  // F constant: J = 0
  const Eigen::VectorXd x0 = Eigen::VectorXd::Zero(2);
  Eigen::VectorXd f0;
  ASSERT_TRUE(problem.evaluate(x0, f0));
  const ChordNewtonResult r = chord_newton(problem, x0, f0, ChordNewtonOptions{});
  EXPECT_EQ(r.status, ChordNewtonStatus::jacobian_failed);
  EXPECT_EQ(r.x, x0);

  CubicProblem failing;
  failing.fail_beyond = 1e-4;  // below the difference step
  ASSERT_TRUE(failing.evaluate(x0, f0));
  EXPECT_EQ(chord_newton(failing, x0, f0, ChordNewtonOptions{}).status, ChordNewtonStatus::jacobian_failed);
}

TEST(ChordNewton, OptionsNameEveryProblem) {
  ChordNewtonOptions options;
  EXPECT_TRUE(options.problems().empty());
  options.steps = -1;
  options.max_abs = 0.0;
  options.jacobian_step = -1.0;
  EXPECT_EQ(options.problems().size(), 3u) << options.problems().to_string();
  CubicProblem problem;
  EXPECT_ERROR((void)chord_newton(problem, Eigen::VectorXd::Zero(2), Eigen::VectorXd::Zero(2), options),
               yarnfit::ErrorCategory::input);
  EXPECT_ERROR((void)chord_newton(problem, Eigen::VectorXd::Zero(2), Eigen::VectorXd::Zero(3), ChordNewtonOptions{}), yarnfit::ErrorCategory::input);
}

}  // namespace
}  // namespace yarnfit::numerics
