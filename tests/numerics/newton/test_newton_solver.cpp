// The one Newton solver (numerics/newton/newton_solver.hpp), on small terms with known
// minimisers (tests/support/test_energy_terms.hpp), with the shell's settings (the defaults)
// and with the yarn's (yarn_fit/solver/equilibrium.cpp): convergence, the shift on indefinite
// Hessians, a line search that never leaves the domain, constrained steps, the step-bound
// hook, an indefinite Hessian that the constraints make definite (the inertia test), and
// every failure reported in the summary.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include "numerics/newton/newton_solver.hpp"
#include "numerics/terms/scene.hpp"
#include "tests/support/test_energy_terms.hpp"
#include "tests/expect_error.hpp"

namespace yarnfit::numerics {
namespace {

using testing::DoubleWellTerm;
using testing::NanGradientTerm;
using testing::QuadraticTerm;
using testing::RosenbrockTerm;
using testing::terms_of;
using testing::WallTerm;

// A list of terms as a Newton problem over all of x, with optional constraints and an
// optional cap on the step length (to exercise the step-bound hook).
class TermsProblem final : public NewtonProblem {
 public:
  explicit TermsProblem(TermList terms, int n) : m_terms(std::move(terms)), m_n(n) {}
  [[nodiscard]] int size() const override { return m_n; }
  [[nodiscard]] double energy(const Eigen::VectorXd& x) const override { return total_energy(m_terms, x); }
  double energy_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override {
    g = total_gradient(m_terms, x);
    return total_energy(m_terms, x);
  }
  bool hessian(const Eigen::VectorXd& x, bool project_psd, Triplets& lower, std::string*) const override {
    Triplets all;
    for (const EnergyTerm* t : m_terms) t->add_hessian(x, all, {project_psd, true});
    for (const auto& t : all)
      if (t.row() >= t.col()) lower.push_back(t);
    return true;
  }
  [[nodiscard]] const Eigen::MatrixXd* constraints() const override { return m_c.rows() > 0 ? &m_c : nullptr; }
  [[nodiscard]] StepBound max_step(const Eigen::VectorXd&, const Eigen::VectorXd& dx) const override {
    const double length = dx.lpNorm<Eigen::Infinity>();
    if (m_cap > 0.0 && length > m_cap) return {m_cap / length, true};
    return {};
  }
  void prepare(const Eigen::VectorXd&) override { ++prepared; }
  [[nodiscard]] std::string describe_invalid_energy(const Eigen::VectorXd& x) const override {
    return describe_non_finite_values(m_terms, x);
  }
  [[nodiscard]] std::string describe_invalid_gradient(const Eigen::VectorXd& x) const override {
    return describe_non_finite_gradients(m_terms, x);
  }

  Eigen::MatrixXd m_c;
  double m_cap = 0.0;
  int prepared = 0;

