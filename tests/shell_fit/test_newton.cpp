// Static Newton solver and load continuation (shell_fit/solver/newton.hpp), on small energy
// terms with known minimisers written here, and on a stretched membrane.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "shell_fit/energies/membrane_term.hpp"
#include "shell_fit/mesh/rect_mesh.hpp"
#include "shell_fit/solver/newton.hpp"

namespace yarnfit::shell {
namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

void add_block(Triplets& h, const std::vector<int>& dofs, const Eigen::MatrixXd& block) {
  for (std::size_t r = 0; r < dofs.size(); ++r) {
    for (std::size_t c = 0; c < dofs.size(); ++c) {
      h.emplace_back(dofs[r], dofs[c], block(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)));
    }
  }
}

Eigen::MatrixXd project_psd_block(const Eigen::MatrixXd& m) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(m);
  return eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() *
         eig.eigenvectors().transpose();
}

// E = ½ (x − c)ᵀ A (x − c), A symmetric positive definite: minimiser c.
class QuadraticTerm final : public EnergyTerm {
 public:
  QuadraticTerm(Eigen::MatrixXd a, Eigen::VectorXd c) : m_a(std::move(a)), m_c(std::move(c)) {}
  [[nodiscard]] std::string name() const override { return "quadratic"; }
  [[nodiscard]] double value(const Eigen::VectorXd& x) const override {
    return 0.5 * (x - m_c).dot(m_a * (x - m_c));
  }
  void add_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override {
    g += m_a * (x - m_c);
  }
  void add_hessian(const Eigen::VectorXd&, Triplets& h, bool) const override {
    for (Eigen::Index r = 0; r < m_a.rows(); ++r) {
      for (Eigen::Index c = 0; c < m_a.cols(); ++c) {
        if (m_a(r, c) != 0.0) h.emplace_back(static_cast<int>(r), static_cast<int>(c), m_a(r, c));
      }
    }
  }

 private:
  Eigen::MatrixXd m_a;
  Eigen::VectorXd m_c;
};

// Linear springs between points in `dim` dimensions: E = Σ ½ k (l − L)². Under compression
// (l < L) the transverse stiffness k(1 − L/l) is negative: the raw Hessian is indefinite.
class SpringTerm final : public EnergyTerm {
 public:
  struct Spring {
    int i, j;
    double k, rest;
  };
  SpringTerm(std::vector<Spring> springs, int dim) : m_springs(std::move(springs)), m_dim(dim) {}
  [[nodiscard]] std::string name() const override { return "springs"; }
  [[nodiscard]] double value(const Eigen::VectorXd& x) const override {
    double e = 0.0;
    for (const auto& s : m_springs) {
      const double l = delta(x, s).norm();
      e += 0.5 * s.k * (l - s.rest) * (l - s.rest);
    }
    return e;
  }
  void add_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override {
    for (const auto& s : m_springs) {
      const Eigen::VectorXd d = delta(x, s);
      const double l = d.norm();
      const Eigen::VectorXd f = s.k * (l - s.rest) * d / l;
      g.segment(m_dim * s.j, m_dim) += f;
      g.segment(m_dim * s.i, m_dim) -= f;
    }
  }
  void add_hessian(const Eigen::VectorXd& x, Triplets& h, bool project_psd) const override {
    for (const auto& s : m_springs) {
      const Eigen::VectorXd d = delta(x, s);
      const double l = d.norm();
      const Eigen::VectorXd n = d / l;
      const Eigen::MatrixXd nn = n * n.transpose();
      const Eigen::MatrixXd id = Eigen::MatrixXd::Identity(m_dim, m_dim);
      Eigen::MatrixXd k = s.k * (nn + (1.0 - s.rest / l) * (id - nn));
      if (project_psd) k = project_psd_block(k);  // the 2×2 block [[K, −K], [−K, K]] ~ K
      Eigen::MatrixXd block(2 * m_dim, 2 * m_dim);
      block << k, -k, -k, k;
      std::vector<int> dofs;
      for (int a = 0; a < m_dim; ++a) dofs.push_back(m_dim * s.i + a);
      for (int a = 0; a < m_dim; ++a) dofs.push_back(m_dim * s.j + a);
      add_block(h, dofs, block);
    }
  }

 private:
  [[nodiscard]] Eigen::VectorXd delta(const Eigen::VectorXd& x, const Spring& s) const {
    return x.segment(m_dim * s.j, m_dim) - x.segment(m_dim * s.i, m_dim);
  }
  std::vector<Spring> m_springs;
  int m_dim;
};

