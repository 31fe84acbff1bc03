// Rod bending with a rest curvature vector in carried material frames (thesis 6.6;
// yarn_fit/energies/rod_bending.cpp): derivatives by finite differences (anchors away from the
// edges, so the frame transport is exercised), smoothness through straight corners,
// κ = 2 tan(φ/2), the circle limit, the magnitude form within the bending plane, a turned
// bending plane costing energy, invariances, PSD projection and degenerate corners.

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

using Rest = Eigen::Vector2d;

auto bending_fn(double la, double lb, const CornerFrames& frames, const Rest& rest, bool project = false) {
  const RodBending model{.kb = kb_default};
  return [la, lb, frames, rest, model, project](const Vec<9>& x, Vec<9>* g, Mat<9>* h) {
    return bending_element(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6), la, lb, frames, rest, model, g, h,
                           project);
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

// Frames anchored on the corner's own edges (the corner as read), the second carried from the
// first so the two differ by no twist.
CornerFrames frames_on(const Vec<9>& x) {
  const EdgeAnchor in = anchor_along(x.segment<3>(3) - x.segment<3>(0));
  const EdgeAnchor out = carried_anchor(in, Eigen::Matrix3d::Identity(), x.segment<3>(6) - x.segment<3>(3));
  return {in, out};
}

// Frames anchored on edges turned by up to `angle` away from the corner's, with a twist
// between them: the corner has moved since it was read.
CornerFrames frames_away(const Vec<9>& x, double angle, std::mt19937& rng) {
  const Vec3 a = x.segment<3>(3) - x.segment<3>(0);
  const Vec3 b = x.segment<3>(6) - x.segment<3>(3);
  const EdgeAnchor in = anchor_along(turned(a.normalized(), uniform(rng, 0.0, angle), rng));
  EdgeAnchor out = carried_anchor(in, Eigen::Matrix3d::Identity(), turned(b.normalized(), uniform(rng, 0.0, angle), rng));
  const double twist = uniform(rng, -0.2, 0.2);
  out.director = std::cos(twist) * out.director + std::sin(twist) * out.tangent.cross(out.director);
  return {in, out};
}

Rest random_rest(double magnitude, std::mt19937& rng) {
  const double angle = uniform(rng, -pi, pi);
  return magnitude * Rest(std::cos(angle), std::sin(angle));
}

TEST(RodBending, DerivativesOfRandomCorners) {
  std::mt19937 rng(21);
  for (const double rest_magnitude : {0.0, 0.3, 1.5}) {
    ErrorTally tally;
    for (int trial = 0; trial < 25; ++trial) {
      const double phi = uniform(rng, 5.0, 170.0) * pi / 180.0;
      const double la = edge_length * uniform(rng, 0.5, 1.5);
      const double lb = edge_length * uniform(rng, 0.5, 1.5);
      const Vec<9> x = corner(phi, la, lb, rng);
      const double rla = la * uniform(rng, 0.8, 1.2);
      const double rlb = lb * uniform(rng, 0.8, 1.2);
      tally.add(expect_element_derivatives<9>(
          bending_fn(rla, rlb, frames_away(x, 1.0, rng), random_rest(rest_magnitude, rng)), x,
          "bending phi=" + std::to_string(phi) + " rest=" + std::to_string(rest_magnitude), element_options()));
    }
    report("bending, rest curvature " + std::to_string(rest_magnitude), tally);
  }
}

TEST(RodBending, NearStraightCornersAreFiniteAndSmooth) {
  std::mt19937 rng(22);
  for (const double rest_magnitude : {0.0, 0.2}) {
    ErrorTally tally;
    for (const double phi : {1e-3, 3e-3, 1e-2}) {
      const Vec<9> x = corner(phi, edge_length, 1.3 * edge_length, rng);
      const CornerFrames frames = frames_away(x, 0.3, rng);
      const Rest rest = random_rest(rest_magnitude, rng);
      Vec<9> g;
      Mat<9> h, p;
      const auto f = bending_fn(edge_length, 1.3 * edge_length, frames, rest);
      EXPECT_TRUE(std::isfinite(f(x, &g, &h)));
      EXPECT_TRUE(g.allFinite());
      EXPECT_TRUE(h.allFinite());
      (void)bending_fn(edge_length, 1.3 * edge_length, frames, rest, true)(x, nullptr, &p);
      EXPECT_TRUE(p.allFinite());
      tally.add(expect_element_derivatives<9>(
          f, x, "near-straight phi=" + std::to_string(phi) + " rest=" + std::to_string(rest_magnitude),
          element_options()));
    }
    report("bending near straight, rest curvature " + std::to_string(rest_magnitude), tally);
  }
  // Exactly straight: zero energy and force without rest curvature, c‖κ̄‖² with it.
  Vec<9> x;
  x << 0.0, 0.0, 0.0, 1e-3, 0.0, 0.0, 2.2e-3, 0.0, 0.0;
  const CornerFrames frames = frames_on(x);
  Vec<9> g;
  Mat<9> h;
  EXPECT_EQ(bending_fn(1e-3, 1.2e-3, frames, Rest::Zero())(x, &g, &h), 0.0);
  EXPECT_EQ(g.lpNorm<Eigen::Infinity>(), 0.0);
  EXPECT_TRUE(h.allFinite());
  const double w = bending_fn(1e-3, 1.2e-3, frames, Rest(0.12, -0.16))(x, &g, &h);
  EXPECT_NEAR(w, kb_default / 2.2e-3 * 0.2 * 0.2, 1e-12 * w);
  EXPECT_TRUE(g.allFinite());
  EXPECT_TRUE(h.allFinite());
}

TEST(RodBending, CornerCurvatureIsTwiceTanHalfAngle) {
  std::mt19937 rng(23);
  for (const double deg : {1.0, 30.0, 90.0, 120.0, 179.0}) {
    const double phi = deg * pi / 180.0;
    const Vec<9> x = corner(phi, 0.7e-3, 1.9e-3, rng);
    const double expected = 2.0 * std::tan(phi / 2.0);
    EXPECT_NEAR(corner_curvature(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6)), expected, 1e-9 * expected)
        << deg << " deg";
    // The vector has that length in any frames, twisted against each other or not.
    EXPECT_NEAR(corner_curvature(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6), frames_on(x)).norm(), expected,
                1e-9 * expected)
        << deg << " deg";
    EXPECT_NEAR(corner_curvature(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6), frames_away(x, 1.0, rng)).norm(),
                expected, 1e-9 * expected)
        << deg << " deg";
  }
}

