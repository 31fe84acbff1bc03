// Yarn element energies (thesis 6.5–6.7, SPEC §3 "Yarn"): biphasic stretch, frame-free
// bending with rest curvature, two-barrier Simpson contact. Derivatives by finite differences,
// closed-form values, invariances, the barrier's onset and its +inf, PSD projections.
//
// Magnitudes are those of a real yarn tile in SI: radius R = 1 mm, edges ~1 mm, ks ~ 1–400 N,
// kb ~ ks R²/4, kc ~ 1e-2..1e3 · ks2/R.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "tests/yarn_fit/element_check.hpp"
#include "yarn_fit/energies/yarn_elements.hpp"

namespace yarnfit::yarn {
namespace {

using testing::ElementCheckOptions;
using testing::ErrorTally;
using testing::expect_element_derivatives;
using testing::min_eigenvalue;

constexpr double pi = std::numbers::pi;
constexpr double inf = std::numeric_limits<double>::infinity();

constexpr double yarn_radius = 1e-3;  // [m]
constexpr double edge_length = 1e-3;  // [m]
constexpr double ks2 = 400.0;         // [N]

// ------------------------------------------------------------------------------ helpers

Vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Vec3 v(normal(rng), normal(rng), normal(rng));
  while (v.norm() < 1e-3) v = Vec3(normal(rng), normal(rng), normal(rng));
  return v.normalized();
}

Eigen::Matrix3d random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
  q.normalize();
  return q.toRotationMatrix();
}

double uniform(std::mt19937& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

// A unit vector at angle `angle` from the unit vector u.
Vec3 turned(const Vec3& u, double angle, std::mt19937& rng) {
  Vec3 perp = random_unit(rng);
  perp = (perp - perp.dot(u) * u).normalized();
  return std::cos(angle) * u + std::sin(angle) * perp;
}

template <int N>
Vec<N> rotate_blocks(const Eigen::Matrix3d& r, const Vec<N>& v) {
  Vec<N> out;
  for (int k = 0; k < N / 3; ++k) out.template segment<3>(3 * k) = r * v.template segment<3>(3 * k);
  return out;
}

template <int N>
Mat<N> rotate_blocks(const Eigen::Matrix3d& r, const Mat<N>& m) {
  Mat<N> big = Mat<N>::Zero();
  for (int k = 0; k < N / 3; ++k) big.template block<3, 3>(3 * k, 3 * k) = r;
  return big * m * big.transpose();
}

template <int N>
Vec3 block_sum(const Vec<N>& g) {
  Vec3 s = Vec3::Zero();
  for (int k = 0; k < N / 3; ++k) s += g.template segment<3>(3 * k);
  return s;
}

void report(const std::string& what, const ErrorTally& tally) {
  std::cout << "[ FD      ] " << what << ": " << tally.count << " configurations, worst gradient "
            << tally.gradient << ", worst Hessian " << tally.hessian << "\n";
}

// ============================================================================ stretch

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
                                              std::string("stretch ") + phase.name));
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
    tally.add(expect_element_derivatives<6>(stretch_fn(edge_length, m), x, "stretch eps_s=1e-12"));
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

// ============================================================================ bending

constexpr double kb_default = ks2 * yarn_radius * yarn_radius / 4.0;  // 1e-4 N·m²

auto bending_fn(double la, double lb, double rest_curvature, bool project = false) {
  const RodBending model{.kb = kb_default};
  return [la, lb, rest_curvature, model, project](const Vec<9>& x, Vec<9>* g, Mat<9>* h) {
    return bending_element(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6), la, lb,
                           rest_curvature, model, g, h, project);
  };
}

// A corner with turning angle φ, edges la, lb, random orientation and position.
Vec<9> corner(double phi, double la, double lb, std::mt19937& rng) {
  const Vec3 x1(uniform(rng, -2e-3, 2e-3), uniform(rng, -2e-3, 2e-3), uniform(rng, -2e-3, 2e-3));
  const Vec3 u = random_unit(rng);
  const Vec3 v = turned(u, phi, rng);
  Vec<9> x;
  x << x1 - la * u, x1, x1 + lb * v;
  return x;
}