// A 1-D chain x_0 < x_1 < … with E = Σ ½k(d − L)² + c (d/L − 1 − log(d/L)), d = x_{i+1} − x_i:
// +inf when any d ≤ 0 (an inverted element). Records whether derivatives were ever asked for
// at an invalid state.
class BarrierChainTerm final : public EnergyTerm {
 public:
  BarrierChainTerm(int segments, double k, double c, double rest)
      : m_segments(segments), m_k(k), m_c(c), m_rest(rest) {}
  [[nodiscard]] std::string name() const override { return "barrier_chain"; }
  [[nodiscard]] double value(const Eigen::VectorXd& x) const override {
    double e = 0.0;
    for (int i = 0; i < m_segments; ++i) {
      const double d = x(i + 1) - x(i);
      if (!(d > 0.0)) return inf;
      const double r = d / m_rest;
      e += 0.5 * m_k * (d - m_rest) * (d - m_rest) + m_c * (r - 1.0 - std::log(r));
    }
    return e;
  }
  void add_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override {
    note(x);
    for (int i = 0; i < m_segments; ++i) {
      const double d = x(i + 1) - x(i);
      const double f = m_k * (d - m_rest) + m_c * (1.0 / m_rest - 1.0 / d);
      g(i + 1) += f;
      g(i) -= f;
    }
  }
  void add_hessian(const Eigen::VectorXd& x, Triplets& h, bool) const override {
    note(x);
    for (int i = 0; i < m_segments; ++i) {
      const double d = x(i + 1) - x(i);
      const double k = m_k + m_c / (d * d);
      add_block(h, {i, i + 1}, (Eigen::Matrix2d() << k, -k, -k, k).finished());
    }
  }
  [[nodiscard]] int invalid_derivative_calls() const { return m_invalid_calls; }

 private:
  void note(const Eigen::VectorXd& x) const {
    if (!std::isfinite(value(x))) ++m_invalid_calls;
  }
  int m_segments;
  double m_k, m_c, m_rest;
  mutable int m_invalid_calls = 0;
};

// E = ½ a |x − target|² − b Σ_k log(1 − x_k): defined only for every x_k < 1. Per coordinate
// the minimiser solves a(x − t)(1 − x) + b = 0.
class WallTerm final : public EnergyTerm {
 public:
  WallTerm(double a, double b, double target) : m_a(a), m_b(b), m_target(target) {}
  [[nodiscard]] std::string name() const override { return "wall"; }
  [[nodiscard]] double value(const Eigen::VectorXd& x) const override {
    double e = 0.0;
    for (Eigen::Index k = 0; k < x.size(); ++k) {
      if (!(x(k) < 1.0)) return inf;
      e += 0.5 * m_a * (x(k) - m_target) * (x(k) - m_target) - m_b * std::log(1.0 - x(k));
    }
    return e;
  }
  void add_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override {
    if (!std::isfinite(value(x))) ++m_invalid_calls;
    for (Eigen::Index k = 0; k < x.size(); ++k) {
      g(k) += m_a * (x(k) - m_target) + m_b / (1.0 - x(k));
    }
  }
  void add_hessian(const Eigen::VectorXd& x, Triplets& h, bool) const override {
    if (!std::isfinite(value(x))) ++m_invalid_calls;
    for (Eigen::Index k = 0; k < x.size(); ++k) {
      const int i = static_cast<int>(k);
      h.emplace_back(i, i, m_a + m_b / ((1.0 - x(k)) * (1.0 - x(k))));
    }
  }
  [[nodiscard]] double minimiser() const {
    // x² − (1 + t)x + t − b/a = 0, smaller root (the one below the wall).
    const double p = 1.0 + m_target;
    return 0.5 * (p - std::sqrt(p * p - 4.0 * (m_target - m_b / m_a)));
  }
  [[nodiscard]] int invalid_derivative_calls() const { return m_invalid_calls; }

 private:
  double m_a, m_b, m_target;
  mutable int m_invalid_calls = 0;
};