TEST(RodBending, InscribedPolygonMatchesCircleEnergy) {
  const double rho = 5e-3;  // circle radius [m]
  const RodBending model{.kb = kb_default};
  double previous_error = inf;
  for (const int n : {6, 12, 50, 200, 1000}) {
    const double step = 2.0 * pi / n;
    const auto vertex = [rho, step](int k) { return Vec3(rho * std::cos(step * k), rho * std::sin(step * k), 0.0); };
    const auto at = [&](int k) {
      Vec<9> x;
      x << vertex(k - 1), vertex(k), vertex(k + 1);
      return x;
    };
    const double len = 2.0 * rho * std::sin(pi / n);
    const double kappa = 2.0 * std::tan(pi / n);
    double total = 0.0;
    for (int k = 0; k < n; ++k) {
      const double w = bending_element(vertex(k - 1), vertex(k), vertex(k + 1), len, len, frames_on(at(k)),
                                       Rest::Zero(), model, nullptr, nullptr, false);
      EXPECT_NEAR(w, kb_default / (2.0 * len) * kappa * kappa, 1e-9 * w);
      total += w;
    }
    // Σ = n kb tan(π/n) / (ρ cos(π/n))  ->  π kb / ρ = ∫ ½ kb (1/ρ)² ds, error ≈ (5/6)(π/n)².
    const double closed = n * kb_default * std::tan(pi / n) / (rho * std::cos(pi / n));
    EXPECT_NEAR(total, closed, 1e-9 * closed) << n;
    const double continuum = pi * kb_default / rho;
    const double error = std::abs(total / continuum - 1.0);
    EXPECT_LT(error, previous_error) << n;
    EXPECT_NEAR(error, 5.0 / 6.0 * (pi / n) * (pi / n), 0.5 * (pi / n) * (pi / n) + 1e-6) << n;
    previous_error = error;

    // With the polygon's own curvature vector as rest curvature the corner is at rest.
    const CornerFrames frames = frames_on(at(0));
    const Rest own = corner_curvature(vertex(-1), vertex(0), vertex(1), frames);
    Vec<9> g, g0;
    const double w_rest = bending_element(vertex(-1), vertex(0), vertex(1), len, len, frames, own, model, &g, nullptr,
                                          false);
    (void)bending_element(vertex(-1), vertex(0), vertex(1), len, len, frames, Rest::Zero(), model, &g0, nullptr, false);
    EXPECT_LT(w_rest, 1e-24 * total);
    EXPECT_LT(g.norm(), 1e-9 * g0.norm());
  }
  EXPECT_LT(previous_error, 1e-5);
}

