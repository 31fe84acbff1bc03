// Newton for a few costly unknowns (the yarn tile's rest-period relaxation), on functions
// whose Hessian it only gets as differences of the gradient, as that relaxation does.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <stdexcept>

#include "numerics/newton/few_dof_newton.hpp"
#include "tests/expect_error.hpp"

namespace yarnfit::numerics {
namespace {

// f(x) = ½ xᵀA x − bᵀx + ¼ c Σ x_i⁴ + d Σ cos(x_i) (d > 1 makes it non-convex near 0), its
// residual ‖∇f‖∞ / tolerance; the Hessian by forward differences of ∇f, as a caller with
// only values and gradients would take it.
template <int N>
class TestFunction final : public FewDofProblem<N> {
 public:
  using Vector = typename FewDofProblem<N>::Vector;
  using Matrix = typename FewDofProblem<N>::Matrix;
  explicit TestFunction(int n) : a(Matrix::Identity(n, n)), b(Vector::Zero(n)) {}

  bool evaluate(const Vector& x, FewDofPoint<N>& at) override {
    ++evaluations;
    if (fail_beyond > 0.0 && x.cwiseAbs().maxCoeff() > fail_beyond) return false;
    at.value = value(x);
    at.gradient = gradient(x);
    at.residual = at.gradient.cwiseAbs().maxCoeff() / tolerance;
    m_last = x;
    return true;
  }
  void accept() override {
    ++accepted;
    current = m_last;
  }
  bool hessian(const Vector& x, const FewDofPoint<N>& at, Matrix& h) override {
    EXPECT_EQ(x, current) << "the Hessian is asked at the accepted point";
    h.resize(x.size(), x.size());
    for (Eigen::Index k = 0; k < x.size(); ++k) {
      Vector probe = x;
      probe[k] += 1e-7;
      h.col(k) = (gradient(probe) - at.gradient) / 1e-7;
    }
    return true;
  }

  [[nodiscard]] double value(const Vector& x) const {
    return 0.5 * x.dot(a * x) - b.dot(x) + 0.25 * c * x.array().pow(4).sum() + d * x.array().cos().sum();
  }
  [[nodiscard]] Vector gradient(const Vector& x) const {
    return a * x - b + (c * x.array().cube() - d * x.array().sin()).matrix();
  }

  Matrix a;
  Vector b;
  double c = 1.0, d = 0.0, tolerance = 1e-10, fail_beyond = 0.0;
  int evaluations = 0, accepted = 0;
  Vector current;

 private:
  Vector m_last;
};

template <int N>
void expect_converges_from(TestFunction<N>& f, typename TestFunction<N>::Vector x, int max_steps) {
  FewDofNewtonOptions options;
  options.max_step = 0.5;
  const FewDofNewtonResult<N> r = minimise_few_dofs(f, x, options);
  ASSERT_EQ(r.status, FewDofNewtonStatus::converged) << to_string(r.status) << " after " << r.steps;
  EXPECT_LE(r.steps, max_steps);
  EXPECT_LE(f.gradient(x).cwiseAbs().maxCoeff(), f.tolerance);
  EXPECT_EQ(x, f.current) << "x is the last accepted point";
  EXPECT_EQ(r.at.value, f.value(x));
  EXPECT_EQ(f.accepted, r.steps + 1) << "the start and every step";
}

TEST(FewDofNewton, ConvergesOnAConvexFunctionFixedSizeAndDynamic) {
  TestFunction<2> fixed(2);
  fixed.a << 3.0, 1.0, 1.0, 2.0;
  fixed.b << 1.0, -2.0;
  expect_converges_from(fixed, Eigen::Vector2d(0.3, 0.4), 12);

  TestFunction<Eigen::Dynamic> dynamic(3);
  dynamic.b = Eigen::Vector3d(1.0, -2.0, 0.5);
  expect_converges_from(dynamic, Eigen::VectorXd::Zero(3), 12);
}

TEST(FewDofNewton, ShiftsANonConvexStartDownhillToAMinimum) {
  // f = ½x² + ¼x⁴ + 2 cos x near 0: f'' = 1 + 3x² − 2 cos x < 0 there, so the Newton step
  // would climb to the maximum at 0; the shifted one goes down to a minimum at ±x*.
  TestFunction<2> f(2);
  f.d = 2.0;
  f.a.setIdentity();
  Eigen::Vector2d x(0.05, -0.02);
  const double start = f.value(x);
  FewDofNewtonOptions options;
  options.max_step = 0.5;
  const FewDofNewtonResult<2> r = minimise_few_dofs(f, x, options);
  ASSERT_EQ(r.status, FewDofNewtonStatus::converged) << to_string(r.status);
  EXPECT_LT(r.at.value, start);
  for (int i = 0; i < 2; ++i) {
    const double curvature = 1.0 + 3.0 * x[i] * x[i] - 2.0 * std::cos(x[i]);
    EXPECT_GT(curvature, 0.0) << "a minimum, not the maximum at 0: x = " << x.transpose();
  }
}

TEST(FewDofNewton, StepsAreCappedAndFailuresReported) {
  TestFunction<2> far(2);
  far.b << 10.0, 0.0;  // the minimum near x0 = 2.0: many capped steps of 0.05
  Eigen::Vector2d x = Eigen::Vector2d::Zero();
  FewDofNewtonOptions options;
  options.max_steps = 5;
  FewDofNewtonResult<2> r = minimise_few_dofs(far, x, options);
  EXPECT_EQ(r.status, FewDofNewtonStatus::max_steps);
  EXPECT_EQ(r.steps, 5);
  EXPECT_NEAR(x[0], 5 * 0.05, 1e-12);

  TestFunction<2> walled(2);
  walled.b << 10.0, 0.0;
  walled.fail_beyond = 1e-4;  // every trial step fails (the last is 0.05 / 64)
  x.setZero();
  r = minimise_few_dofs(walled, x, FewDofNewtonOptions{});
  EXPECT_EQ(r.status, FewDofNewtonStatus::no_descent);
  EXPECT_EQ(r.steps, 0);
  EXPECT_EQ(walled.evaluations, 1 + 7) << "the start, then d, d/2, …, d/64";
  EXPECT_EQ(x, Eigen::Vector2d::Zero());

  x.setConstant(1.0);
  r = minimise_few_dofs(walled, x, FewDofNewtonOptions{});
  EXPECT_EQ(r.status, FewDofNewtonStatus::evaluation_failed);
}

TEST(FewDofNewton, OptionsNameEveryProblem) {
  FewDofNewtonOptions options;
  EXPECT_TRUE(options.problems().empty());
  options.max_step = 0.0;
  options.armijo = 0.5;
  EXPECT_EQ(options.problems().size(), 2u) << options.problems().to_string();
  TestFunction<2> f(2);
  Eigen::Vector2d x = Eigen::Vector2d::Zero();
  EXPECT_ERROR((void)minimise_few_dofs(f, x, options), yarnfit::ErrorCategory::input);
}

}  // namespace
}  // namespace yarnfit::numerics