TEST(RodBending, DerivativesOfRandomCorners) {
  std::mt19937 rng(21);
  for (const double rest_curvature : {0.0, 0.3, 1.5}) {
    ErrorTally tally;
    for (int trial = 0; trial < 25; ++trial) {
      const double phi = uniform(rng, 5.0, 170.0) * pi / 180.0;
      const double la = edge_length * uniform(rng, 0.5, 1.5);
      const double lb = edge_length * uniform(rng, 0.5, 1.5);
      const Vec<9> x = corner(phi, la, lb, rng);
      const double rla = la * uniform(rng, 0.8, 1.2);
      const double rlb = lb * uniform(rng, 0.8, 1.2);
      tally.add(expect_element_derivatives<9>(
          bending_fn(rla, rlb, rest_curvature), x,
          "bending phi=" + std::to_string(phi) + " rest=" + std::to_string(rest_curvature)));
    }
    report("bending, rest curvature " + std::to_string(rest_curvature), tally);
  }
}

TEST(RodBending, NearStraightCornersAreFiniteAndSmooth) {
  std::mt19937 rng(22);
  for (const double rest_curvature : {0.0, 0.2}) {
    ErrorTally tally;
    for (const double phi : {1e-3, 3e-3, 1e-2}) {
      const Vec<9> x = corner(phi, edge_length, 1.3 * edge_length, rng);
      Vec<9> g;
      Mat<9> h, p;
      const auto f = bending_fn(edge_length, 1.3 * edge_length, rest_curvature);
      EXPECT_TRUE(std::isfinite(f(x, &g, &h)));
      EXPECT_TRUE(g.allFinite());
      EXPECT_TRUE(h.allFinite());
      (void)bending_fn(edge_length, 1.3 * edge_length, rest_curvature, true)(x, nullptr, &p);
      EXPECT_TRUE(p.allFinite());
      tally.add(expect_element_derivatives<9>(
          f, x, "near-straight phi=" + std::to_string(phi) + " rest=" +
                    std::to_string(rest_curvature)));
    }
    report("bending near straight, rest curvature " + std::to_string(rest_curvature), tally);
  }
  // Exactly straight: finite everywhere, zero energy and force without rest curvature.
  Vec<9> x;
  x << 0.0, 0.0, 0.0, 1e-3, 0.0, 0.0, 2.2e-3, 0.0, 0.0;
  Vec<9> g;
  Mat<9> h;
  EXPECT_EQ(bending_fn(1e-3, 1.2e-3, 0.0)(x, &g, &h), 0.0);
  EXPECT_EQ(g.lpNorm<Eigen::Infinity>(), 0.0);
  EXPECT_TRUE(h.allFinite());
  const double w = bending_fn(1e-3, 1.2e-3, 0.2)(x, &g, &h);
  EXPECT_NEAR(w, kb_default / 2.2e-3 * 0.2 * 0.2, 1e-7 * w);
  EXPECT_TRUE(g.allFinite());
  EXPECT_TRUE(h.allFinite());
}

TEST(RodBending, CornerCurvatureIsTwiceTanHalfAngle) {
  std::mt19937 rng(23);
  for (const double deg : {1.0, 30.0, 90.0, 120.0, 179.0}) {
    const double phi = deg * pi / 180.0;
    const Vec<9> x = corner(phi, 0.7e-3, 1.9e-3, rng);
    EXPECT_NEAR(corner_curvature(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6)),
                2.0 * std::tan(phi / 2.0), 1e-9 * 2.0 * std::tan(phi / 2.0))
        << deg << " deg";
  }
}