 private:
  TermList m_terms;
  int m_n;
};

TEST(NewtonSolver, QuadraticConvergesInOneStep) {
  const int n = 6;
  Eigen::MatrixXd m = Eigen::MatrixXd::Random(n, n);
  const Eigen::MatrixXd a = m * m.transpose() + n * Eigen::MatrixXd::Identity(n, n);
  const Eigen::VectorXd c = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
  const QuadraticTerm term(a, c);
  TermsProblem problem(terms_of({&term}), n);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  const NewtonSummary s = solve_newton(problem, x, NewtonOptions::for_shell());
  ASSERT_TRUE(s.converged()) << s.brief();
  EXPECT_EQ(s.iterations, 1) << s.brief();
  EXPECT_EQ(s.regularised_steps, 0);
  EXPECT_LT((x - c).lpNorm<Eigen::Infinity>(), 1e-12);
  EXPECT_LE(s.residual, 1e-8);
  EXPECT_GT(s.initial_residual, 1.0);
  EXPECT_NEAR(s.energy, 0.0, 1e-20);
  EXPECT_EQ(problem.prepared, 2) << "prepared before the first iteration and after the step";
  EXPECT_NE(s.brief().find("converged"), std::string::npos) << s.brief();
}

TEST(NewtonSolver, IndefiniteDoubleWellIsSafeguardedByTheShift) {
  // Starting near the maximum at 0, plain Newton would climb to it; the shift must turn the
  // step downhill, and the solver must still end at a true minimum, with either settings.
  const DoubleWellTerm term(0.3);
  for (const bool yarn_like : {false, true}) {
    Eigen::VectorXd x(6);
    x << 0.05, -0.02, 0.01, 0.08, -0.04, 0.0;
    TermsProblem problem(terms_of({&term}), 6);
    NewtonOptions options = yarn_like ? NewtonOptions::for_yarn_tile() : NewtonOptions::for_shell();
    options.tolerance = 1e-12;
    options.policy.project_psd = false;
    const NewtonSummary s = solve_newton(problem, x, options);
    ASSERT_TRUE(s.converged()) << s.brief();
    std::cout << "[ double well" << (yarn_like ? ", yarn settings" : "") << " ] " << s.brief() << "\n";
    EXPECT_GT(s.regularised_steps, 0) << "the start is indefinite: a shift was needed";
    const Eigen::MatrixXd h = Eigen::MatrixXd(total_hessian(terms_of({&term}), x, false));
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(h).eigenvalues().minCoeff(), 0.0)
        << "a minimum, not a saddle: x = " << x.transpose();
    EXPECT_LT(s.energy, term.value(Eigen::VectorXd::Zero(6)));
  }
}

TEST(NewtonSolver, LineSearchNeverStepsIntoTheInfiniteRegion) {
  // The full Newton step from 0 overshoots the wall at 1; only backtracking keeps it valid.
  for (const bool yarn_like : {false, true}) {
    const WallTerm term(1.0, 1e-3, 3.0);
    TermsProblem problem(terms_of({&term}), 3);
    Eigen::VectorXd x = Eigen::VectorXd::Zero(3);
    x(1) = -2.0;
    NewtonOptions options = yarn_like ? NewtonOptions::for_yarn_tile() : NewtonOptions::for_shell();
    options.tolerance = 1e-10;
    const NewtonSummary s = solve_newton(problem, x, options);
    ASSERT_TRUE(s.converged()) << s.brief();
    EXPECT_EQ(term.invalid_derivative_calls(), 0);
    for (Eigen::Index k = 0; k < 3; ++k) EXPECT_NEAR(x(k), term.minimiser(), 1e-10);
  }
}

TEST(NewtonSolver, InvalidStartIsReportedAndLeavesXUnchanged) {
  const WallTerm term(1.0, 1e-3, 3.0);
  TermsProblem problem(terms_of({&term}), 2);
  Eigen::VectorXd x = Eigen::VectorXd::Constant(2, 0.5);
  x(1) = 1.5;
  const Eigen::VectorXd start = x;
  const NewtonSummary s = solve_newton(problem, x, NewtonOptions::for_shell());
  EXPECT_EQ(s.status, NewtonStatus::invalid_start);
  EXPECT_FALSE(s.converged());
  EXPECT_EQ(s.iterations, 0);
  EXPECT_EQ(x, start);
  EXPECT_NE(s.message.find("wall"), std::string::npos) << s.message;
  EXPECT_TRUE(std::isnan(s.residual));
}

TEST(NewtonSolver, MaxIterationsKeepsTheLastValidIterateAndRosenbrockConvergesEitherWay) {
  const RosenbrockTerm term;
  TermsProblem problem(terms_of({&term}), 2);
  Eigen::VectorXd x(2);
  x << -1.2, 1.0;
  NewtonOptions options = NewtonOptions::for_shell();
  options.max_iterations = 3;
  const NewtonSummary s = solve_newton(problem, x, options);
  EXPECT_EQ(s.status, NewtonStatus::max_iterations);
  EXPECT_EQ(s.iterations, 3);
  EXPECT_DOUBLE_EQ(s.energy, term.value(x));
  EXPECT_LT(s.energy, 24.2) << "every accepted step decreased the energy";
  EXPECT_FALSE(s.message.empty());
  for (const bool yarn_like : {false, true}) {
    for (const bool project : {true, false}) {
      x << -1.2, 1.0;
      options = yarn_like ? NewtonOptions::for_yarn_tile() : NewtonOptions::for_shell();
      options.tolerance = 1e-10;
      options.policy.project_psd = project;
      const NewtonSummary full = solve_newton(problem, x, options);
      ASSERT_TRUE(full.converged()) << full.brief();
      std::cout << "[ rosenbrock, " << (yarn_like ? "yarn" : "shell") << " settings, project_psd " << project
                << " ] " << full.brief() << "\n";
      EXPECT_NEAR(x(0), 1.0, 1e-8);
      EXPECT_NEAR(x(1), 1.0, 1e-8);
    }
  }
}

TEST(NewtonSolver, NonFiniteGradientIsReportedNotPassedOn) {
  const NanGradientTerm term;
  TermsProblem problem(terms_of({&term}), 2);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(2);
  const NewtonSummary s = solve_newton(problem, x, NewtonOptions::for_shell());
  EXPECT_EQ(s.status, NewtonStatus::non_finite) << s.brief();
  EXPECT_TRUE(x.allFinite());
  EXPECT_TRUE(std::isfinite(s.energy));
  EXPECT_NE(s.message.find("nan_gradient"), std::string::npos) << s.message;
}

TEST(NewtonSolver, ConstrainedQuadraticReachesTheKktSolutionAndStaysFeasible) {
  // min ½|x − c|² subject to Σx = 0 and x0 − x1 = 0: x = P c with P the projector on the
  // constraints' null space.
  const int n = 5;
  const Eigen::VectorXd c = Eigen::VectorXd::LinSpaced(n, 1.0, 3.0);
  const QuadraticTerm term(Eigen::MatrixXd::Identity(n, n), c);
  TermsProblem problem(terms_of({&term}), n);
  problem.m_c = Eigen::MatrixXd::Zero(2, n);
  problem.m_c.row(0).setOnes();
  problem.m_c(1, 0) = 1.0;
  problem.m_c(1, 1) = -1.0;
  const Eigen::MatrixXd& C = problem.m_c;
  const Eigen::MatrixXd projector =
      Eigen::MatrixXd::Identity(n, n) - C.transpose() * (C * C.transpose()).inverse() * C;
  Eigen::VectorXd x = Eigen::VectorXd::Constant(n, 0.7);  // infeasible start: projected first
  NewtonOptions options = NewtonOptions::for_yarn_tile();  // never below a shift of 1e-10: a few steps
  options.tolerance = 1e-13;
  const NewtonSummary s = solve_newton(problem, x, options);
  ASSERT_TRUE(s.converged()) << s.brief();
  EXPECT_LT((x - projector * c).lpNorm<Eigen::Infinity>(), 1e-12);
  EXPECT_LT((C * x).lpNorm<Eigen::Infinity>(), 1e-14);
  // The residual is the projected gradient: zero at the solution although ∇E = x − c is not.
  EXPECT_LE(s.residual, 1e-8);
  EXPECT_GT((x - c).lpNorm<Eigen::Infinity>(), 0.1);
  EXPECT_LT((projected_gradient(&C, x - c)).lpNorm<Eigen::Infinity>(), 1e-12);
}

TEST(NewtonSolver, StepBoundLimitsEveryStepAndStillConverges) {
  // A cap of 0.1 on every step: from 0 to c (|c|∞ = 2) takes at least 20 steps, each one cut.
  const int n = 3;
  const Eigen::VectorXd c = Eigen::Vector3d(2.0, -1.0, 0.5);
  const QuadraticTerm term(Eigen::MatrixXd::Identity(n, n), c);
  TermsProblem problem(terms_of({&term}), n);
  problem.m_cap = 0.1;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  const NewtonSummary s = solve_newton(problem, x, NewtonOptions::for_shell());
  ASSERT_TRUE(s.converged()) << s.brief();
  EXPECT_GE(s.iterations, 20);
  EXPECT_LE(s.iterations, 22);
  EXPECT_LT((x - c).lpNorm<Eigen::Infinity>(), 1e-9);
}

TEST(NewtonSolver, LooseToleranceEndsASlowSolveVisibly) {
  const RosenbrockTerm term;
  TermsProblem problem(terms_of({&term}), 2);
  problem.m_cap = 1e-3;  // creeping steps
  Eigen::VectorXd x(2);
  x << -1.2, 1.0;
  NewtonOptions options = NewtonOptions::for_yarn_tile();
  options.loose_after = 5;
  options.loose_tolerance = 1e3;
  const NewtonSummary s = solve_newton(problem, x, options);
  EXPECT_EQ(s.status, NewtonStatus::converged_loosely) << s.brief();
  EXPECT_TRUE(s.converged());
  EXPECT_EQ(s.iterations, 5);
  EXPECT_NE(s.message.find("loose"), std::string::npos) << s.message;
}

TEST(NewtonSolver, OptionsListEveryProblem) {
  for (const NewtonOptions& preset :
       {NewtonOptions::for_shell(), NewtonOptions::for_shell_unprojected(), NewtonOptions::for_yarn_tile()})
    EXPECT_TRUE(preset.problems().empty()) << preset.problems().to_string();
  NewtonOptions options = NewtonOptions::for_shell();
  options.policy.shift_growth = 1.0;
  options.policy.armijo = 0.7;
  options.policy.max_line_search_steps = 0;
  const Problems found = options.problems();
  ASSERT_EQ(found.size(), 3u);
  std::vector<std::string> fields;
  for (const auto& p : found.items()) fields.push_back(p.field);
  EXPECT_EQ(fields, (std::vector<std::string>{"NewtonOptions.policy.max_line_search_steps", "NewtonOptions.policy.armijo",
                                              "NewtonOptions.policy.shift_growth"}));
  EXPECT_NE(found.one_line().find("armijo: must be in (0, 0.5)"), std::string::npos) << found.one_line();
  const QuadraticTerm term(Eigen::MatrixXd::Identity(2, 2), Eigen::VectorXd::Zero(2));
  TermsProblem problem(terms_of({&term}), 2);
  Eigen::VectorXd x = Eigen::VectorXd::Ones(2);
  EXPECT_ERROR((void)solve_newton(problem, x, options), yarnfit::ErrorCategory::input);
}


// E = Σ (x_i − c_i)⁶, the order at which a contact barrier (1 − x)⁶ enters: the minimum is
// degenerate and Newton converges only linearly, x − c ← 0.8 (x − c). Its read-out is Σ x_i.
class SixthOrderProblem final : public NewtonProblem {
 public:
  explicit SixthOrderProblem(Eigen::VectorXd c) : m_c(std::move(c)) {}
  [[nodiscard]] int size() const override { return static_cast<int>(m_c.size()); }
  [[nodiscard]] double energy(const Eigen::VectorXd& x) const override { return (x - m_c).array().pow(6).sum(); }
  double energy_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override {
    g = 6.0 * (x - m_c).array().pow(5).matrix();
    return energy(x);
  }
  bool hessian(const Eigen::VectorXd& x, bool, Triplets& lower, std::string*) const override {
    for (int i = 0; i < size(); ++i) lower.emplace_back(i, i, 30.0 * std::pow(x[i] - m_c[i], 4));
    return true;
  }
  bool readout(const Eigen::VectorXd& x, Eigen::VectorXd& values) const override {
    if (!m_readout) return false;
    values = Eigen::VectorXd::Constant(1, x.sum());
    return true;
  }
  Eigen::VectorXd m_c;
  bool m_readout = true;
};

TEST(NewtonSolver, ReadoutTestEndsALinearlyConvergingSolveWithinItsTolerance) {
  const Eigen::VectorXd c = Eigen::Vector2d(0.3, -0.2);
  const double limit = c.sum();
  const double tolerance = 1e-3;
  NewtonOptions options = NewtonOptions::for_yarn_tile();
  options.tolerance = 0.0;  // unreachable: only the read-out test can end the solve
  options.max_iterations = 400;
  options.readout_tolerance = tolerance;
  SixthOrderProblem problem(c);
  Eigen::VectorXd x = c + Eigen::Vector2d(1.0, 0.5);
  const NewtonSummary s = solve_newton(problem, x, options);
  EXPECT_EQ(s.status, NewtonStatus::converged_readout) << s.brief();
  EXPECT_TRUE(s.converged());
  EXPECT_NE(s.message.find("read-out"), std::string::npos) << s.message;
  // The ratio 0.8 is the worst the test allows for: the read-out is within its tolerance of
  // the limit, and not already far inside it (the test stops as soon as it may).
  EXPECT_LE(std::abs(x.sum() - limit), tolerance * (1.0 + 1e-9)) << s.brief();
  EXPECT_GT(std::abs(x.sum() - limit), 0.1 * tolerance) << s.brief();
  EXPECT_LE(s.readout_change, 0.25 * tolerance);
  EXPECT_LT(s.iterations, 60) << s.brief();

  // Without a read-out (or with the test off) the same solve runs to its cap.
  for (const bool test_off : {false, true}) {
    SixthOrderProblem again(c);
    again.m_readout = test_off;  // the test off, or no read-out to test
    NewtonOptions plain = options;
    if (test_off) plain.readout_tolerance = 0.0;
    Eigen::VectorXd y = c + Eigen::Vector2d(1.0, 0.5);
    const NewtonSummary t = solve_newton(again, y, plain);
    EXPECT_FALSE(t.converged()) << t.brief();
    EXPECT_EQ(t.readout_change, 0.0);
  }
  options.readout_steps = 0;
  EXPECT_FALSE(options.problems().empty());
  options.readout_steps = 3;
  options.readout_tolerance = -1.0;
  EXPECT_FALSE(options.problems().empty());
}

}  // namespace
}  // namespace yarnfit::numerics

