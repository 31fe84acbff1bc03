// Frame-free rod bending with rest curvature (thesis 6.6; yarn_fit/energies/rod_bending.cpp):
// derivatives by finite differences, smoothness through straight corners, κ = 2 tan(φ/2),
// the circle limit, invariances, PSD projection and degenerate corners.

#include <gtest/gtest.h>

#include <algorithm>
#include <tuple>
#include <utility>
#include <vector>

#include "tests/yarn_fit/energies/element_fixtures.hpp"

namespace yarnfit::yarn {
namespace {

using namespace fixtures;

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
          "bending phi=" + std::to_string(phi) + " rest=" + std::to_string(rest_curvature), element_options()));
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
                    std::to_string(rest_curvature),
          element_options()));
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

}  // namespace
}  // namespace yarnfit::yarn