TEST(RodBending, InscribedPolygonMatchesCircleEnergy) {
  const double rho = 5e-3;  // circle radius [m]
  const RodBending model{.kb = kb_default};
  double previous_error = inf;
  for (const int n : {6, 12, 50, 200, 1000}) {
    const double step = 2.0 * pi / n;
    const auto vertex = [rho, step](int k) {
      return Vec3(rho * std::cos(step * k), rho * std::sin(step * k), 0.0);
    };
    const double len = 2.0 * rho * std::sin(pi / n);
    const double kappa = 2.0 * std::tan(pi / n);
    const double kappa_smoothed = std::sqrt(kappa * kappa + 1e-16) - 1e-8;
    double total = 0.0;
    for (int k = 0; k < n; ++k) {
      const double w = bending_element(vertex(k - 1), vertex(k), vertex(k + 1), len, len, 0.0,
                                       model, nullptr, nullptr, false);
      EXPECT_NEAR(w, kb_default / (2.0 * len) * kappa_smoothed * kappa_smoothed, 1e-9 * w);
      EXPECT_NEAR(corner_curvature(vertex(k - 1), vertex(k), vertex(k + 1)), kappa, 1e-9 * kappa);
      total += w;
    }
    // Σ = n kb tan(π/n) / (ρ cos(π/n))  ->  π kb / ρ = ∫ ½ kb (1/ρ)² ds, error ≈ (5/6)(π/n)².
    // (κ smoothing: (κs/κ)² = 1 − O(δ/κ), with the exact factor the sum matches to round-off.)
    const double closed = n * kb_default * std::tan(pi / n) / (rho * std::cos(pi / n)) *
                          (kappa_smoothed / kappa) * (kappa_smoothed / kappa);
    EXPECT_NEAR(total, closed, 1e-9 * closed) << n;
    const double continuum = pi * kb_default / rho;
    const double error = std::abs(total / continuum - 1.0);
    EXPECT_LT(error, previous_error) << n;
    EXPECT_NEAR(error, 5.0 / 6.0 * (pi / n) * (pi / n), 0.5 * (pi / n) * (pi / n) + 1e-6) << n;
    previous_error = error;

    // With the polygon's own curvature as rest curvature the corner is at rest.
    Vec<9> g, g0;
    const double w_rest = bending_element(vertex(-1), vertex(0), vertex(1), len, len, kappa,
                                          model, &g, nullptr, false);
    (void)bending_element(vertex(-1), vertex(0), vertex(1), len, len, 0.0, model, &g0, nullptr,
                          false);
    EXPECT_LT(w_rest, 1e-12 * total);
    EXPECT_LT(g.norm(), 1e-5 * g0.norm());
  }
  EXPECT_LT(previous_error, 1e-5);
}

TEST(RodBending, RigidMotionAndRotationInvariance) {
  std::mt19937 rng(24);
  for (int trial = 0; trial < 10; ++trial) {
    const Vec<9> x = corner(uniform(rng, 0.1, 2.5), edge_length, 0.8 * edge_length, rng);
    const Eigen::Matrix3d r = random_rotation(rng);
    const Vec3 shift = 1e-2 * random_unit(rng);
    Vec<9> y;
    for (int k = 0; k < 3; ++k) y.segment<3>(3 * k) = r * x.segment<3>(3 * k) + shift;
    const auto f = bending_fn(edge_length, 0.8 * edge_length, 0.5);
    Vec<9> gx, gy;
    Mat<9> hx, hy;
    const double wx = f(x, &gx, &hx);
    const double wy = f(y, &gy, &hy);
    EXPECT_NEAR(wy, wx, 1e-10 * wx);
    EXPECT_LT((gy - rotate_blocks<9>(r, gx)).lpNorm<Eigen::Infinity>(),
              1e-8 * gx.lpNorm<Eigen::Infinity>());
    EXPECT_LT((hy - rotate_blocks<9>(r, hx)).lpNorm<Eigen::Infinity>(),
              1e-8 * hx.lpNorm<Eigen::Infinity>());
    // Translations carry no force; rotations carry no torque.
    EXPECT_LT(block_sum<9>(gx).norm(), 1e-9 * gx.norm());
    Vec3 torque = Vec3::Zero();
    for (int k = 0; k < 3; ++k) torque += x.segment<3>(3 * k).cross(gx.segment<3>(3 * k));
    EXPECT_LT(torque.norm(), 1e-9 * gx.norm() * x.norm());
  }
}

TEST(RodBending, ProjectionIsPsd) {
  std::mt19937 rng(25);
  int indefinite = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const double phi = uniform(rng, 5.0, 170.0) * pi / 180.0;
    const double rest_curvature = trial % 2 == 0 ? 0.0 : 2.0 * std::tan(uniform(rng, 0.0, 1.4));
    const Vec<9> x = corner(phi, edge_length, 1.1 * edge_length, rng);
    Mat<9> h, p;
    (void)bending_fn(edge_length, 1.1 * edge_length, rest_curvature, false)(x, nullptr, &h);
    (void)bending_fn(edge_length, 1.1 * edge_length, rest_curvature, true)(x, nullptr, &p);
    const double scale = h.lpNorm<Eigen::Infinity>();
    if (min_eigenvalue<9>(h) < -1e-8 * scale) ++indefinite;
    EXPECT_GE(min_eigenvalue<9>(p), -1e-10 * scale);
    EXPECT_LT((p - p.transpose()).lpNorm<Eigen::Infinity>(), 1e-12 * scale);
  }
  EXPECT_GT(indefinite, 0) << "no indefinite bending Hessian seen: projection untested";
}