namespace yarnfit::numerics {
namespace {

// H = Q diag(2, 1, −1) Qᵀ, Q a rotation: indefinite, with its negative direction q2.
Eigen::Matrix3d indefinite_hessian(Eigen::Matrix3d& q) {
  q = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, 2.0, 0.5).normalized()).toRotationMatrix();
  return q * Eigen::Vector3d(2.0, 1.0, -1.0).asDiagonal() * q.transpose();
}

bool factorise(ShiftedLdlt& f, const Eigen::Matrix3d& h, double shift) {
  Triplets lower;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c <= r; ++c) lower.emplace_back(r, c, h(r, c));
  f.assemble(3, lower);
  return f.factorise(shift);
}

TEST(ShiftedLdlt, CountsNegativePivotsAndTellsDefinitenessOnTheConstraintsNullSpace) {
  Eigen::Matrix3d q;
  const Eigen::Matrix3d h = indefinite_hessian(q);
  ShiftedLdlt f;
  EXPECT_FALSE(factorise(f, h, 0.0));
  EXPECT_EQ(f.negative_pivots(), 1);
  // C forbids the negative direction: H is positive definite on C z = 0.
  const Eigen::MatrixXd forbids = q.col(2).transpose();
  EXPECT_TRUE(positive_definite_on_constraints(f, forbids));
  // C forbids a positive direction: q2 stays free, H is not positive definite there.
  const Eigen::MatrixXd keeps = q.col(0).transpose();
  EXPECT_FALSE(positive_definite_on_constraints(f, keeps));
  // The negative and one positive direction forbidden: the free one is positive.
  Eigen::MatrixXd two(2, 3);
  two << q.col(2).transpose(), q.col(0).transpose();
  EXPECT_TRUE(positive_definite_on_constraints(f, two));
  // A definite matrix: no negative pivots.
  // Shifted past the negative eigenvalue (a relative shift of 1.5 / mean |diag|): definite.
  ShiftedLdlt g;
  EXPECT_TRUE(factorise(g, h, 1.5 / f.mean_diagonal()));
  EXPECT_EQ(g.negative_pivots(), 0);
}

