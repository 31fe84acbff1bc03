// The in-plane law (6.1) of shell_fit/energies/inplane_material.hpp: ψ, P and ∂P/∂F against
// central differences, zero at rest and the analytic uniaxial response, the surface form for
// any embedding, and +inf (never NaN) at inversion.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "shell_fit/core/shell_mesh.hpp"
#include "shell_fit/core/shell_params.hpp"
#include "shell_fit/energies/inplane_material.hpp"
#include "tests/shell_fit/energies/shell_fixtures.hpp"

namespace yarnfit::shell {
namespace {

using namespace fixtures;
using Matrix32 = Eigen::Matrix<double, 3, 2>;

// Central differences of a matrix function over a step sweep, best step; relative to ‖·‖∞.
template <typename Fn, typename Arg>
double best_fd_error(const Fn& f, const Arg& F, const Eigen::MatrixXd& analytic) {
  double best = std::numeric_limits<double>::infinity();
  const double norm = std::max(analytic.lpNorm<Eigen::Infinity>(), 1e-300);
  for (double h = 1e-2; h >= 1e-8; h /= 10.0) {
    Eigen::MatrixXd fd(analytic.rows(), analytic.cols());
    for (int c = 0; c < static_cast<int>(F.size()); ++c) {
      Arg Fp = F, Fm = F;
      Fp.data()[c] += h;
      Fm.data()[c] -= h;
      const Eigen::MatrixXd d = (f(Fp) - f(Fm)) / (2.0 * h);
      fd.col(c) = Eigen::Map<const Eigen::VectorXd>(d.data(), d.size());
    }
    best = std::min(best, (fd - analytic).lpNorm<Eigen::Infinity>() / norm);
  }
  return best;
}

// ψ → P and P → ∂P/∂F by central differences, planar and surface, at random deformations
// (stretch, compression and shear up to ±30 % in F) in every test material frame.
void expect_derivatives_match_finite_differences(const InplaneParams& params, const char* name) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  double worst_pk1 = 0.0, worst_dpk1 = 0.0;
  for (const double angle : test_angles()) {
    const InplaneMaterial m(params, angle);
    for (int trial = 0; trial < 5; ++trial) {
      Eigen::Matrix2d F = Eigen::Matrix2d::Identity();
      F += Eigen::Matrix2d::NullaryExpr([&] { return u(rng); });
      ASSERT_GT(F.determinant(), 0.2);
      const auto psi = [&](const Eigen::Matrix2d& G) {
        return Eigen::MatrixXd::Constant(1, 1, m.psi(G));
      };
      const auto pk1 = [&](const Eigen::Matrix2d& G) { return Eigen::MatrixXd(m.pk1(G)); };
      const Eigen::Matrix2d P = m.pk1(F);
      const double e1 = best_fd_error(psi, F, Eigen::Map<const Eigen::RowVector4d>(P.data()));
      const double e2 = best_fd_error(pk1, F, m.dpk1(F));
      EXPECT_LT(e1, 1e-7) << "pk1, angle " << angle;
      EXPECT_LT(e2, 1e-7) << "dpk1, angle " << angle;
      EXPECT_LE((m.dpk1(F) - m.dpk1(F).transpose()).norm(), 1e-10 * m.dpk1(F).norm());
      worst_pk1 = std::max(worst_pk1, e1);
      worst_dpk1 = std::max(worst_dpk1, e2);

      // Surface F (3×2): a tilted, rotated, stretched triangle.
      Matrix32 F3 = rotation3(u(rng), u(rng), u(rng)).leftCols<2>() * F;
      F3 += Matrix32::NullaryExpr([&] { return 0.3 * u(rng); });
      const auto psi3 = [&](const Matrix32& G) {
        return Eigen::MatrixXd::Constant(1, 1, m.psi_surface(G));
      };
      const auto pk13 = [&](const Matrix32& G) { return Eigen::MatrixXd(m.pk1_surface(G)); };
      const Matrix32 P3 = m.pk1_surface(F3);
      const double e3 =
          best_fd_error(psi3, F3, Eigen::Map<const Eigen::Matrix<double, 1, 6>>(P3.data()));
      const double e4 = best_fd_error(pk13, F3, m.dpk1_surface(F3));
      EXPECT_LT(e3, 1e-7) << "3x2 pk1, angle " << angle;
      EXPECT_LT(e4, 1e-7) << "3x2 dpk1, angle " << angle;
      worst_pk1 = std::max(worst_pk1, e3);
      worst_dpk1 = std::max(worst_dpk1, e4);
    }
  }
  std::printf("InplaneMaterial FD (%s): worst best-step rel. error pk1 %.2e, dpk1 %.2e\n", name, worst_pk1,
              worst_dpk1);
}

TEST(InplaneMaterialTest, DerivativesMatchFiniteDifferences) {
  expect_derivatives_match_finite_differences(sample_inplane(), "eq. 6.1");
}

TEST(InplaneMaterialTest, StiffeningDerivativesMatchFiniteDifferences) {
  expect_derivatives_match_finite_differences(sample_stiffening(), "stiffening");
}

// With every lock-up stiffness l = 0 the stiffening law is eq. 6.1 exactly, whatever the rates.
TEST(InplaneMaterialTest, StiffeningWithoutLockupIsTheThesisLawBitwise) {
  InplaneParams q = sample_inplane();
  q.bxx = 7.0;
  q.byy = 0.3;
  q.bss = 2.0;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  for (const double angle : test_angles()) {
    const InplaneMaterial thesis(sample_inplane(), angle), zero_lockup(q, angle);
    for (int trial = 0; trial < 5; ++trial) {
      const Eigen::Matrix2d F = Eigen::Matrix2d::Identity() + Eigen::Matrix2d::NullaryExpr([&] { return u(rng); });
      EXPECT_EQ(zero_lockup.psi(F), thesis.psi(F));
      EXPECT_EQ(zero_lockup.pk1(F), thesis.pk1(F));
      EXPECT_EQ(zero_lockup.dpk1(F), thesis.dpk1(F));
    }
  }
}

// The lock-up adds nothing at small strain and, along a pure weft pull with no lateral
// strain (ε = (e, 0, 0)), exactly φ_x(e) + φ_y(ayy e) with
// φ(x) = l (e^{bx} − 1 − bx − b²x²/2)/b³ to eq. 6.1's energy; with the width held narrower,
// the weft lock-up sees e + axx ε2.
TEST(InplaneMaterialTest, LockupAddsTheClosedFormAlongAWeftPull) {
  const InplaneParams p = sample_stiffening();
  const InplaneMaterial thesis(sample_inplane(), 0.0), stiff(p, 0.0);
  const auto phi = [](double l, double b, double x) {
    return x > 0 ? l * (std::exp(b * x) - 1 - b * x - b * b * x * x / 2) / (b * b * b) : 0.0;
  };
  const auto dphi = [](double l, double b, double x) {
    return x > 0 ? l * (std::exp(b * x) - 1 - b * x) / (b * b) : 0.0;
  };
  for (const double s : {0.05, 0.2, 0.5}) {
    const Eigen::Matrix2d F = Eigen::Vector2d(1 + s, 1.0).asDiagonal();
    const double e = 0.5 * ((1 + s) * (1 + s) - 1.0);
    const double added = phi(p.lxx, p.bxx, e) + phi(p.lyy, p.byy, p.ayy * e);
    EXPECT_NEAR(stiff.psi(F) - thesis.psi(F), added, 1e-12 * std::max(1.0, added)) << "s " << s;
    // Stress: P00 = (1+s) (φ_x'(e) + ayy φ_y'(ayy e)) more; the width feels axx φ_x'(e).
    const double sx = dphi(p.lxx, p.bxx, e), sy = dphi(p.lyy, p.byy, p.ayy * e);
    EXPECT_NEAR(stiff.pk1(F)(0, 0) - thesis.pk1(F)(0, 0), (1 + s) * (sx + p.ayy * sy), 1e-11 * std::max(1.0, sx));
    EXPECT_NEAR(stiff.pk1(F)(1, 1) - thesis.pk1(F)(1, 1), p.axx * sx + sy, 1e-11 * std::max(1.0, sx));
    // Narrowed by c: ε2 = ((1−c)² − 1)/2 < 0 relieves the weft lock-up, u_x = e + axx ε2.
    const double c = 0.1, e2 = 0.5 * ((1 - c) * (1 - c) - 1.0);
    const Eigen::Matrix2d N = Eigen::Vector2d(1 + s, 1 - c).asDiagonal();
    const double narrowed = phi(p.lxx, p.bxx, e + p.axx * e2) + phi(p.lyy, p.byy, e2 + p.ayy * e);
    EXPECT_NEAR(stiff.psi(N) - thesis.psi(N), narrowed, 1e-12 * std::max(1.0, narrowed)) << "s " << s;
  }
  // Compression along the weft engages no lock-up (⟨u⟩₊).
  const Eigen::Matrix2d C = Eigen::Vector2d(0.8, 1.0).asDiagonal();
  EXPECT_EQ(stiff.psi(C), thesis.psi(C));
}

// ∂ψ/∂p_k and ∂P/∂p_k of the parameter-derivative laws against central differences in p_k,
// for all fourteen parameters (the lock-up rates and shares enter nonlinearly).
TEST(InplaneMaterialTest, ParameterDerivativeLawsMatchFiniteDifferences) {
  const InplaneParams p = sample_stiffening();
  const auto base = to_array(p);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.25, 0.25);
  for (const double angle : test_angles()) {
    for (int trial = 0; trial < 3; ++trial) {
      const Eigen::Matrix2d F = Eigen::Matrix2d::Identity() + Eigen::Matrix2d::NullaryExpr([&] { return u(rng); });
      for (int k = 0; k < k_inplane_param_count; ++k) {
        const InplaneMaterial d = InplaneMaterial::parameter_derivative(p, angle, k);
        const double h = 1e-5 * std::max(std::abs(base[static_cast<std::size_t>(k)]), 1.0);
        auto up = base, down = base;
        up[static_cast<std::size_t>(k)] += h;
        down[static_cast<std::size_t>(k)] -= h;
        const InplaneMaterial mu(inplane_from_array(up), angle), md(inplane_from_array(down), angle);
        const double fd_psi = (mu.psi(F) - md.psi(F)) / (2 * h);
        const Eigen::Matrix2d fd_P = (mu.pk1(F) - md.pk1(F)) / (2 * h);
        // Relative 1e-7, with a floor for the differences' round-off (ψ is O(1) J/m² here).
        EXPECT_NEAR(d.psi(F), fd_psi, 1e-7 * std::abs(fd_psi) + 1e-9) << k_inplane_param_names[k];
        EXPECT_LE((d.pk1(F) - fd_P).lpNorm<Eigen::Infinity>(), 1e-7 * fd_P.lpNorm<Eigen::Infinity>() + 1e-9)
            << k_inplane_param_names[k] << " angle " << angle;
        // The law's own tangent (the share laws need φ''') against differences of its stress.
        const auto dP = [&](const Eigen::Matrix2d& G) { return Eigen::MatrixXd(d.pk1(G)); };
        if (d.dpk1(F).norm() > 0.0) {
          EXPECT_LT(best_fd_error(dP, F, d.dpk1(F)), 1e-7) << k_inplane_param_names[k] << " angle " << angle;
        }
      }
    }
  }
}