TEST(RodBending, DegenerateCornersAreInfinite) {
  const Vec3 o = Vec3::Zero();
  const Vec3 ex(1e-3, 0.0, 0.0);
  const RodBending model{.kb = kb_default};
  for (const auto& [x0, x1, x2] : {std::tuple{o, o, ex}, std::tuple{o, ex, ex},
                                   std::tuple{o, ex, Vec3(o)}}) {  // zero a, zero b, folded
    const double w = bending_element(x0, x1, x2, 1e-3, 1e-3, 0.1, model, nullptr, nullptr, false);
    EXPECT_TRUE(std::isinf(w) && w > 0.0);
  }
  EXPECT_TRUE(std::isinf(corner_curvature(o, ex, o)));
}

// ============================================================================ contact

TwoBarrierContact contact_model(double kc1_relative = 1.0) {
  return {.kc1 = kc1_relative * ks2 / yarn_radius,
          .r1 = yarn_radius,
          .kc2 = 1e3 * ks2 / yarn_radius,
          .r2 = 0.25 * yarn_radius};
}

auto contact_fn(const TwoBarrierContact& model, double la = edge_length, double lb = edge_length,
                bool project = false) {
  return [model, la, lb, project](const Vec<12>& x, Vec<12>* g, Mat<12>* h) {
    return contact_element(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6), x.segment<3>(9), la,
                           lb, model, g, h, project);
  };
}

Vec<12> pack(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1) {
  Vec<12> x;
  x << a0, a1, b0, b1;
  return x;
}

// Segment pairs whose closest quadrature point pair is at distance d.
Vec<12> parallel_pair(double d, double shift) {
  const double l = edge_length;
  return pack(Vec3(0, 0, 0), Vec3(l, 0, 0), Vec3(shift, d, 0), Vec3(l + shift, d, 0));
}
Vec<12> crossing_pair(double d) {
  const double l = edge_length;
  return pack(Vec3(-l / 2, 0, 0), Vec3(l / 2, 0, 0), Vec3(0, -l / 2, d), Vec3(0, l / 2, d));
}
Vec<12> skew_pair(double d) {  // 60° apart, midpoints at distance d, b tilted out of plane
  const double l = edge_length;
  const Vec3 mid_b(0.0, 0.0, d);
  const Vec3 dir_b = Vec3(std::cos(pi / 3), std::sin(pi / 3), 0.0);
  return pack(Vec3(-l / 2, 0, 0), Vec3(l / 2, 0, 0), mid_b - 0.45 * l * dir_b + Vec3(0, 0, 0.1 * l),
              mid_b + 0.55 * l * dir_b + Vec3(0, 0, -0.1 * l));
}

TEST(Barrier, ScalarDerivativesAndLimits) {
  ErrorTally tally;
  for (const double x : {0.01, 0.1, 0.3, 0.5, 0.8, 0.95, 0.999}) {
    const auto f = [](const Vec<1>& y, Vec<1>* g, Mat<1>* h) {
      if (g != nullptr) (*g)(0) = Barrier::first(y(0));
      if (h != nullptr) (*h)(0, 0) = Barrier::second(y(0));
      return Barrier::value(y(0));
    };
    ElementCheckOptions options;
    options.length_scale = std::min(x, 1.0 - x);
    tally.add(expect_element_derivatives<1>(f, Vec<1>(x), "barrier x=" + std::to_string(x),
                                            options));
  }
  report("barrier f(x)^2", tally);
  // f(x) = −(x − 1)² log x.
  EXPECT_NEAR(Barrier::value(0.5), std::pow(0.25 * std::log(2.0), 2), 1e-15);
  EXPECT_EQ(Barrier::value(1.0), 0.0);
  EXPECT_EQ(Barrier::value(2.0), 0.0);
  EXPECT_EQ(Barrier::first(1.0), 0.0);
  EXPECT_EQ(Barrier::second(1.0), 0.0);
  EXPECT_EQ(Barrier::first(1.5), 0.0);
  EXPECT_EQ(Barrier::second(1.5), 0.0);
  for (const double x : {0.0, -0.5}) {
    EXPECT_TRUE(std::isinf(Barrier::value(x)) && Barrier::value(x) > 0.0);
    EXPECT_FALSE(std::isnan(Barrier::first(x)));
    EXPECT_FALSE(std::isnan(Barrier::second(x)));
  }
  EXPECT_GT(Barrier::value(1e-300), 1e5);
}

