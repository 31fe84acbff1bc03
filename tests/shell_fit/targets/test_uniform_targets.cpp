// Uniform zero-orthogonal-stress targets (thesis eq. 6.3).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "shell_fit/energies/inplane_material.hpp"
#include "shell_fit/targets/uniform_targets.hpp"
#include "tests/test_support.hpp"
#include "tests/shell_fit/known_materials.hpp"

namespace yarnfit::shell {
namespace {

using known::k_knit;

Eigen::Matrix2d uniaxial_F(double angle, double s, double c) {
  const Eigen::Vector2d u(std::cos(angle), std::sin(angle)), v(-std::sin(angle), std::cos(angle));
  return (1 + s) * u * u.transpose() + (1 - c) * v * v.transpose();
}

TEST(UniformTargets, SmallStrainLimitIsTheLinearOrthotropicSolution) {
  // Without area terms, small strain: ν = kxy/kyy, σ = (kxx − kxy²/kyy) s for a weft pull.
  const InplaneParams p{120.0, 35.0, 400.0, 30.0, 0.0, 0.0};
  const double s = 1e-5;
  const UniaxialPoint w = uniaxial_point(p, 0.0, s);
  ASSERT_TRUE(w.converged);
  EXPECT_NEAR(w.compression / s, p.kxy / p.kyy, 1e-4);
  EXPECT_NEAR(w.stress / s, p.kxx - p.kxy * p.kxy / p.kyy, 1e-2);
  const UniaxialPoint y = uniaxial_point(p, std::numbers::pi / 2, s);
  EXPECT_NEAR(y.compression / s, p.kxy / p.kxx, 1e-4);
  EXPECT_NEAR(y.stress / s, p.kyy - p.kxy * p.kxy / p.kxx, 1e-2);
}

TEST(UniformTargets, CompressionMinimisesTheEnergyAndZeroesTheOrthogonalStress) {
  for (double angle : {0.0, std::numbers::pi / 4, std::numbers::pi / 2, 0.3}) {
    const InplaneMaterial m(k_knit, 0.0);
    double c_prev = 0.0;
    for (double s : {0.05, 0.3, 0.8, 1.6}) {
      const UniaxialPoint pt = uniaxial_point(k_knit, angle, s, c_prev);
      c_prev = pt.compression;
      ASSERT_TRUE(pt.converged) << angle << " " << s;
      const Eigen::Vector2d v(-std::sin(angle), std::cos(angle));
      const double orth = v.dot(m.pk1(uniaxial_F(angle, s, pt.compression)) * v);
      EXPECT_NEAR(orth, 0.0, 1e-8 * k_knit.kyy);
      const double psi = m.psi(uniaxial_F(angle, s, pt.compression));
      for (double dc : {-1e-3, 1e-3}) EXPECT_GE(m.psi(uniaxial_F(angle, s, pt.compression + dc)), psi);
    }
  }
}

// Two independent routes to σ_s: uᵀPu at c*, and dΨ(s, c*(s))/ds by differences along the
// target path (equal by the envelope theorem, since ∂Ψ/∂c = 0 there).
TEST(UniformTargets, StressIsTheDerivativeOfTheEnergyAlongThePath) {
  const InplaneMaterial m(k_knit, 0.0);
  for (double angle : {0.0, std::numbers::pi / 4, std::numbers::pi / 2}) {
    for (double s : {0.1, 0.5, 1.2}) {
      const double h = 1e-5;
      const auto a = uniaxial_point(k_knit, angle, s - h), b = uniaxial_point(k_knit, angle, s + h);
      const double dpsi = (m.psi(uniaxial_F(angle, s + h, b.compression)) -
                           m.psi(uniaxial_F(angle, s - h, a.compression))) / (2 * h);
      const double sigma = uniaxial_point(k_knit, angle, s).stress;
      EXPECT_NEAR(dpsi, sigma, 1e-6 * std::abs(sigma)) << angle << " " << s;
    }
  }
}

TEST(UniformTargets, WeftAndWarpSwapWithTheStiffnesses) {
  InplaneParams swapped = k_knit;
  std::swap(swapped.kxx, swapped.kyy);
  for (double s : {0.2, 0.9}) {
    const auto w = uniaxial_point(k_knit, 0.0, s);
    const auto y = uniaxial_point(swapped, std::numbers::pi / 2, s);
    EXPECT_NEAR(w.stress, y.stress, 1e-9 * w.stress);
    EXPECT_NEAR(w.compression, y.compression, 1e-9);
  }
}

TEST(UniformTargets, HardCasesStayFinite) {
  const InplaneParams anisotropic{10000.0, 50.0, 100.0, 20.0, 1.0, 1.0};     // kxx/kyy = 100
  const InplaneParams near_inversion{100.0, 95.0, 100.0, 10.0, 0.0, 0.5};   // large kxy
  for (const auto& p : {anisotropic, near_inversion, k_knit}) {
    double c = 0.0;
    for (int i = 0; i <= 20; ++i) {
      const auto pt = uniaxial_point(p, std::numbers::pi / 2 * (i % 3) / 2.0, 2.0 * i / 20, c);
      c = pt.compression;
      EXPECT_TRUE(std::isfinite(pt.stress) && std::isfinite(pt.compression));
      EXPECT_LT(pt.compression, 1.0);
      EXPECT_TRUE(pt.converged) << i;
    }
  }
}

TEST(UniformTargets, GeneratedTargetsAndCsv) {
  ShellParams p;
  p.inplane = k_knit;
  p.bending.ktheta = {1e-6, 2e-6, 3e-6};
  TargetRanges r;
  r.max_stretch[0] = 0.8;
  r.max_stretch[2] = 0.4;
  r.max_curvature[0] = 200.0;
  const auto t = generate_uniform_targets(p, r);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].stretch.size(), 25u);
  EXPECT_DOUBLE_EQ(t[0].stretch.back().stretch, 0.8);
  EXPECT_EQ(t[0].bending.size(), 15u);
  EXPECT_DOUBLE_EQ(t[0].bending.back().stress, 2 * 1e-6 * 200.0);
  EXPECT_TRUE(t[1].bending.empty());
  yarnfit::testing::ScratchDir dir("targets");
  db::write_uniform_targets_csv(t, dir / "uniform_targets.csv");
  const std::string text = yarnfit::testing::read_file(dir / "uniform_targets.csv");
  EXPECT_EQ(text.rfind("direction,kind,stretch,compression,stress_s_N_per_m,curvature_per_m,stress_kappa_N\n", 0), 0u);
  EXPECT_NE(text.find("warp,stretch,0.4,"), std::string::npos);
  EXPECT_NE(text.find("weft,bending,,,,200,"), std::string::npos);
}

