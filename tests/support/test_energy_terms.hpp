#pragma once
// Small energy terms with known minimisers, for the tests of the Newton solver
// (tests/numerics/newton) and of the shell's static equilibrium (tests/shell_fit/solver):
// quadratics, springs that buckle, a barrier chain and a wall that are +inf beyond their
// domain, double wells and Rosenbrock's valley with indefinite Hessians, and a term that
// breaks its contract with a NaN gradient.

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "numerics/terms/energy_term.hpp"
#include "numerics/terms/scene.hpp"

namespace yarnfit::testing {

using numerics::Triplets;

inline constexpr double inf = std::numeric_limits<double>::infinity();

inline void add_block(Triplets& h, const std::vector<int>& dofs, const Eigen::MatrixXd& block) {
  for (std::size_t r = 0; r < dofs.size(); ++r) {
    for (std::size_t c = 0; c < dofs.size(); ++c) {
      h.emplace_back(dofs[r], dofs[c], block(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)));
    }
  }
}

inline Eigen::MatrixXd project_psd_block(const Eigen::MatrixXd& m) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(m);
  return eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() *
         eig.eigenvectors().transpose();
}

// E = ½ (x − c)ᵀ A (x − c), A symmetric positive definite: minimiser c.
class QuadraticTerm final : public numerics::EnergyTerm {
 public:
  QuadraticTerm(Eigen::MatrixXd a, Eigen::VectorXd c) : m_a(std::move(a)), m_c(std::move(c)) {}
  [[nodiscard]] std::string name() const override { return "quadratic"; }
  void add_value(const Eigen::VectorXd& x, double& energy) const override { energy += value_of(x); }
  [[nodiscard]] double value_of(const Eigen::VectorXd& x) const {
    return 0.5 * (x - m_c).dot(m_a * (x - m_c));
  }
  void add_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override {
    g += m_a * (x - m_c);
  }
  void add_hessian(const Eigen::VectorXd&, Triplets& h, const numerics::HessianOptions&) const override {
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
class SpringTerm final : public numerics::EnergyTerm {
 public:
  struct Spring {
    int i, j;
    double k, rest;
  };
  SpringTerm(std::vector<Spring> springs, int dim) : m_springs(std::move(springs)), m_dim(dim) {}
  [[nodiscard]] std::string name() const override { return "springs"; }
  void add_value(const Eigen::VectorXd& x, double& energy) const override { energy += value_of(x); }
  [[nodiscard]] double value_of(const Eigen::VectorXd& x) const {
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
  void add_hessian(const Eigen::VectorXd& x, Triplets& h, const numerics::HessianOptions& options) const override {
    for (const auto& s : m_springs) {
      const Eigen::VectorXd d = delta(x, s);
      const double l = d.norm();
      const Eigen::VectorXd n = d / l;
      const Eigen::MatrixXd nn = n * n.transpose();
      const Eigen::MatrixXd id = Eigen::MatrixXd::Identity(m_dim, m_dim);
      Eigen::MatrixXd k = s.k * (nn + (1.0 - s.rest / l) * (id - nn));
      if (options.project_psd) k = project_psd_block(k);  // the 2×2 block [[K, −K], [−K, K]] ~ K
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
class BarrierChainTerm final : public numerics::EnergyTerm {
 public:
  BarrierChainTerm(int segments, double k, double c, double rest)
      : m_segments(segments), m_k(k), m_c(c), m_rest(rest) {}
  [[nodiscard]] std::string name() const override { return "barrier_chain"; }
  void add_value(const Eigen::VectorXd& x, double& energy) const override { energy += value_of(x); }
  [[nodiscard]] double value_of(const Eigen::VectorXd& x) const {
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
  void add_hessian(const Eigen::VectorXd& x, Triplets& h, const numerics::HessianOptions&) const override {
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
    if (!std::isfinite(value_of(x))) ++m_invalid_calls;
  }
  int m_segments;
  double m_k, m_c, m_rest;
  mutable int m_invalid_calls = 0;
};

// E = ½ a |x − target|² − b Σ_k log(1 − x_k): defined only for every x_k < 1. Per coordinate
// the minimiser solves a(x − t)(1 − x) + b = 0.
class WallTerm final : public numerics::EnergyTerm {
 public:
  WallTerm(double a, double b, double target) : m_a(a), m_b(b), m_target(target) {}
  [[nodiscard]] std::string name() const override { return "wall"; }
  void add_value(const Eigen::VectorXd& x, double& energy) const override { energy += value_of(x); }
  [[nodiscard]] double value_of(const Eigen::VectorXd& x) const {
    double e = 0.0;
    for (Eigen::Index k = 0; k < x.size(); ++k) {
      if (!(x(k) < 1.0)) return inf;
      e += 0.5 * m_a * (x(k) - m_target) * (x(k) - m_target) - m_b * std::log(1.0 - x(k));
    }
    return e;
  }
  void add_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override {
    if (!std::isfinite(value_of(x))) ++m_invalid_calls;
    for (Eigen::Index k = 0; k < x.size(); ++k) {
      g(k) += m_a * (x(k) - m_target) + m_b / (1.0 - x(k));
    }
  }
  void add_hessian(const Eigen::VectorXd& x, Triplets& h, const numerics::HessianOptions&) const override {
    if (!std::isfinite(value_of(x))) ++m_invalid_calls;
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
class DoubleWellTerm final : public numerics::EnergyTerm {
 public:
  explicit DoubleWellTerm(double coupling) : m_kappa(coupling) {}
  [[nodiscard]] std::string name() const override { return "double_well"; }
  void add_value(const Eigen::VectorXd& x, double& energy) const override { energy += value_of(x); }
  [[nodiscard]] double value_of(const Eigen::VectorXd& x) const {
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
  void add_hessian(const Eigen::VectorXd& x, Triplets& h, const numerics::HessianOptions&) const override {
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
class RosenbrockTerm final : public numerics::EnergyTerm {
 public:
  [[nodiscard]] std::string name() const override { return "rosenbrock"; }
  void add_value(const Eigen::VectorXd& x, double& energy) const override { energy += value_of(x); }
  [[nodiscard]] double value_of(const Eigen::VectorXd& x) const {
    return std::pow(1.0 - x(0), 2) + 100.0 * std::pow(x(1) - x(0) * x(0), 2);
  }
  void add_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override {
    g(0) += -2.0 * (1.0 - x(0)) - 400.0 * x(0) * (x(1) - x(0) * x(0));
    g(1) += 200.0 * (x(1) - x(0) * x(0));
  }
  void add_hessian(const Eigen::VectorXd& x, Triplets& h, const numerics::HessianOptions& options) const override {
    Eigen::MatrixXd m(2, 2);
    m << 2.0 - 400.0 * (x(1) - 3.0 * x(0) * x(0)), -400.0 * x(0), -400.0 * x(0), 200.0;
    add_block(h, {0, 1}, options.project_psd ? project_psd_block(m) : m);
  }
};

// Returns a finite value everywhere but a NaN gradient for x_0 > 0.5: a term breaking its
// contract, which the solver must report rather than pass on.
class NanGradientTerm final : public numerics::EnergyTerm {
 public:
  [[nodiscard]] std::string name() const override { return "nan_gradient"; }
  void add_value(const Eigen::VectorXd& x, double& energy) const override { energy += value_of(x); }
  [[nodiscard]] double value_of(const Eigen::VectorXd& x) const {
    return 0.5 * (x.array() - 1.0).square().sum();
  }
  void add_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override {
    g += (x.array() - 1.0).matrix();
    if (x(0) > 0.5) g(0) = std::numeric_limits<double>::quiet_NaN();
  }
  void add_hessian(const Eigen::VectorXd& x, Triplets& h, const numerics::HessianOptions&) const override {
    for (Eigen::Index k = 0; k < x.size(); ++k) h.emplace_back(static_cast<int>(k), static_cast<int>(k), 1.0);
  }
};

inline numerics::TermList terms_of(std::initializer_list<const numerics::EnergyTerm*> list) { return numerics::TermList(list); }

}  // namespace yarnfit::testing