TEST(Barrier, C2OnsetAtOne) {
  // f ≈ h³ for x = 1 − h, so f² ≈ h⁶, (f²)' ≈ −6h⁵, (f²)'' ≈ 30h⁴: all three vanish at x = 1.
  for (const double h : {1e-2, 1e-3, 1e-4}) {
    const double x = 1.0 - h;
    EXPECT_NEAR(Barrier::value(x) / std::pow(h, 6), 1.0, 2.0 * h);
    EXPECT_NEAR(Barrier::first(x) / (-6.0 * std::pow(h, 5)), 1.0, 3.0 * h);
    EXPECT_NEAR(Barrier::second(x) / (30.0 * std::pow(h, 4)), 1.0, 4.0 * h);
  }
  EXPECT_LT(Barrier::second(1.0 - 1e-6), 1e-22);
  EXPECT_EQ(Barrier::second(1.0 + 1e-6), 0.0);
}

TEST(TwoBarrierContact, LawDerivativesMonotoneAndCutoff) {
  const TwoBarrierContact m = contact_model();
  EXPECT_DOUBLE_EQ(m.cutoff_distance(), 2.0 * yarn_radius);
  ErrorTally tally;
  for (const double d : {0.05e-3, 0.3e-3, 0.49e-3, 0.51e-3, 1e-3, 1.9e-3, 1.999e-3}) {
    const auto f = [&m](const Vec<1>& y, Vec<1>* g, Mat<1>* h) {
      if (g != nullptr) (*g)(0) = m.de(y(0));
      if (h != nullptr) (*h)(0, 0) = m.d2e(y(0));
      return m.e(y(0));
    };
    ElementCheckOptions options;
    options.length_scale = std::min({d, std::abs(d - 0.5e-3), 2e-3 - d});
    tally.add(expect_element_derivatives<1>(f, Vec<1>(d), "law D=" + std::to_string(d), options));
  }
  report("two-barrier law e(D)", tally);

  // Monotone decreasing on (0, cutoff), zero beyond; the stiff barrier adds below 2 R2.
  double previous = inf;
  for (int k = 1; k <= 2200; ++k) {
    const double d = 1e-6 * k;
    const double e = m.e(d);
    EXPECT_LE(m.de(d), 0.0) << d;
    if (d < m.cutoff_distance()) {
      EXPECT_LT(e, previous) << d;
    } else {
      EXPECT_EQ(e, 0.0) << d;
      EXPECT_EQ(m.de(d), 0.0) << d;
      EXPECT_EQ(m.d2e(d), 0.0) << d;
    }
    previous = e;
  }
  EXPECT_NEAR(m.e(1e-3), m.kc1 * Barrier::value(0.5), 1e-12 * m.e(1e-3));
  EXPECT_NEAR(m.e(0.25e-3), m.kc1 * Barrier::value(0.125) + m.kc2 * Barrier::value(0.5),
              1e-12 * m.e(0.25e-3));
  EXPECT_TRUE(std::isinf(m.e(0.0)) && m.e(0.0) > 0.0);
}

