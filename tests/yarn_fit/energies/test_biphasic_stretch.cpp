// Biphasic yarn stretch (thesis 6.5; yarn_fit/energies/biphasic_stretch.cpp): derivatives
// by finite differences in every phase, closed-form values, C¹ kinks, invariances, the
// analytic PSD projection and the +inf of a zero-length edge.

#include <gtest/gtest.h>

#include <algorithm>
#include <tuple>
#include <utility>
#include <vector>

#include "tests/yarn_fit/energies/element_fixtures.hpp"

namespace yarnfit::yarn {
namespace {

using namespace fixtures;

BiphasicStretch stretch_model() { return {.ks1 = 20.0, .ks2 = ks2, .eps_s = 0.05}; }

auto stretch_fn(double rest_length, const BiphasicStretch& model, bool project = false) {
  return [rest_length, model, project](const Vec<6>& x, Vec<6>* g, Mat<6>* h) {
    return stretch_element(x.head<3>(), x.tail<3>(), rest_length, model, g, h, project);
  };
}

Vec<6> edge_at_strain(double strain, double rest_length, std::mt19937& rng) {
  Vec<6> x;
  const Vec3 x0(uniform(rng, -1e-3, 1e-3), uniform(rng, -1e-3, 1e-3), uniform(rng, -1e-3, 1e-3));
  x << x0, x0 + rest_length * (1.0 + strain) * random_unit(rng);
  return x;
}

TEST(BiphasicStretch, DerivativesInEachPhase) {
  std::mt19937 rng(11);
  const BiphasicStretch model = stretch_model();
  struct Phase {
    const char* name;
    double lo, hi;
  };
  for (const Phase& phase : {Phase{"compression", -0.3, -0.005}, Phase{"soft", 0.004, 0.046},
                             Phase{"stiff", 0.055, 0.4}}) {
    ErrorTally tally;
    for (int trial = 0; trial < 20; ++trial) {
      const double rest = edge_length * uniform(rng, 0.5, 1.5);
      const double strain = uniform(rng, phase.lo, phase.hi);
      const Vec<6> x = edge_at_strain(strain, rest, rng);
      tally.add(expect_element_derivatives<6>(stretch_fn(rest, model), x,
                                              std::string("stretch ") + phase.name, element_options()));
    }
    report(std::string("stretch, ") + phase.name, tally);
  }
}

TEST(BiphasicStretch, ClosedFormValues) {
  const BiphasicStretch m = stretch_model();
  EXPECT_DOUBLE_EQ(m.w(-0.1), 0.5 * 400.0 * 0.01);                                // 2 N
  EXPECT_DOUBLE_EQ(m.w(0.03), 0.5 * 20.0 * 0.03 * 0.03);                          // 0.009 N
  EXPECT_DOUBLE_EQ(m.w(0.15), 0.5 * (400.0 * 0.01 + 20.0 * 0.05 * (0.3 - 0.05)));  // 2.125 N
  EXPECT_DOUBLE_EQ(m.dw(-0.1), -40.0);
  EXPECT_DOUBLE_EQ(m.dw(0.03), 0.6);
  EXPECT_DOUBLE_EQ(m.dw(0.15), 400.0 * 0.1 + 20.0 * 0.05);
  EXPECT_EQ(m.w(0.0), 0.0);
  EXPECT_EQ(m.dw(0.0), 0.0);

  // The element is L̄ w(ε) with ε from the current length, tension w'(ε) along the edge.
  const double rest = 1.2e-3;
  const Vec3 x0(1e-3, -2e-3, 0.5e-3);
  const Vec3 x1 = x0 + rest * 1.15 * Vec3(0.0, 0.6, 0.8);
  Vec<6> g;
  EXPECT_NEAR(stretch_element(x0, x1, rest, m, &g, nullptr, false), rest * 2.125, 1e-15);
  EXPECT_NEAR(g.tail<3>().norm(), m.dw(0.15), 1e-10);
  EXPECT_NEAR(g.tail<3>().dot(Vec3(0.0, 0.6, 0.8)), m.dw(0.15), 1e-10);
  EXPECT_LT((g.head<3>() + g.tail<3>()).norm(), 1e-12);
}

TEST(BiphasicStretch, C1AtBothKinksWithStatedOneSidedCurvatures) {
  const BiphasicStretch m = stretch_model();
  const double tiny = 1e-12;
  for (const double kink : {0.0, m.eps_s}) {
    EXPECT_NEAR(m.w(kink - tiny), m.w(kink + tiny), 1e-9) << "w jumps at " << kink;
    EXPECT_NEAR(m.dw(kink - tiny), m.dw(kink + tiny), 1e-9) << "w' jumps at " << kink;
  }
  // w'' = ks2 | ks1 | ks2, and d2w reports the right limit at a kink.
  EXPECT_EQ(m.d2w(-tiny), m.ks2);
  EXPECT_EQ(m.d2w(0.0), m.ks1);
  EXPECT_EQ(m.d2w(m.eps_s - tiny), m.ks1);
  EXPECT_EQ(m.d2w(m.eps_s), m.ks2);
  EXPECT_EQ(m.d2w(m.eps_s + tiny), m.ks2);
  // The curvature jump is real (ks1 ≠ ks2): the kinks are C¹, not C².
  EXPECT_GT(std::abs(m.d2w(-tiny) - m.d2w(tiny)), 100.0);
}

TEST(BiphasicStretch, VanishingSoftPhaseStaysFinite) {
  std::mt19937 rng(12);
  BiphasicStretch m = stretch_model();
  m.eps_s = 1e-12;
  for (const double strain : {-0.1, -1e-6, 0.0, 5e-13, 1e-12, 2e-12, 1e-6, 0.1}) {
    EXPECT_TRUE(std::isfinite(m.w(strain)));
    EXPECT_TRUE(std::isfinite(m.dw(strain)));
    EXPECT_TRUE(std::isfinite(m.d2w(strain)));
    // Tends to the single-stiffness spring ½ ks2 ε².
    EXPECT_NEAR(m.w(strain), 0.5 * ks2 * strain * strain, 1e-10 * (1.0 + std::abs(strain)));
  }
  ErrorTally tally;
  for (const double strain : {-0.1, 0.1, 0.3}) {
    const Vec<6> x = edge_at_strain(strain, edge_length, rng);
    Vec<6> g;
    Mat<6> h;
    EXPECT_TRUE(std::isfinite(stretch_element(x.head<3>(), x.tail<3>(), edge_length, m, &g, &h,
                                              true)));
    EXPECT_TRUE(g.allFinite());
    EXPECT_TRUE(h.allFinite());
    tally.add(expect_element_derivatives<6>(stretch_fn(edge_length, m), x, "stretch eps_s=1e-12", element_options()));
  }
  report("stretch, eps_s = 1e-12", tally);
}

TEST(BiphasicStretch, RigidMotionInvariance) {
  std::mt19937 rng(13);
  const BiphasicStretch m = stretch_model();
  for (int trial = 0; trial < 10; ++trial) {
    const Vec<6> x = edge_at_strain(uniform(rng, -0.2, 0.3), edge_length, rng);
    const Eigen::Matrix3d r = random_rotation(rng);
    const Vec3 shift = 1e-2 * random_unit(rng);
    Vec<6> y;
    y << r * x.head<3>() + shift, r * x.tail<3>() + shift;
    Vec<6> gx, gy;
    Mat<6> hx, hy;
    const double wx = stretch_element(x.head<3>(), x.tail<3>(), edge_length, m, &gx, &hx, false);
    const double wy = stretch_element(y.head<3>(), y.tail<3>(), edge_length, m, &gy, &hy, false);
    EXPECT_NEAR(wy, wx, 1e-12 * std::abs(wx));
    EXPECT_LT((gy - rotate_blocks<6>(r, gx)).lpNorm<Eigen::Infinity>(),
              1e-9 * gx.lpNorm<Eigen::Infinity>());
    EXPECT_LT((hy - rotate_blocks<6>(r, hx)).lpNorm<Eigen::Infinity>(),
              1e-9 * hx.lpNorm<Eigen::Infinity>());
  }
}

TEST(BiphasicStretch, AnalyticProjection) {
  std::mt19937 rng(14);
  const BiphasicStretch m = stretch_model();
  for (const double strain : {0.02, 0.2}) {  // stretched: the Hessian is PSD already
    const Vec<6> x = edge_at_strain(strain, edge_length, rng);
    Mat<6> h, p;
    (void)stretch_element(x.head<3>(), x.tail<3>(), edge_length, m, nullptr, &h, false);
    (void)stretch_element(x.head<3>(), x.tail<3>(), edge_length, m, nullptr, &p, true);
    EXPECT_GE(min_eigenvalue<6>(h), -1e-9 * h.norm());
    EXPECT_EQ((h - h.transpose()).lpNorm<Eigen::Infinity>(), 0.0);  // exactly symmetric
    EXPECT_LT((p - h).lpNorm<Eigen::Infinity>(), 1e-12 * h.lpNorm<Eigen::Infinity>());
  }
  // Compressed: the transverse curvature w'/l < 0 makes the raw Hessian indefinite.
  const Vec<6> x = edge_at_strain(-0.1, edge_length, rng);
  Mat<6> h, p;
  (void)stretch_element(x.head<3>(), x.tail<3>(), edge_length, m, nullptr, &h, false);
  (void)stretch_element(x.head<3>(), x.tail<3>(), edge_length, m, nullptr, &p, true);
  const double scale = h.lpNorm<Eigen::Infinity>();
  EXPECT_LT(min_eigenvalue<6>(h), -1e-3 * scale);
  EXPECT_GE(min_eigenvalue<6>(p), -1e-12 * scale);
  // Only the transverse part is clamped: the axial stiffness 2 w''/L̄ survives.
  const Eigen::SelfAdjointEigenSolver<Mat<6>> eig(p, Eigen::EigenvaluesOnly);
  EXPECT_NEAR(eig.eigenvalues().maxCoeff(), 2.0 * ks2 / edge_length, 1e-9 * scale);
}

TEST(BiphasicStretch, ZeroLengthEdgeIsInfinite) {
  const Vec3 x(1e-3, 2e-3, 3e-3);
  const double value = stretch_element(x, x, edge_length, stretch_model(), nullptr, nullptr, false);
  EXPECT_TRUE(std::isinf(value) && value > 0.0);
}

}  // namespace
}  // namespace yarnfit::yarn
