// Static equilibrium of shell scenes (shell_fit/solver/static_equilibrium.hpp): the one
// Newton solver over the free DOFs with the clamped ones held exactly, clamp reactions and
// their sign, buckling under compression, and load continuation, on small terms with known
// equilibria (tests/support/test_energy_terms.hpp) and on stretched membranes.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <iostream>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "numerics/util/clock.hpp"
#include "shell_fit/energies/membrane_term.hpp"
#include "shell_fit/mesh/rect_mesh.hpp"
#include "shell_fit/solver/static_equilibrium.hpp"
#include "tests/support/test_energy_terms.hpp"
#include "tests/expect_error.hpp"

namespace yarnfit::shell {
namespace {

using testing::BarrierChainTerm;
using testing::QuadraticTerm;
using testing::SpringTerm;
using testing::terms_of;

TEST(StaticEquilibrium, FixedDofsKeepTheirValuesExactly) {
  // The quadratic pulls every coordinate to c; fixing some leaves a smaller system whose
  // solution is the Schur complement: x_f = c_f − A_ff⁻¹ A_fc (x_c − c_c).
  const int n = 5;
  Eigen::MatrixXd a = Eigen::MatrixXd::Identity(n, n) * 4.0;
  for (int i = 0; i + 1 < n; ++i) a(i, i + 1) = a(i + 1, i) = -1.0;
  const Eigen::VectorXd c = Eigen::VectorXd::Ones(n);
  const QuadraticTerm term(a, c);
  Eigen::VectorXd x(n);
  x << 0.123456789, 0.0, -7.5, 0.0, 0.0;
  const Eigen::VectorXd start = x;
  const std::vector<int> fixed = {0, 2, 2};  // duplicates allowed
  const NewtonSummary s = solve_static(terms_of({&term}), x, fixed, NewtonOptions::for_shell());
  ASSERT_TRUE(s.converged()) << s.brief();
  EXPECT_EQ(x(0), start(0));
  EXPECT_EQ(x(2), start(2));
  const std::vector<int> f = {1, 3, 4};
  const std::vector<int> cdofs = {0, 2};
  const Eigen::MatrixXd aff = a(f, f);
  const Eigen::VectorXd expected = c(f) - aff.ldlt().solve(a(f, cdofs) * (x(cdofs) - c(cdofs)));
  EXPECT_LT((x(f) - expected).lpNorm<Eigen::Infinity>(), 1e-12);
  EXPECT_ERROR((void)solve_static(terms_of({&term}), x, {n}, NewtonOptions::for_shell()),
               yarnfit::ErrorCategory::input);
}

TEST(StaticEquilibrium, SpringChainReachesKnownEquilibriumAndClampReactionsHaveTheDocumentedSign) {
  // A chain of springs in 2-D between ends fixed at (0,0) and (D,0), in series: tension
  // T = (D − ΣL)/Σ(1/k), each spring at L + T/k. Start with a transverse zig-zag.
  const std::vector<double> k = {1.0, 2.0, 4.0, 0.5, 3.0};
  const std::vector<double> rest = {1.0, 0.5, 1.5, 1.0, 0.8};
  const int n = static_cast<int>(k.size());
  std::vector<SpringTerm::Spring> springs;
  for (int i = 0; i < n; ++i) springs.push_back({i, i + 1, k[i], rest[i]});
  const SpringTerm term(springs, 2);
  const double span = 7.0;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(2 * (n + 1));
  for (int v = 0; v <= n; ++v) {
    x(2 * v) = span * v / n;
    x(2 * v + 1) = (v == 0 || v == n) ? 0.0 : 0.3 * (v % 2 == 0 ? 1 : -1);
  }
  const std::vector<int> fixed = vertex_dofs({0, n}, 2);
  NewtonOptions options = NewtonOptions::for_shell();
  options.tolerance = 1e-12;
  const NewtonSummary s = solve_static(terms_of({&term}), x, fixed, options);
  ASSERT_TRUE(s.converged()) << s.brief();
  std::cout << "[ spring chain ] " << s.brief() << "\n";
  double sum_rest = 0.0, compliance = 0.0;
  for (int i = 0; i < n; ++i) {
    sum_rest += rest[i];
    compliance += 1.0 / k[i];
  }
  const double tension = (span - sum_rest) / compliance;
  double expected_x = 0.0;
  for (int i = 0; i < n; ++i) {
    expected_x += rest[i] + tension / k[i];
    EXPECT_NEAR(x(2 * (i + 1)), expected_x, 1e-10);
    EXPECT_NEAR(x(2 * (i + 1) + 1), 0.0, 1e-10);
  }
  // The right clamp pulls the chain towards +x with the tension, the left one towards −x.
  EXPECT_NEAR(clamp_force(terms_of({&term}), x, {n}, 2, 0), tension, 1e-10);
  EXPECT_NEAR(clamp_force(terms_of({&term}), x, {0}, 2, 0), -tension, 1e-10);
  const Eigen::VectorXd r = clamp_reaction(terms_of({&term}), x, vertex_dofs({n}, 2));
  EXPECT_NEAR(r(0), tension, 1e-10);
  EXPECT_NEAR(r(1), 0.0, 1e-10);
}

TEST(StaticEquilibrium, CompressedSpringChainBucklesWithAndWithoutProjection) {
  // Ends pushed together to half the rest length: the straight chain is a saddle, and every
  // minimum (energy 0) has all springs at rest length.
  const int n = 8;
  std::vector<SpringTerm::Spring> springs;
  for (int i = 0; i < n; ++i) springs.push_back({i, i + 1, 10.0, 1.0});
  const SpringTerm term(springs, 2);
  for (const bool project : {true, false}) {
    Eigen::VectorXd x = Eigen::VectorXd::Zero(2 * (n + 1));
    for (int v = 0; v <= n; ++v) {
      x(2 * v) = 0.5 * v;
      x(2 * v + 1) = (v == 0 || v == n) ? 0.0 : 1e-3 * std::sin(1.3 * v);
    }
    NewtonOptions options = NewtonOptions::for_shell();
    options.tolerance = 1e-10;
    options.policy.project_psd = project;
    const NewtonSummary s = solve_static(terms_of({&term}), x, vertex_dofs({0, n}, 2), options);
    ASSERT_TRUE(s.converged()) << "project_psd " << project << ": " << s.brief();
    std::cout << "[ buckling chain, project_psd " << project << " ] " << s.brief() << "\n";
    EXPECT_LT(s.energy, 1e-18);
    for (int i = 0; i < n; ++i) {
      EXPECT_NEAR((x.segment<2>(2 * i + 2) - x.segment<2>(2 * i)).norm(), 1.0, 1e-9);
    }
    EXPECT_EQ(x(2 * n), 0.5 * n);
  }
}

TEST(StaticEquilibrium, RejectsInvalidOptionsAndArguments) {
  NewtonOptions options = NewtonOptions::for_shell();
  EXPECT_TRUE(options.problems().empty()) << options.problems().to_string();
  options.policy.shift_growth = 1.0;
  EXPECT_FALSE(options.problems().empty());
  EXPECT_NE(options.problems().to_string().find("shift_growth"), std::string::npos) << options.problems().to_string();
  const QuadraticTerm term(Eigen::MatrixXd::Identity(2, 2), Eigen::VectorXd::Zero(2));
  Eigen::VectorXd x = Eigen::VectorXd::Ones(2);
  EXPECT_ERROR((void)solve_static(terms_of({&term}), x, {}, options), yarnfit::ErrorCategory::input);
  EXPECT_ERROR((void)solve_static({}, x, {}, NewtonOptions::for_shell()), yarnfit::ErrorCategory::input);
  EXPECT_ERROR((void)solve_static(terms_of({nullptr}), x, {}, NewtonOptions::for_shell()), yarnfit::ErrorCategory::input);
  ContinuationOptions copt;
  EXPECT_TRUE(copt.problems().empty()) << copt.problems().to_string();
  copt.min_step = 0.0;
  copt.newton.tolerance = -1.0;
  const std::string why = copt.problems().to_string();
  EXPECT_NE(why.find("ContinuationOptions.min_step: must be positive"), std::string::npos) << why;
  EXPECT_NE(why.find("ContinuationOptions.newton.tolerance: "), std::string::npos) << why;
}

TEST(StaticEquilibrium, AllFixedIsConvergedAtOnce) {
  const QuadraticTerm term(Eigen::MatrixXd::Identity(2, 2), Eigen::VectorXd::Zero(2));
  Eigen::VectorXd x = Eigen::VectorXd::Ones(2);
  const NewtonSummary s = solve_static(terms_of({&term}), x, {0, 1}, NewtonOptions::for_shell());
  EXPECT_TRUE(s.converged());
  EXPECT_EQ(s.iterations, 0);
  EXPECT_EQ(x, Eigen::VectorXd::Ones(2));
}

TEST(Continuation, CompressingABarrierChainNeedsCutBacks) {
  // Push the right end of a 10-segment chain from x = 10 to x = 2. In one step, the right end
  // passes its neighbour (an inverted element): the start is invalid. Continuation halves the
  // load step until the move is admissible, then walks on.
  const int segments = 10;
  const BarrierChainTerm term(segments, 1.0, 0.1, 1.0);
  const auto rest = Eigen::VectorXd::LinSpaced(segments + 1, 0.0, 10.0);
  const std::vector<int> fixed = {0, segments};
  const auto set_boundary = [&](double lambda, Eigen::VectorXd& x) {
    x(segments) = 10.0 - 8.0 * lambda;
  };

  Eigen::VectorXd one_step = rest;
  set_boundary(1.0, one_step);
  const NewtonSummary direct = solve_static(terms_of({&term}), one_step, fixed, NewtonOptions::for_shell());
  EXPECT_FALSE(direct.converged());
  EXPECT_EQ(direct.status, NewtonStatus::invalid_start) << direct.brief();

  Eigen::VectorXd x = rest;
  ContinuationOptions options;
  options.initial_step = 0.5;
  options.newton.tolerance = 1e-10;
  const NewtonSummary s = solve_continuation(terms_of({&term}), x, fixed, set_boundary, options);
  ASSERT_TRUE(s.converged()) << s.brief();
  std::cout << "[ barrier chain continuation ] " << s.brief() << "\n";
  EXPECT_GT(s.cut_backs, 0);
  EXPECT_GT(s.continuation_steps, 1);
  EXPECT_DOUBLE_EQ(s.lambda, 1.0);
  EXPECT_EQ(term.invalid_derivative_calls(), 0);
  EXPECT_EQ(x(segments), 2.0);
  for (int v = 0; v <= segments; ++v) EXPECT_NEAR(x(v), 0.2 * v, 1e-10);
}

TEST(Continuation, FailsCleanlyBelowTheMinimumStep) {
  // The right end is pushed past the left one: no admissible state exists beyond λ = 0.5.
  const int segments = 4;
  const BarrierChainTerm term(segments, 1.0, 0.1, 1.0);
  const std::vector<int> fixed = {0, segments};
  Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(segments + 1, 0.0, 4.0);
  ContinuationOptions options;
  options.min_step = 1e-3;
  const NewtonSummary s = solve_continuation(
      terms_of({&term}), x, fixed, [&](double lambda, Eigen::VectorXd& y) { y(segments) = 4.0 - 8.0 * lambda; },
      options);
  EXPECT_FALSE(s.converged());
  EXPECT_GT(s.cut_backs, 0);
  EXPECT_LT(s.lambda, 0.5);
  EXPECT_GT(s.lambda, 0.4);
  EXPECT_TRUE(std::isfinite(term.value(x))) << "x is the last converged state";
  EXPECT_NEAR(x(segments), 4.0 - 8.0 * s.lambda, 1e-12);
  EXPECT_NE(s.message.find("min_step"), std::string::npos) << s.message;
  std::cout << "[ impossible load ] " << s.brief() << "\n";
}

// ---------------------------------------------------------------------------------------------

struct StretchResult {
  NewtonSummary summary;
  Eigen::VectorXd x;
  double force = 0.0;
  double milliseconds = 0.0;
};

// A swatch clamped at x = 0 and x = length, the right clamp moved to (1 + stretch)·length.
StretchResult stretch_membrane(const ShellMesh& mesh, const InplaneParams& params, double length,
                               double stretch, const ContinuationOptions& options) {
  const MembraneTerm membrane(mesh, params, 2);
  const std::vector<int> left = vertices_at_x(mesh, 0.0);
  const std::vector<int> right = vertices_at_x(mesh, length);
  std::vector<int> clamped = left;
  clamped.insert(clamped.end(), right.begin(), right.end());
  const std::vector<int> fixed = vertex_dofs(clamped, 2);
  const Eigen::VectorXd rest = rest_state(mesh, 2);
  const auto set_boundary = [&](double lambda, Eigen::VectorXd& x) {
    for (const int v : right) x(2 * v) = rest(2 * v) * (1.0 + lambda * stretch);
  };
  StretchResult r;
  r.x = rest;
  const auto t0 = numerics::Clock::now();
  r.summary = solve_continuation(terms_of({&membrane}), r.x, fixed, set_boundary, options);
  r.milliseconds = 1e3 * numerics::seconds_since(t0);
  r.force = clamp_force(terms_of({&membrane}), r.x, right, 2, 0);
  return r;
}

// Near-isotropic knit membrane for the swatch tests [N/m]: kxx kxy kyy kss kn1 kn2.
const InplaneParams k_swatch_membrane{100.0, 30.0, 100.0, 35.0, 0.0, 10.0};

TEST(Continuation, MembraneSwatchStretchedByHalfConverges) {
  const double length = 0.1, width = 0.06;
  const InplaneParams params = k_swatch_membrane;
  const ShellMesh mesh = make_rect_mesh(length, width, 20, 12, 0.0);
  ContinuationOptions options;
  // Forces are ~N over ~20 clamped nodes; 1e-9 N per node is far below any measurement.
  options.newton.tolerance = 1e-9;
  const StretchResult best_of = [&] {
    StretchResult best = stretch_membrane(mesh, params, length, 0.5, options);
    for (int k = 0; k < 4; ++k) {  // timings on a shared machine: keep the fastest
      StretchResult again = stretch_membrane(mesh, params, length, 0.5, options);
      if (again.milliseconds < best.milliseconds) best = std::move(again);
    }
    return best;
  }();
  const NewtonSummary& s = best_of.summary;
  ASSERT_TRUE(s.converged()) << s.brief();
  std::cout << "[ membrane 20x12, 50 % ] " << s.brief() << "; " << best_of.milliseconds
            << " ms; clamp force " << best_of.force << " N\n";
  EXPECT_DOUBLE_EQ(s.lambda, 1.0);
  EXPECT_GT(best_of.force, 0.0) << "the right clamp pulls the swatch along +x";
  // Necking: the free edges move inwards at mid-length.
  const std::vector<int> mid = vertices_at_x(mesh, length / 2);
  const double w = best_of.x(2 * mid.back() + 1) - best_of.x(2 * mid.front() + 1);
  EXPECT_LT(w, width);
  EXPECT_GT(w, 0.5 * width);
  // Equilibrium: the two clamps' forces balance.
  const MembraneTerm membrane(mesh, params, 2);
  const double left_force = clamp_force(terms_of({&membrane}), best_of.x, vertices_at_x(mesh, 0.0), 2, 0);
  EXPECT_NEAR(left_force, -best_of.force, 1e-6 * best_of.force);

  // The same load in a single step: either it fails or it needs more work than the walk's
  // smallest step; with continuation it always succeeds. Report both.
  ContinuationOptions single = options;
  single.initial_step = 1.0;
  single.step_growth = 1.0;
  const StretchResult one = stretch_membrane(mesh, params, length, 0.5, single);
  std::cout << "[ membrane 20x12, 50 % from a single initial step ] " << one.summary.brief()
            << "; " << one.milliseconds << " ms\n";
  if (one.summary.converged()) {
    EXPECT_NEAR(one.force, best_of.force, 1e-6 * best_of.force);
  }
}

TEST(Continuation, MembraneOnATwiceRefinedMeshConverges) {
  // 80×48 cells (7,938 DOFs): the mesh-convergence check's size. The clamp force changes
  // little with refinement (only the clamp corners are singular).
  const double length = 0.1, width = 0.06;
  const InplaneParams params = k_swatch_membrane;
  ContinuationOptions options;
  options.newton.tolerance = 1e-9;
  const ShellMesh coarse = make_rect_mesh(length, width, 20, 12, std::numbers::pi / 4);
  const ShellMesh fine = refine(refine(coarse));
  const StretchResult a = stretch_membrane(coarse, params, length, 0.3, options);
  const StretchResult b = stretch_membrane(fine, params, length, 0.3, options);
  ASSERT_TRUE(a.summary.converged()) << a.summary.brief();
  ASSERT_TRUE(b.summary.converged()) << b.summary.brief();
  std::cout << "[ bias membrane 30 %, 20x12 ] " << a.summary.brief() << "; force " << a.force
            << " N\n[ bias membrane 30 %, 80x48 ] " << b.summary.brief() << "; force " << b.force
            << " N\n";
  EXPECT_NEAR(b.force, a.force, 0.05 * a.force);
}

}  // namespace
}  // namespace yarnfit::shell