TEST(ContactElement, DerivativesNearOuterInnerAndBetween) {
  const TwoBarrierContact m = contact_model();
  const double outer = 2.0 * m.r1;
  const double inner = 2.0 * m.r2;
  struct Band {
    const char* name;
    std::vector<double> distances;
  };
  const Band bands[] = {
      {"outer", {0.9 * outer, 0.99 * outer, 0.999 * outer}},
      {"inner", {0.5 * inner, 0.9 * inner, 0.99 * inner, 0.999 * inner, 1.01 * inner}},
      {"between", {0.4 * outer, 0.6 * outer, 0.8 * outer}},
  };
  for (const Band& band : bands) {
    ErrorTally tally;
    for (const double d : band.distances) {
      const auto f = contact_fn(m, 1.1 * edge_length, 0.9 * edge_length);
      // Shifted along the yarn, but by less than the room left below the cutoff.
      const double shift = std::min(0.3 * edge_length, 0.5 * std::sqrt(outer * outer - d * d));
      const std::pair<std::string, Vec<12>> configurations[] = {
          {"parallel", parallel_pair(d, 0.0)},
          {"parallel shifted", parallel_pair(d, shift)},
          {"crossing", crossing_pair(d)},
          {"skew", skew_pair(d)},
      };
      for (const auto& [name, x] : configurations) {
        const std::string what = name + " D=" + std::to_string(d);
        EXPECT_GT(f(x, nullptr, nullptr), 0.0) << what << ": not in contact, check is vacuous";
        tally.add(expect_element_derivatives<12>(f, x, what));
      }
    }
    report(std::string("contact, ") + band.name + " radius", tally);
  }
  // Random skew pairs in the contact range, with a softer and a stiffer soft barrier.
  std::mt19937 rng(31);
  ErrorTally tally;
  for (int trial = 0; trial < 30; ++trial) {
    const TwoBarrierContact mr = contact_model(std::pow(10.0, uniform(rng, -2.0, 2.0)));
    const Vec3 ca = 1e-3 * random_unit(rng);
    const Vec3 cb = ca + uniform(rng, 0.3, 2.0) * 1e-3 * random_unit(rng);
    const Vec3 ua = random_unit(rng), ub = random_unit(rng);
    const double la = uniform(rng, 0.5, 1.5) * edge_length;
    const double lb = uniform(rng, 0.5, 1.5) * edge_length;
    const Vec<12> x = pack(ca - 0.5 * la * ua, ca + 0.5 * la * ua, cb - 0.5 * lb * ub,
                           cb + 0.5 * lb * ub);
    Vec<12> g;
    if (contact_fn(mr, la, lb)(x, &g, nullptr) == 0.0) continue;  // nothing within reach
    tally.add(expect_element_derivatives<12>(contact_fn(mr, la, lb), x,
                                             "random pair " + std::to_string(trial)));
  }
  EXPECT_GE(tally.count, 10);
  report("contact, random pairs", tally);
}

TEST(ContactElement, ExactlyZeroBeyondCutoff) {
  const TwoBarrierContact m = contact_model();
  const auto check_zero = [&m](const Vec<12>& x, const char* what) {
    Vec<12> g = Vec<12>::Constant(7.0);
    Mat<12> h = Mat<12>::Constant(7.0);
    EXPECT_EQ(contact_fn(m)(x, &g, &h), 0.0) << what;
    EXPECT_TRUE((g.array() == 0.0).all()) << what;
    EXPECT_TRUE((h.array() == 0.0).all()) << what;
  };
  // Bounding boxes apart: the broad phase answers.
  check_zero(parallel_pair(1.0001 * m.cutoff_distance(), 0.0), "parallel beyond cutoff");
  check_zero(crossing_pair(2.5e-3), "crossing beyond cutoff");
  // Bounding boxes overlap but every quadrature pair is beyond the cutoff (2.83 mm apart).
  check_zero(pack(Vec3(0, 0, 0), Vec3(4e-3, 4e-3, 0), Vec3(3e-3, -1e-3, 0), Vec3(7e-3, 3e-3, 0)),
             "diagonal pair with overlapping boxes");
  // Just inside: not zero.
  EXPECT_GT(contact_fn(m)(parallel_pair(0.999 * m.cutoff_distance(), 0.0), nullptr, nullptr),
            0.0);
}

