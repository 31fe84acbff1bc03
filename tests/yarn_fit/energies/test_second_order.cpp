// SecondOrder numbers (yarn_fit/energies/second_order.hpp) and the bending element's Hessian
// made with them: a function with a closed-form Hessian, then the element against the jet of
// jets it replaced (value, gradient and Hessian to rounding) and against central differences
// of its exact gradient, over random corners, frames moved away from the corners and rest
// curvatures; and the time of each, printed.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>

#include "tests/yarn_fit/energies/element_fixtures.hpp"
#include "yarn_fit/energies/second_order.hpp"

namespace yarnfit::yarn {
namespace {

using namespace fixtures;
using S2 = SecondOrder<2>;

// f(x, y) = sqrt(x y) / (x + y) − 3 x / y + 2: every operation the type defines.
TEST(SecondOrder, MatchesAClosedFormHessian) {
  const double x = 0.7, y = 1.9;
  const S2 vx = S2::variable(x, 0), vy = S2::variable(y, 1);
  const S2 f = sqrt(vx * vy) / (vx + vy) - 3.0 * vx / vy + 2.0;
  // Closed form, by hand: r = sqrt(xy), s = x + y, f = r/s − 3x/y + 2.
  const double r = std::sqrt(x * y), s = x + y;
  const double fx = (0.5 * y / r) / s - r / (s * s) - 3.0 / y;
  const double fy = (0.5 * x / r) / s - r / (s * s) + 3.0 * x / (y * y);
  const double rxx = -0.25 * y * y / (r * r * r), ryy = -0.25 * x * x / (r * r * r);
  const double rxy = 0.5 / r - 0.25 * x * y / (r * r * r);
  const double rx = 0.5 * y / r, ry = 0.5 * x / r;
  const double fxx = rxx / s - 2.0 * rx / (s * s) + 2.0 * r / (s * s * s);
  const double fyy = ryy / s - 2.0 * ry / (s * s) + 2.0 * r / (s * s * s) - 6.0 * x / (y * y * y);
  const double fxy = rxy / s - (rx + ry) / (s * s) + 2.0 * r / (s * s * s) + 3.0 / (y * y);
  EXPECT_NEAR(f.a, r / s - 3.0 * x / y + 2.0, 1e-15);
  EXPECT_NEAR(f.g[0], fx, 1e-14);
  EXPECT_NEAR(f.g[1], fy, 1e-14);
  EXPECT_NEAR(f.h(0, 0), fxx, 1e-13);
  EXPECT_NEAR(f.h(1, 1), fyy, 1e-13);
  EXPECT_NEAR(f.h(0, 1), fxy, 1e-13);
  EXPECT_NEAR(f.h(0, 1), f.h(1, 0), 1e-15);
}

struct Case {
  Vec<9> x;
  CornerFrames frames;
  Eigen::Vector2d rest;
  double la, lb;
};

std::vector<Case> random_corners(int count) {
  std::mt19937 rng(20261206);
  std::vector<Case> cases;
  for (int k = 0; k < count; ++k) {
    const double la = uniform(rng, 0.5e-3, 2e-3), lb = uniform(rng, 0.5e-3, 2e-3);
    const Vec3 x1(uniform(rng, -2e-3, 2e-3), uniform(rng, -2e-3, 2e-3), uniform(rng, -2e-3, 2e-3));
    const Vec3 u = random_unit(rng);
    const Vec3 v = turned(u, uniform(rng, 0.0, 2.0), rng);
    Case c;
    c.x << x1 - la * u, x1, x1 + lb * v;
    // Anchors turned away from the edges and twisted against each other: the corner has moved
    // since its frames were read.
    const EdgeAnchor in = anchor_along(turned(u, uniform(rng, 0.0, 0.4), rng));
    EdgeAnchor out = carried_anchor(in, Eigen::Matrix3d::Identity(), turned(v, uniform(rng, 0.0, 0.4), rng));
    const double twist = uniform(rng, -0.3, 0.3);
    out.director = std::cos(twist) * out.director + std::sin(twist) * out.tangent.cross(out.director);
    c.frames = {in, out};
    c.rest = Eigen::Vector2d(uniform(rng, -1.0, 1.0), uniform(rng, -1.0, 1.0));
    c.la = la;
    c.lb = lb;
    cases.push_back(c);
  }
  return cases;
}

TEST(SecondOrder, BendingHessianIsTheNestedJetsOneAndTheGradientsDerivative) {
  const RodBending model{.kb = 1e-6};
  int compared = 0;
  for (const Case& c : random_corners(200)) {
    Vec<9> g, g_ref;
    Mat<9> h, h_ref;
    const double w = bending_element(c.x.segment<3>(0), c.x.segment<3>(3), c.x.segment<3>(6), c.la, c.lb, c.frames,
                                     c.rest, model, &g, &h, false);
    const double w_ref = bending_element_by_nested_jets(c.x.segment<3>(0), c.x.segment<3>(3), c.x.segment<3>(6),
                                                        c.la, c.lb, c.frames, c.rest, model, g_ref, h_ref);
    ASSERT_EQ(std::isfinite(w), std::isfinite(w_ref));
    if (!std::isfinite(w)) continue;
    ++compared;
    EXPECT_NEAR(w, w_ref, 1e-13 * std::abs(w_ref));
    EXPECT_LE((g - g_ref).norm(), 1e-12 * g_ref.norm());
    EXPECT_LE((h - h_ref).norm(), 1e-11 * h_ref.norm()) << "corner " << compared;
    EXPECT_LE((h - h.transpose()).norm(), 1e-14 * h.norm());
    // Central differences of the exact gradient.
    Mat<9> fd;
    const double step = 1e-9;
    for (int j = 0; j < 9; ++j) {
      Vec<9> xp = c.x, xm = c.x, gp, gm;
      xp[j] += step;
      xm[j] -= step;
      bending_element(xp.segment<3>(0), xp.segment<3>(3), xp.segment<3>(6), c.la, c.lb, c.frames, c.rest, model, &gp,
                      nullptr, false);
      bending_element(xm.segment<3>(0), xm.segment<3>(3), xm.segment<3>(6), c.la, c.lb, c.frames, c.rest, model, &gm,
                      nullptr, false);
      fd.col(j) = (gp - gm) / (2.0 * step);
    }
    EXPECT_LE((h - fd).norm(), 1e-5 * h.norm()) << "corner " << compared;
  }
  EXPECT_GT(compared, 190);
}

// What the change bought (printed, not asserted: the machine is shared).
TEST(SecondOrder, BendingHessianTimeAgainstNestedJets) {
  const RodBending model{.kb = 1e-6};
  const auto cases = random_corners(64);
  const auto time = [&](bool nested) {
    double best = 1e300, sink = 0.0;
    for (int repeat = 0; repeat < 5; ++repeat) {
      const auto start = std::chrono::steady_clock::now();
      for (int k = 0; k < 20; ++k)
        for (const Case& c : cases) {
          Vec<9> g;
          Mat<9> h;
          sink += nested ? bending_element_by_nested_jets(c.x.segment<3>(0), c.x.segment<3>(3), c.x.segment<3>(6),
                                                          c.la, c.lb, c.frames, c.rest, model, g, h)
                         : bending_element(c.x.segment<3>(0), c.x.segment<3>(3), c.x.segment<3>(6), c.la, c.lb,
                                           c.frames, c.rest, model, &g, &h, false);
          sink += h(0, 0);
        }
      best = std::min(best, std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count());
    }
    EXPECT_TRUE(std::isfinite(sink));
    return best / (20.0 * static_cast<double>(cases.size()));
  };
  const double nested = time(true), second = time(false);
  std::printf("  bending element with Hessian: %.2f us (SecondOrder) against %.2f us (nested jets): %.1fx\n", second,
              nested, nested / second);
}

}  // namespace
}  // namespace yarnfit::yarn