// The stiffening law is convex along every uniaxial path over a knit's fitted range (up to
// 150 % stretch): along a pull with the width held (F = I + s u uᵀ) the energy's second
// difference is non-negative, and along the zero-orthogonal-stress path of the targets the
// stress never falls (the reduced energy W(s) = Ψ(s, c*(s)) has W' = σ_s). Parameters: a
// sharp and a mild lock-up on a knit-like eq. 6.1.
TEST(UniformTargets, StiffeningEnergyIsConvexAlongUniaxialPaths) {
  // With lateral shares of either sign (the lock-up pulls the width in, or holds it out) the
  // stress must still grow.
  const InplaneParams sharp{120.0, 35.0, 400.0, 30.0, 5.0, 8.0, 300.0, 8.0, 2000.0, 2.0, 40.0, 4.0, -3.0, 0.5};
  InplaneParams mild{3.0, 1.0, 20.0, 2.0, 0.5, 0.5, 5.0, 0.0, 60.0, 0.5, 0.0, 0.0, 3.0, 0.0};
  for (const InplaneParams& p : {sharp, mild}) {
    const InplaneMaterial m(p, 0.0);
    for (int a = 0; a <= 8; ++a) {
      const double angle = a * std::numbers::pi / 16;
      const Eigen::Vector2d u(std::cos(angle), std::sin(angle));
      const auto held = [&](double s) { return m.psi(Eigen::Matrix2d::Identity() + s * u * u.transpose()); };
      const double h = 1e-3;
      double c = 0.0, sigma_prev = 0.0;
      for (double s = h; s <= 1.5; s += 0.01) {
        const double second = held(s + h) - 2 * held(s) + held(s - h);
        EXPECT_GE(second, -1e-12 * std::abs(held(s))) << "held width, angle " << angle << " s " << s;
        const UniaxialPoint pt = uniaxial_point(p, angle, s, c);
        ASSERT_TRUE(pt.converged) << angle << " " << s;
        c = pt.compression;
        EXPECT_GE(pt.stress, sigma_prev) << "free width, angle " << angle << " s " << s;
        sigma_prev = pt.stress;
      }
    }
  }
}

}  // namespace
}  // namespace yarnfit::shell