TEST(ContactElement, SymmetricUnderSwappingSegments) {
  const TwoBarrierContact m = contact_model();
  for (const Vec<12>& x : {skew_pair(0.7e-3), crossing_pair(0.4e-3), parallel_pair(1.5e-3, 2e-4)}) {
    Vec<12> swapped;
    swapped << x.tail<6>(), x.head<6>();
    Vec<12> g, gs;
    Mat<12> h, hs;
    const double w = contact_fn(m, 1.2e-3, 0.8e-3)(x, &g, &h);
    const double ws = contact_fn(m, 0.8e-3, 1.2e-3)(swapped, &gs, &hs);
    ASSERT_GT(w, 0.0);
    EXPECT_NEAR(ws, w, 1e-13 * w);
    Vec<12> gs_back;
    gs_back << gs.tail<6>(), gs.head<6>();
    EXPECT_LT((gs_back - g).lpNorm<Eigen::Infinity>(), 1e-12 * g.lpNorm<Eigen::Infinity>());
    Mat<12> hs_back;
    hs_back << hs.bottomRightCorner<6, 6>(), hs.bottomLeftCorner<6, 6>(),
        hs.topRightCorner<6, 6>(), hs.topLeftCorner<6, 6>();
    EXPECT_LT((hs_back - h).lpNorm<Eigen::Infinity>(), 1e-12 * h.lpNorm<Eigen::Infinity>());
    // Contact forces are internal: they sum to zero.
    EXPECT_LT(block_sum<12>(g).norm(), 1e-12 * g.norm());
  }
}

TEST(ContactElement, CoincidentQuadraturePointsGiveInfinity) {
  const TwoBarrierContact m = contact_model();
  const double l = edge_length;
  // The midpoint of a is b0; a crossing at distance 0; identical segments.
  for (const Vec<12>& x :
       {pack(Vec3(-l / 2, 0, 0), Vec3(l / 2, 0, 0), Vec3(0, 0, 0), Vec3(0, l, 0)),
        crossing_pair(0.0), parallel_pair(0.0, 0.0)}) {
    Vec<12> g;
    Mat<12> h;
    const double w = contact_fn(m)(x, &g, &h);
    EXPECT_TRUE(std::isinf(w) && w > 0.0) << w;
    EXPECT_TRUE(std::isinf(contact_fn(m)(x, nullptr, nullptr)));
  }
  // Close but apart: finite and large.
  const double w = contact_fn(m)(crossing_pair(1e-9), nullptr, nullptr);
  EXPECT_TRUE(std::isfinite(w));
  EXPECT_GT(w, 1e3 * contact_fn(m)(crossing_pair(0.25e-3), nullptr, nullptr));
}

TEST(ContactElement, EnergyDecreasesWithSeparation) {
  const TwoBarrierContact m = contact_model();
  double previous = inf;
  for (int k = 1; k <= 100; ++k) {
    const double d = 0.02e-3 * k;  // up to the cutoff
    const double w = contact_fn(m)(crossing_pair(d), nullptr, nullptr);
    if (d < m.cutoff_distance() * (1.0 - 1e-12)) {
      EXPECT_LT(w, previous) << d;
    }
    previous = w;
  }
  EXPECT_EQ(previous, 0.0);
}

TEST(ContactElement, AnalyticProjectionIsPsd) {
  const TwoBarrierContact m = contact_model();
  int indefinite = 0;
  for (const Vec<12>& x : {parallel_pair(0.3e-3, 0.0), parallel_pair(1.2e-3, 3e-4),
                           crossing_pair(0.2e-3), crossing_pair(1.0e-3), crossing_pair(1.98e-3),
                           skew_pair(0.45e-3), skew_pair(1.5e-3)}) {
    Mat<12> h, p;
    (void)contact_fn(m, edge_length, edge_length, false)(x, nullptr, &h);
    (void)contact_fn(m, edge_length, edge_length, true)(x, nullptr, &p);
    const double scale = h.lpNorm<Eigen::Infinity>();
    ASSERT_GT(scale, 0.0);
    if (min_eigenvalue<12>(h) < -1e-8 * scale) ++indefinite;
    EXPECT_GE(min_eigenvalue<12>(p), -1e-12 * scale);
    EXPECT_EQ((h - h.transpose()).lpNorm<Eigen::Infinity>(), 0.0);  // exactly symmetric
    EXPECT_EQ((p - p.transpose()).lpNorm<Eigen::Infinity>(), 0.0);
    // Clamping removes only curvature: h − p is negative semi-definite.
    EXPECT_GE(min_eigenvalue<12>(Mat<12>(p - h)), -1e-12 * scale);
  }
  EXPECT_GT(indefinite, 0) << "no indefinite contact Hessian seen: projection untested";
}

}  // namespace
}  // namespace yarnfit::yarn