// Within the bending plane the vector form is the magnitude form c (|κ| − |κ̄|)²; a rest
// curvature keeps its direction, so turning the bending plane about the yarn costs energy
// (c |κ̄|² (2 sin(ψ/2))² to first order for a turn ψ), where the magnitude form has a ring of
// minima.
TEST(RodBending, TurningTheBendingPlaneCostsEnergy) {
  const double la = 1e-3, lb = 1.2e-3, phi = 0.6;
  const double c = kb_default / (la + lb);
  const auto planar = [&](double turn) {
    const Vec3 a = Vec3::UnitX();
    const Vec3 bend(std::cos(phi), std::sin(phi) * std::cos(turn), std::sin(phi) * std::sin(turn));
    Vec<9> x;
    x << -la * a, Vec3::Zero(), lb * bend;
    return x;
  };
  const Vec<9> rest_shape = planar(0.0);
  const CornerFrames frames = frames_on(rest_shape);
  const Rest rest = corner_curvature(rest_shape.segment<3>(0), rest_shape.segment<3>(3), rest_shape.segment<3>(6), frames);
  const auto energy = [&](const Vec<9>& x, const Rest& r) {
    return bending_element(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6), la, lb, frames, r,
                           RodBending{kb_default}, nullptr, nullptr, false);
  };
  // Same plane, another magnitude: the magnitude form.
  for (const double scale : {0.3, 0.8, 1.7}) {
    const double expected = c * (1.0 - scale) * (1.0 - scale) * rest.squaredNorm();
    EXPECT_NEAR(energy(rest_shape, scale * rest), expected, 1e-9 * expected) << scale;
  }
  // Turned plane: positive, growing, ~ c |κ̄|² ψ² for small ψ.
  double previous = 0.0;
  for (const double turn : {0.01, 0.1, 0.5, 1.0, 2.0}) {
    const double w = energy(planar(turn), rest);
    EXPECT_GT(w, previous) << turn;
    previous = w;
  }
  const double small = 1e-3;
  const double ratio = energy(planar(small), rest) / (c * rest.squaredNorm() * small * small);
  EXPECT_GT(ratio, 0.1);
  EXPECT_LT(ratio, 2.0);
}

TEST(RodBending, RigidMotionWithItsFramesAndTranslationInvariance) {
  std::mt19937 rng(24);
  for (int trial = 0; trial < 10; ++trial) {
    const Vec<9> x = corner(uniform(rng, 0.1, 2.5), edge_length, 0.8 * edge_length, rng);
    const CornerFrames frames = frames_away(x, 0.5, rng);
    const Eigen::Matrix3d r = random_rotation(rng);
    const Vec3 shift = 1e-2 * random_unit(rng);
    Vec<9> y;
    for (int k = 0; k < 3; ++k) y.segment<3>(3 * k) = r * x.segment<3>(3 * k) + shift;
    const CornerFrames turned_frames{{r * frames.in.tangent, r * frames.in.director},
                                     {r * frames.out.tangent, r * frames.out.director}};
    const Rest rest = random_rest(0.5, rng);
    Vec<9> gx, gy;
    Mat<9> hx, hy;
    const double wx = bending_fn(edge_length, 0.8 * edge_length, frames, rest)(x, &gx, &hx);
    const double wy = bending_fn(edge_length, 0.8 * edge_length, turned_frames, rest)(y, &gy, &hy);
    EXPECT_NEAR(wy, wx, 1e-10 * wx);
    EXPECT_LT((gy - rotate_blocks<9>(r, gx)).lpNorm<Eigen::Infinity>(), 1e-8 * gx.lpNorm<Eigen::Infinity>());
    EXPECT_LT((hy - rotate_blocks<9>(r, hx)).lpNorm<Eigen::Infinity>(), 1e-8 * hx.lpNorm<Eigen::Infinity>());
    // Translations carry no force.
    EXPECT_LT(block_sum<9>(gx).norm(), 1e-9 * gx.norm());
  }
}

TEST(RodBending, ProjectionIsPsd) {
  std::mt19937 rng(25);
  int indefinite = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const double phi = uniform(rng, 5.0, 170.0) * pi / 180.0;
    const Rest rest = trial % 2 == 0 ? Rest::Zero() : random_rest(2.0 * std::tan(uniform(rng, 0.0, 1.4)), rng);
    const Vec<9> x = corner(phi, edge_length, 1.1 * edge_length, rng);
    const CornerFrames frames = frames_away(x, 0.5, rng);
    Mat<9> h, p;
    (void)bending_fn(edge_length, 1.1 * edge_length, frames, rest, false)(x, nullptr, &h);
    (void)bending_fn(edge_length, 1.1 * edge_length, frames, rest, true)(x, nullptr, &p);
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
  const Vec3 ey(0.0, 1e-3, 0.0);
  const RodBending model{.kb = kb_default};
  const CornerFrames along_x{anchor_along(ex), anchor_along(ex)};
  for (const auto& [x0, x1, x2] : {std::tuple{o, o, ex}, std::tuple{o, ex, ex},
                                   std::tuple{o, ex, Vec3(o)}}) {  // zero a, zero b, folded
    const double w = bending_element(x0, x1, x2, 1e-3, 1e-3, along_x, Rest(0.1, 0.0), model, nullptr, nullptr, false);
    EXPECT_TRUE(std::isinf(w) && w > 0.0);
  }
  // An edge turned back against its anchor has no frame to read the curvature in.
  const double w = bending_element(o, -ex, -ex - ey, 1e-3, 1e-3, along_x, Rest::Zero(), model, nullptr, nullptr, false);
  EXPECT_TRUE(std::isinf(w) && w > 0.0);
  EXPECT_TRUE(std::isinf(corner_curvature(o, ex, o)));
  EXPECT_FALSE(corner_curvature(o, ex, o, along_x).allFinite());
}

}  // namespace
}  // namespace yarnfit::yarn