// The constrained minimum of ½(x − c)ᵀH(x − c) with H indefinite but positive definite on
// C x = 0: the exact constrained Newton step reaches it at once; shifting H until all of it is
// positive definite (the solver without the inertia test) converges only linearly.
TEST(NewtonSolver, AnIndefiniteHessianDefiniteOnTheConstraintsTakesTheExactStep) {
  Eigen::Matrix3d q;
  const Eigen::Matrix3d h = indefinite_hessian(q);
  const Eigen::Vector3d c(0.3, -0.2, 0.9);
  const QuadraticTerm term(h, c);
  // The minimiser: x − c has no part along q0, q1, and q2·x = 0.
  const Eigen::Vector3d expected = q.col(0) * q.col(0).dot(c) + q.col(1) * q.col(1).dot(c);
  const auto solve = [&](bool accept, Eigen::VectorXd& x) {
    TermsProblem problem(terms_of({&term}), 3);
    problem.m_c = q.col(2).transpose();
    x = Eigen::VectorXd::Zero(3);
    NewtonOptions options = NewtonOptions::for_yarn_tile();
    options.tolerance = 1e-12;
    options.max_iterations = 500;
    options.policy.accept_definite_on_constraints = accept;
    const NewtonSummary s = solve_newton(problem, x, options);
    std::cout << "[ newton  ] " << (accept ? "with" : "without") << " the inertia test: " << s.brief() << "\n";
    return s;
  };
  Eigen::VectorXd x;
  const NewtonSummary exact = solve(true, x);
  EXPECT_TRUE(exact.converged()) << exact.brief();
  EXPECT_LE(exact.iterations, 2);
  EXPECT_LT((x - expected).lpNorm<Eigen::Infinity>(), 1e-12);
  // The shift that makes all of H definite is of the size of its negative eigenvalue, and the
  // step then contracts the error along q0, q1 by only σ/(λ + σ) a step: the creep.
  const NewtonSummary shifted = solve(false, x);
  EXPECT_GT(shifted.iterations, 100) << shifted.brief();
}

}  // namespace
}  // namespace yarnfit::numerics
