// The periodic yarn system (yarn_fit/periodic/yarn_system.hpp) on the real stockinette tile:
// derivatives of the assembled system, invariances (translation, period shift, in-plane
// rotation with the load direction, a doubled tile), and a scene as a list of terms.

#include <gtest/gtest.h>

#include <Eigen/SparseCore>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "tests/yarn_fit/yarn_fixtures.hpp"

namespace yarnfit::yarn {
namespace {

using namespace fixtures;

TEST_F(StockinetteSystem, AssembledGradientAndHessianMatchFiniteDifferences) {
  YarnSystem sys(make_yarn_tile(tile), params);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> small(-0.05, 0.05);
  Eigen::VectorXd g(sys.dof_count());
  for (int i = 0; i < g.size(); ++i) g[i] = small(rng) * sys.tile().radius;
  for (const auto& [label, chi] :
       {std::pair{"weft 20 %", CoarseDeformation{0.2, 0.05, 0.0, weft_angle()}},
        std::pair{"bias 10 %, rotated frame", CoarseDeformation{0.1, 0.0, 0.0, bias_angle() + 0.3}},
        std::pair{"bent κ = 40/m", CoarseDeformation{0.05, 0.0, 40.0, warp_angle()}}}) {
    sys.set_deformation(chi);
    sys.rebuild_contacts(g);
    expect_system_derivatives(sys, g, label);
  }
}

TEST_F(StockinetteSystem, TranslationAndPeriodShiftLeaveTheResponseUnchanged) {
  const CoarseDeformation chi{0.2, 0.0, 0.0, weft_angle()};
  const Sample base = relaxed(tile, params, chi);
  ASSERT_TRUE(base.ok) << base.message;
  db::PeriodicTile moved = tile;
  for (auto& p : moved.positions) {
    p[0] += 0.37e-3;
    p[1] -= 1.3e-3;
    p[2] += 0.2e-3;
  }
  // Vertex 5 moved by a whole period in x: its edges' offsets change accordingly.
  moved.positions[5][0] += moved.period_x;
  for (auto& e : moved.edges) {
    if (e.v0 == 5) e.dx += 1;
    if (e.v1 == 5) e.dx -= 1;
  }
  const Sample shifted = relaxed(moved, params, chi);
  ASSERT_TRUE(shifted.ok) << shifted.message;
  EXPECT_LT(rel(shifted.energy_density, base.energy_density), 1e-8);
  EXPECT_LT(rel(shifted.stress_s, base.stress_s), 1e-8);
}

TEST_F(StockinetteSystem, InPlaneRotationWithTheLoadDirectionLeavesTheResponseUnchanged) {
  const double turn = 0.6;
  for (const double angle : {weft_angle(), bias_angle()}) {
    const Sample base = relaxed(tile, params, {0.2, 0.0, 0.0, angle});
    const Sample turned = relaxed(tile, params, {0.2, 0.0, 0.0, angle + turn}, turn);
    ASSERT_TRUE(base.ok && turned.ok) << base.message << turned.message;
    EXPECT_LT(rel(turned.energy_density, base.energy_density), 1e-8) << "angle " << angle;
    EXPECT_LT(rel(turned.stress_s, base.stress_s), 1e-8) << "angle " << angle;
  }
}

// The doubled tile pins every copy of the original pins (repeat_yarn_tile), so the original's
// periodic states are among its own; both are solved cold from the affine state.

TEST_F(StockinetteSystem, DoubledTileGivesTheSameDensityAndStress) {
  const CoarseDeformation chi{0.2, 0.0, 0.0, weft_angle()};
  const Sample base = relaxed(tile, params, chi);
  ASSERT_TRUE(base.ok) << base.message;
  for (const auto& [nx, ny] : {std::pair{2, 1}, std::pair{1, 2}}) {
    YarnSystem sys(repeat_yarn_tile(tile, nx, ny), params);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(sys.dof_count());
    EquilibriumOptions o;
    o.force_tolerance = 1e-11 * params.ks2;
    const Sample doubled = simulate_sample(sys, chi, g, o);
    ASSERT_TRUE(doubled.ok) << doubled.message;
    EXPECT_LT(rel(doubled.energy_density, base.energy_density), 1e-3) << nx << "x" << ny;
    EXPECT_LT(rel(doubled.stress_s, base.stress_s), 1e-3) << nx << "x" << ny;
  }
}

// SPEC §4: a scene simulates exactly the terms it lists, and its results say so.
TEST_F(StockinetteSystem, RemovingATermRemovesItsNameFromTheEffectsAndItsEnergyFromPsi) {
  const YarnTile base = make_yarn_tile(tile);
  YarnSystem all(base, params);
  YarnSystem no_contact(base, params, {YarnTermKind::stretch, YarnTermKind::bending});
  EXPECT_EQ(all.effects(), (std::vector<std::string>{"stretch", "bending", "contact"}));
  EXPECT_EQ(no_contact.effects(), (std::vector<std::string>{"stretch", "bending"}));
  // At the same state, Ψ without the contact term is Ψ less the contact energy.
  const CoarseDeformation chi{0.1, 0.02, 0.0, weft_angle()};
  Eigen::VectorXd g = Eigen::VectorXd::Zero(all.dof_count());
  const Sample s = simulate_sample(all, chi, g, EquilibriumOptions{});
  ASSERT_TRUE(s.ok) << s.message;
  EXPECT_EQ(s.effects, all.effects());
  no_contact.set_deformation(chi);
  double contact = 0.0;
  for (const auto& [name, e] : all.energy_by_term(g)) {
    if (name == "contact") contact = e;
  }
  EXPECT_GT(contact, 0.0) << "the relaxed stockinette has yarns in contact";
  EXPECT_NEAR(no_contact.energy(g), all.energy(g) - contact, 1e-12 * all.energy(g));
  EXPECT_LT(no_contact.energy(g), all.energy(g));
  // A sample of the reduced scene reports the reduced effects; bent, it adds co-rotation.
  Eigen::VectorXd h = Eigen::VectorXd::Zero(no_contact.dof_count());
  const Sample reduced = simulate_sample(no_contact, {0.0, 0.0, 30.0, weft_angle()}, h, EquilibriumOptions{});
  EXPECT_EQ(reduced.effects, (std::vector<std::string>{"stretch", "bending", "co-rotation"}));
}

TEST_F(StockinetteSystem, ACopyIsIndependentAndGivesTheSameNumbers) {
  YarnSystem a(make_yarn_tile(tile), params);
  const Eigen::VectorXd g = Eigen::VectorXd::Constant(a.dof_count(), 1e-6);
  a.set_deformation({0.2, 0.0, 0.0, bias_angle()});
  a.rebuild_contacts(g);
  YarnSystem b = a;
  Eigen::VectorXd ga, gb;
  EXPECT_EQ(a.energy_gradient(g, ga), b.energy_gradient(g, gb));
  EXPECT_EQ(ga, gb);
  // Changing the copy leaves the original as it was: the copy's terms read its own tile.
  b.set_deformation({0.3, 0.0, 0.0, bias_angle()});
  b.mutable_tile().edges[0].rest_length *= 1.1;
  Eigen::VectorXd ga2;
  EXPECT_EQ(a.energy_gradient(g, ga2), a.energy_gradient(g, ga));
  EXPECT_NE(b.energy(g), a.energy(g));
}

}  // namespace
}  // namespace yarnfit::yarn