TEST(InplaneMaterialTest, ZeroAtRestAndAnalyticUniaxial) {
  const InplaneParams p = sample_inplane();
  for (const double angle : test_angles()) {
    const InplaneMaterial m(p, angle);
    EXPECT_EQ(m.psi(Eigen::Matrix2d::Identity()), 0.0);
    EXPECT_LE(m.pk1(Eigen::Matrix2d::Identity()).norm(), 1e-14);
    EXPECT_EQ(m.psi_surface(Matrix32::Identity()), 0.0);
    EXPECT_LE(m.pk1_surface(Matrix32::Identity()).norm(), 1e-14);
  }
  // F = diag(1+s, 1): E = diag(e, 0), e = ((1+s)² − 1)/2, J = 1 + s.
  const double s = 0.2;
  const double e = 0.5 * ((1 + s) * (1 + s) - 1.0);
  const double area = p.kn1 * s * s + p.kn2 * std::log(1 + s) * std::log(1 + s);
  const Eigen::Matrix2d F = Eigen::Vector2d(1 + s, 1.0).asDiagonal();
  // Weft along lab x: ε = (e, 0, 0).
  EXPECT_NEAR(InplaneMaterial(p, 0.0).psi(F), 0.5 * p.kxx * e * e + area, 1e-13);
  // Warp along lab x: ε = (0, e, 0).
  EXPECT_NEAR(InplaneMaterial(p, pi / 2).psi(F), 0.5 * p.kyy * e * e + area, 1e-13);
  // Bias: E_m = Rᵀ diag(e, 0) R = [[e/2, −e/2], [−e/2, e/2]], ε = (e/2, e/2, −e).
  const double bias =
      0.5 * (p.kxx * e * e / 4 + 2 * p.kxy * e * e / 4 + p.kyy * e * e / 4 + p.kss * e * e);
  EXPECT_NEAR(InplaneMaterial(p, pi / 4).psi(F), bias + area, 1e-13);
  // The stretch stress is P00 = (1+s) S00 + f'(J) (thesis: σ_s = uᵀ P u).
  const double f1 = 2 * p.kn1 * s + 2 * p.kn2 * std::log(1 + s) / (1 + s);
  EXPECT_NEAR(InplaneMaterial(p, 0.0).pk1(F)(0, 0), (1 + s) * p.kxx * e + f1, 1e-12);
  // The orthogonal stress carries the Poisson coupling: P11 = S11 + f'(J) (1+s) = kxy e + …
  EXPECT_NEAR(InplaneMaterial(p, 0.0).pk1(F)(1, 1), p.kxy * e + f1 * (1 + s), 1e-12);
}