// Coupled double wells E = Σ (x_i² − 1)² + ½ κ Σ (x_{i+1} − x_i)². Near 0 the Hessian
// 12x² − 4 is negative; add_hessian ignores project_psd on purpose, so only the solver's
// shift can save the step.
class DoubleWellTerm final : public EnergyTerm {
 public:
  explicit DoubleWellTerm(double coupling) : m_kappa(coupling) {}
  [[nodiscard]] std::string name() const override { return "double_well"; }
  [[nodiscard]] double value(const Eigen::VectorXd& x) const override {
    double e = 0.0;
    for (Eigen::Index i = 0; i < x.size(); ++i) e += std::pow(x(i) * x(i) - 1.0, 2);
    for (Eigen::Index i = 0; i + 1 < x.size(); ++i) e += 0.5 * m_kappa * std::pow(x(i + 1) - x(i), 2);
    return e;
  }
  void add_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override {
    for (Eigen::Index i = 0; i < x.size(); ++i) g(i) += 4.0 * x(i) * (x(i) * x(i) - 1.0);
    for (Eigen::Index i = 0; i + 1 < x.size(); ++i) {
      const double f = m_kappa * (x(i + 1) - x(i));
      g(i + 1) += f;
      g(i) -= f;
    }
  }
  void add_hessian(const Eigen::VectorXd& x, Triplets& h, bool) const override {
    for (Eigen::Index i = 0; i < x.size(); ++i) {
      h.emplace_back(static_cast<int>(i), static_cast<int>(i), 12.0 * x(i) * x(i) - 4.0);
    }
    for (Eigen::Index i = 0; i + 1 < x.size(); ++i) {
      const int a = static_cast<int>(i);
      add_block(h, {a, a + 1}, (Eigen::Matrix2d() << m_kappa, -m_kappa, -m_kappa, m_kappa).finished());
    }
  }

 private:
  double m_kappa;
};

// Rosenbrock (1 − x)² + 100 (y − x²)²: a curved valley, indefinite Hessian in places.
class RosenbrockTerm final : public EnergyTerm {
 public:
  [[nodiscard]] std::string name() const override { return "rosenbrock"; }
  [[nodiscard]] double value(const Eigen::VectorXd& x) const override {
    return std::pow(1.0 - x(0), 2) + 100.0 * std::pow(x(1) - x(0) * x(0), 2);
  }
  void add_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override {
    g(0) += -2.0 * (1.0 - x(0)) - 400.0 * x(0) * (x(1) - x(0) * x(0));
    g(1) += 200.0 * (x(1) - x(0) * x(0));
  }
  void add_hessian(const Eigen::VectorXd& x, Triplets& h, bool project_psd) const override {
    Eigen::MatrixXd m(2, 2);
    m << 2.0 - 400.0 * (x(1) - 3.0 * x(0) * x(0)), -400.0 * x(0), -400.0 * x(0), 200.0;
    add_block(h, {0, 1}, project_psd ? project_psd_block(m) : m);
  }
};

// Returns a finite value everywhere but a NaN gradient for x_0 > 0.5: a term breaking its
// contract, which the solver must report rather than pass on.
class NanGradientTerm final : public EnergyTerm {
 public:
  [[nodiscard]] std::string name() const override { return "nan_gradient"; }
  [[nodiscard]] double value(const Eigen::VectorXd& x) const override {
    return 0.5 * (x.array() - 1.0).square().sum();
  }
  void add_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override {
    g += (x.array() - 1.0).matrix();
    if (x(0) > 0.5) g(0) = std::numeric_limits<double>::quiet_NaN();
  }
  void add_hessian(const Eigen::VectorXd& x, Triplets& h, bool) const override {
    for (Eigen::Index k = 0; k < x.size(); ++k) h.emplace_back(static_cast<int>(k), static_cast<int>(k), 1.0);
  }
};

std::vector<const EnergyTerm*> terms_of(std::initializer_list<const EnergyTerm*> list) {
  return std::vector<const EnergyTerm*>(list);
}

// ---------------------------------------------------------------------------------------------

TEST(Newton, QuadraticConvergesInOneStep) {
  const int n = 6;
  Eigen::MatrixXd m = Eigen::MatrixXd::Random(n, n);
  const Eigen::MatrixXd a = m * m.transpose() + n * Eigen::MatrixXd::Identity(n, n);
  const Eigen::VectorXd c = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
  const QuadraticTerm term(a, c);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  const NewtonSummary s = solve_static(terms_of({&term}), x, {}, NewtonOptions{});
  ASSERT_TRUE(s.converged()) << s.brief();
  EXPECT_EQ(s.iterations, 1) << s.brief();
  EXPECT_EQ(s.regularised_steps, 0);
  EXPECT_LT((x - c).lpNorm<Eigen::Infinity>(), 1e-12);
  EXPECT_LE(s.gradient_norm, 1e-8);
  EXPECT_NEAR(s.energy, 0.0, 1e-20);
  EXPECT_NE(s.brief().find("converged"), std::string::npos) << s.brief();
}

