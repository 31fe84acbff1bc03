// The FAB's loop-method bend scene (issue 51): the clamped–clamped elastica without gravity,
// up and down alike there, the catenary of a limp heavy strip, and gravity parting up from down.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "shell_fit/scenes/loop_bend.hpp"
#include "tests/shell_fit/known_materials.hpp"
#include "tests/expect_error.hpp"

namespace yarnfit::shell {
namespace {

// Nearly inextensible: the push of these loops strains the membrane by ~1e-5 or less.
using known::k_stiff;

ShellParams params_for(double ktheta) {
  ShellParams p;
  p.inplane = k_stiff;
  p.bending.ktheta = {ktheta, ktheta, ktheta};
  return p;
}

// A narrow strip keeps the tests fast: push and weight are both per unit width.
LoopBendSetup setup(double length, LoopDirection direction, double gravity) {
  LoopBendSetup s;
  s.length = length;
  s.width = 0.25 * length;
  s.areal_density = 0.1;
  s.gravity = gravity;
  s.direction = direction;
  return s;
}

TEST(LoopBend, PushesAsTheClampedElasticaWithoutGravity) {
  const double L = 0.02, ktheta = 1e-6, B = 2.0 * ktheta;
  const std::vector<double> d{0.95 * L, 0.8 * L, 0.6 * L};
  const auto up = LoopBendScene(setup(L, LoopDirection::up, 0.0)).run(params_for(ktheta), d);
  const auto down = LoopBendScene(setup(L, LoopDirection::down, 0.0)).run(params_for(ktheta), d);
  ASSERT_TRUE(up.ok) << up.message;
  ASSERT_TRUE(down.ok) << down.message;
  EXPECT_EQ(up.effects, (std::vector<std::string>{"membrane", "bending", "gravity"}));
  for (std::size_t i = 0; i < d.size(); ++i) {
    const double push = B * 0.25 * L * elastica_clamped_push(d[i], L);
    std::cout << "d/L " << d[i] / L << "  push " << -up.samples[i].force << " N, elastica " << push << " N ("
              << 100.0 * (-up.samples[i].force / push - 1.0) << " %), height " << up.samples[i].height * 1e3
              << " mm, " << up.samples[i].newton_iterations << " its\n";
    EXPECT_NEAR(-up.samples[i].force, push, 0.015 * push) << d[i];
    EXPECT_GT(up.samples[i].height, 0.0);
    EXPECT_LT(down.samples[i].height, 0.0);
    // Mirror images: the same push.
    EXPECT_NEAR(down.samples[i].force, up.samples[i].force, 1e-6 * push);
  }
}

TEST(LoopBend, ElasticaFormulaTendsToEuler) {
  const double L = 0.1;
  EXPECT_NEAR(elastica_clamped_push(0.99999 * L, L), 4.0 * M_PI * M_PI / (L * L), 1e-3 * 4.0 * M_PI * M_PI / (L * L));
  EXPECT_GT(elastica_clamped_push(0.5 * L, L), elastica_clamped_push(0.9 * L, L));
  EXPECT_ERROR((void)elastica_clamped_push(L, L), yarnfit::ErrorCategory::input);
}

// A limp, heavy strip hangs as a catenary: horizontal tension H = ρ g W a with
// L = 2a sinh(d/(2a)). Bending stiffens only boundary layers of the bending length
// ℓ = (B/(ρ g))^(1/3) at the clamps, so the scene comes closer to it as ℓ/L shrinks.
TEST(LoopBend, HangsAsACatenaryWhenLimp) {
  const double L = 0.08, d = 0.072, rho = 0.1, g = 9.81, W = 0.004;
  double lo = 1e-4, hi = 10.0;  // a from L = 2a sinh(d/(2a)): the left side falls with a
  for (int i = 0; i < 200; ++i) {
    const double a = 0.5 * (lo + hi);
    (2.0 * a * std::sinh(d / (2.0 * a)) > L ? lo : hi) = a;
  }
  const double H = rho * g * W * 0.5 * (lo + hi);
  std::vector<double> misses;
  for (const double ell : {0.006, 0.003}) {
    LoopBendSetup s = setup(L, LoopDirection::down, g);
    s.width = W;
    s.cells_along = 48;
    const auto run = LoopBendScene(s).run(params_for(rho * g * ell * ell * ell / 2.0), {d});
    ASSERT_TRUE(run.ok) << run.message;
    EXPECT_GT(run.samples[0].force, 0.0);  // it pulls: a hanging strip is in tension
    misses.push_back(std::abs(run.samples[0].force / H - 1.0));
    std::cout << "bending length " << ell * 1e3 << " mm: catenary H " << H << " N, scene " << run.samples[0].force
              << " N (" << 100.0 * (run.samples[0].force / H - 1.0) << " %), sag " << run.samples[0].height * 1e3
              << " mm\n";
  }
  EXPECT_LT(misses[1], 0.7 * misses[0]);
  EXPECT_LT(misses[1], 0.06);
}

// Gravity helps a down loop and fights an up one: the down loop pulls more (pushes less).
TEST(LoopBend, GravityPartsUpFromDown) {
  const double L = 0.02, ktheta = 2e-7;
  const std::vector<double> d{0.9 * L};
  const auto up = LoopBendScene(setup(L, LoopDirection::up, 9.81)).run(params_for(ktheta), d);
  const auto down = LoopBendScene(setup(L, LoopDirection::down, 9.81)).run(params_for(ktheta), d);
  ASSERT_TRUE(up.ok && down.ok) << up.message << down.message;
  std::cout << "up " << up.samples[0].force << " N, down " << down.samples[0].force << " N\n";
  EXPECT_GT(down.samples[0].force, up.samples[0].force);
  EXPECT_ERROR((void)LoopBendScene(setup(L, LoopDirection::up, 9.81)).initial_state(1.1 * L),
               yarnfit::ErrorCategory::input);
}

}  // namespace
}  // namespace yarnfit::shell