TEST(InplaneMaterialTest, SurfaceMatchesPlanarForAnyEmbedding) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  for (const double angle : test_angles()) {
    const InplaneMaterial m(sample_inplane(), angle);
    for (int trial = 0; trial < 4; ++trial) {
      Eigen::Matrix2d F =
          Eigen::Matrix2d::Identity() + Eigen::Matrix2d::NullaryExpr([&] { return u(rng); });
      const Eigen::Matrix3d Q = rotation3(3 * u(rng), 3 * u(rng), 3 * u(rng));
      const Matrix32 F3 = Q.leftCols<2>() * F;
      EXPECT_NEAR(m.psi_surface(F3), m.psi(F), 1e-12 * std::max(1.0, m.psi(F)));
      // P3 = Q P (the stress rotates with the embedding).
      EXPECT_LE((m.pk1_surface(F3) - Q.leftCols<2>() * m.pk1(F)).norm(), 1e-11 * m.pk1(F).norm());
    }
  }
}

TEST(InplaneMaterialTest, InversionGivesInfinityNeverNaN) {
  const InplaneParams p = sample_inplane();
  const InplaneMaterial m(p, 0.3);
  Eigen::Matrix2d inverted;
  inverted << -0.8, 0.1, 0.05, 1.1;  // det < 0
  EXPECT_EQ(m.psi(inverted), std::numeric_limits<double>::infinity());
  EXPECT_TRUE(m.pk1(inverted).isZero());
  EXPECT_TRUE(m.dpk1(inverted).isZero());
  const Eigen::Matrix2d collapsed = Eigen::Vector2d(1.0, 0.0).asDiagonal();  // J = 0
  EXPECT_EQ(m.psi(collapsed), std::numeric_limits<double>::infinity());
  EXPECT_TRUE(m.pk1(collapsed).allFinite());
  // Without the log barrier the signed J enters (J − 1)² as in plain StVK: finite, smooth.
  InplaneParams q = p;
  q.kn2 = 0.0;
  const InplaneMaterial plain(q, 0.3);
  const double J = inverted.determinant();
  const InplaneMaterial stvk_only({q.kxx, q.kxy, q.kyy, q.kss, 0.0, 0.0}, 0.3);
  EXPECT_NEAR(plain.psi(inverted), stvk_only.psi(inverted) + q.kn1 * (J - 1) * (J - 1), 1e-12);
  EXPECT_TRUE(plain.pk1(inverted).allFinite());
  EXPECT_TRUE(plain.dpk1(inverted).allFinite());
  // Surface F of rank 1 (a triangle collapsed onto a line in 3-D).
  Matrix32 degenerate;
  degenerate << 1.0, 2.0, 0.5, 1.0, 0.0, 0.0;
  EXPECT_EQ(m.psi_surface(degenerate), std::numeric_limits<double>::infinity());
  EXPECT_TRUE(m.pk1_surface(degenerate).allFinite());
  EXPECT_TRUE(m.dpk1_surface(degenerate).allFinite());
  EXPECT_TRUE(std::isfinite(plain.psi_surface(degenerate)));
  EXPECT_TRUE(plain.pk1_surface(degenerate).allFinite());
  EXPECT_TRUE(plain.dpk1_surface(degenerate).allFinite());
}

}  // namespace
}  // namespace yarnfit::shell