TEST(Newton, FixedDofsKeepTheirValuesExactly) {
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
  const NewtonSummary s = solve_static(terms_of({&term}), x, fixed, NewtonOptions{});
  ASSERT_TRUE(s.converged()) << s.brief();
  EXPECT_EQ(x(0), start(0));
  EXPECT_EQ(x(2), start(2));
  const std::vector<int> f = {1, 3, 4};
  const std::vector<int> cdofs = {0, 2};
  const Eigen::MatrixXd aff = a(f, f);
  const Eigen::VectorXd expected = c(f) - aff.ldlt().solve(a(f, cdofs) * (x(cdofs) - c(cdofs)));
  EXPECT_LT((x(f) - expected).lpNorm<Eigen::Infinity>(), 1e-12);
  EXPECT_THROW((void)solve_static(terms_of({&term}), x, {n}, NewtonOptions{}), std::invalid_argument);
}

TEST(Newton, SpringChainReachesKnownEquilibriumAndClampReactionsHaveTheDocumentedSign) {
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
  NewtonOptions options;
  options.gradient_tolerance = 1e-12;
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

TEST(Newton, IndefiniteDoubleWellIsSafeguardedByTheShift) {
  // Starting near the maximum at 0, plain Newton would climb to it; the shift must turn the
  // step downhill, and the solver must still end at a true minimum.
  const DoubleWellTerm term(0.3);
  Eigen::VectorXd x(6);
  x << 0.05, -0.02, 0.01, 0.08, -0.04, 0.0;
  NewtonOptions options;
  options.gradient_tolerance = 1e-12;
  options.project_psd = false;
  const NewtonSummary s = solve_static(terms_of({&term}), x, {}, options);
  ASSERT_TRUE(s.converged()) << s.brief();
  std::cout << "[ double well ] " << s.brief() << "\n";
  EXPECT_GT(s.regularised_steps, 0) << "the start is indefinite: a shift was needed";
  const Eigen::MatrixXd h = Eigen::MatrixXd(total_hessian(terms_of({&term}), x, false));
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(h).eigenvalues().minCoeff(), 0.0)
      << "a minimum, not a saddle: x = " << x.transpose();
  EXPECT_LT(s.energy, term.value(Eigen::VectorXd::Zero(6)));
}

TEST(Newton, CompressedSpringChainBucklesWithAndWithoutProjection) {
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
    NewtonOptions options;
    options.gradient_tolerance = 1e-10;
    options.project_psd = project;
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

TEST(Newton, LineSearchNeverStepsIntoTheInfiniteRegion) {
  // The full Newton step from 0 overshoots the wall at 1; only backtracking keeps it valid.
  const WallTerm term(1.0, 1e-3, 3.0);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(3);
  x(1) = -2.0;
  NewtonOptions options;
  options.gradient_tolerance = 1e-10;
  const NewtonSummary s = solve_static(terms_of({&term}), x, {}, options);
  ASSERT_TRUE(s.converged()) << s.brief();
  std::cout << "[ wall ] " << s.brief() << "\n";
  EXPECT_EQ(term.invalid_derivative_calls(), 0);
  EXPECT_TRUE(std::isfinite(term.value(x)));
  for (Eigen::Index k = 0; k < 3; ++k) EXPECT_NEAR(x(k), term.minimiser(), 1e-10);
  EXPECT_LT(term.minimiser(), 1.0);
  EXPECT_GT(term.minimiser(), 0.99);
}

TEST(Newton, InvalidStartIsReportedAndLeavesXUnchanged) {
  const WallTerm term(1.0, 1e-3, 3.0);
  Eigen::VectorXd x = Eigen::VectorXd::Constant(2, 0.5);
  x(1) = 1.5;
  const Eigen::VectorXd start = x;
  const NewtonSummary s = solve_static(terms_of({&term}), x, {}, NewtonOptions{});
  EXPECT_EQ(s.status, NewtonStatus::invalid_start);
  EXPECT_FALSE(s.converged());
  EXPECT_EQ(s.iterations, 0);
  EXPECT_EQ(x, start);
  EXPECT_NE(s.message.find("wall"), std::string::npos) << s.message;
  EXPECT_NE(s.brief().find("invalid_start"), std::string::npos) << s.brief();
}

TEST(Newton, MaxIterationsKeepsTheLastValidIterate) {
  const RosenbrockTerm term;
  Eigen::VectorXd x(2);
  x << -1.2, 1.0;
  NewtonOptions options;
  options.max_iterations = 3;
  const NewtonSummary s = solve_static(terms_of({&term}), x, {}, options);
  EXPECT_EQ(s.status, NewtonStatus::max_iterations);
  EXPECT_EQ(s.iterations, 3);
  EXPECT_TRUE(x.allFinite());
  EXPECT_DOUBLE_EQ(s.energy, term.value(x));
  EXPECT_LT(s.energy, 24.2) << "every accepted step decreased the energy";
  EXPECT_TRUE(std::isfinite(s.gradient_norm));
  EXPECT_FALSE(s.message.empty());

  // With the default budget it reaches the minimum at (1, 1), with and without projection.
  for (const bool project : {true, false}) {
    x << -1.2, 1.0;
    options = NewtonOptions{};
    options.gradient_tolerance = 1e-10;
    options.project_psd = project;
    const NewtonSummary full = solve_static(terms_of({&term}), x, {}, options);
    ASSERT_TRUE(full.converged()) << full.brief();
    std::cout << "[ rosenbrock, project_psd " << project << " ] " << full.brief() << "\n";
    EXPECT_NEAR(x(0), 1.0, 1e-8);
    EXPECT_NEAR(x(1), 1.0, 1e-8);
  }
}

TEST(Newton, NonFiniteGradientIsReportedNotPassedOn) {
  const NanGradientTerm term;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(2);
  const NewtonSummary s = solve_static(terms_of({&term}), x, {}, NewtonOptions{});
  EXPECT_EQ(s.status, NewtonStatus::non_finite) << s.brief();
  EXPECT_TRUE(x.allFinite());
  EXPECT_TRUE(std::isfinite(s.energy));
  EXPECT_NE(s.message.find("nan_gradient"), std::string::npos) << s.message;
}

TEST(Newton, RejectsInvalidOptionsAndArguments) {
  NewtonOptions options;
  std::string why;
  EXPECT_TRUE(options.is_valid(&why));
  options.regularisation_growth = 1.0;
  EXPECT_FALSE(options.is_valid(&why));
  EXPECT_NE(why.find("regularisation_growth"), std::string::npos) << why;
  const QuadraticTerm term(Eigen::MatrixXd::Identity(2, 2), Eigen::VectorXd::Zero(2));
  Eigen::VectorXd x = Eigen::VectorXd::Ones(2);
  EXPECT_THROW((void)solve_static(terms_of({&term}), x, {}, options), std::invalid_argument);
  EXPECT_THROW((void)solve_static({}, x, {}, NewtonOptions{}), std::invalid_argument);
  EXPECT_THROW((void)solve_static(terms_of({nullptr}), x, {}, NewtonOptions{}), std::invalid_argument);
  ContinuationOptions copt;
  EXPECT_TRUE(copt.is_valid(&why)) << why;
  copt.min_step = 0.0;
  EXPECT_FALSE(copt.is_valid(&why));
  EXPECT_NE(why.find("min_step"), std::string::npos) << why;
}

TEST(Newton, AllFixedIsConvergedAtOnce) {
  const QuadraticTerm term(Eigen::MatrixXd::Identity(2, 2), Eigen::VectorXd::Zero(2));
  Eigen::VectorXd x = Eigen::VectorXd::Ones(2);
  const NewtonSummary s = solve_static(terms_of({&term}), x, {0, 1}, NewtonOptions{});
  EXPECT_TRUE(s.converged());
  EXPECT_EQ(s.iterations, 0);
  EXPECT_EQ(x, Eigen::VectorXd::Ones(2));
}

// ---------------------------------------------------------------------------------------------

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
  const NewtonSummary direct = solve_static(terms_of({&term}), one_step, fixed, NewtonOptions{});
  EXPECT_FALSE(direct.converged());
  EXPECT_EQ(direct.status, NewtonStatus::invalid_start) << direct.brief();

  Eigen::VectorXd x = rest;
  ContinuationOptions options;
  options.initial_step = 0.5;
  options.newton.gradient_tolerance = 1e-10;
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
  const auto t0 = std::chrono::steady_clock::now();
  r.summary = solve_continuation(terms_of({&membrane}), r.x, fixed, set_boundary, options);
  r.milliseconds =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
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
  options.newton.gradient_tolerance = 1e-9;
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
  options.newton.gradient_tolerance = 1e-9;
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
