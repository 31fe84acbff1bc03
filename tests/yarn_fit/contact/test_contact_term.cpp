// The contact term (yarn_fit/contact/contact_term.hpp) over the real stockinette tile: its
// derivatives in the tile's DOFs, the collision-free step it gives the line search (no pair
// closes by more than half its distance, whatever the direction), and its closest distance.

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>

#include "numerics/geometry/segment_distance.hpp"
#include "tests/yarn_fit/energies/term_check.hpp"

namespace yarnfit::yarn {
namespace {

using namespace fixtures;

TEST_F(StockinetteSystem, ContactTermDerivativesMatchFiniteDifferences) {
  expect_yarn_term_derivatives(tile, params, "contact");
}

// Every candidate pair's distance at g + t·dg, against its distance at g.
double worst_closing(const YarnSystem& system, const Eigen::VectorXd& g, const Eigen::VectorXd& moved) {
  double worst = std::numeric_limits<double>::infinity();
  const auto point = [&](const Eigen::VectorXd& state, int v, const Cell& c) {
    const Eigen::Vector3d p = system.position(state, v, c);
    return numerics::Point3{p.x(), p.y(), p.z()};
  };
  for (const auto& cc : system.contacts().pairs()) {
    const auto& ea = system.tile().edges[static_cast<std::size_t>(cc.a)];
    const auto& eb = system.tile().edges[static_cast<std::size_t>(cc.b)];
    const auto distance = [&](const Eigen::VectorXd& s) {
      return numerics::segment_segment_distance(point(s, ea.v0, {0, 0}), point(s, ea.v1, ea.cell1),
                                                point(s, eb.v0, cc.cell), point(s, eb.v1, cc.cell + eb.cell1));
    };
    worst = std::min(worst, distance(moved) / distance(g));
  }
  return worst;
}

TEST_F(StockinetteSystem, CollisionFreeStepNeverClosesAPairByMoreThanHalf) {
  YarnSystem system(make_yarn_tile(tile), params);
  const Eigen::VectorXd g = perturbed_state(system, 5);
  system.set_deformation({0.1, 0.0, 0.0, bias_angle()});
  system.rebuild_contacts(g);
  ASSERT_GT(system.contacts().pairs().size(), 0u);
  std::mt19937 rng(9);
  std::normal_distribution<double> normal;
  int limited = 0;
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::VectorXd dg(system.dof_count());
    for (int i = 0; i < dg.size(); ++i) dg[i] = normal(rng);
    dg *= (trial + 1) * 0.2 * system.tile().radius / dg.lpNorm<Eigen::Infinity>();  // up to 4 R per vertex
    const double t = system.collision_free_fraction(g, dg);
    ASSERT_GT(t, 0.0);
    ASSERT_LE(t, 1.0);
    if (t < 1.0) ++limited;
    // Distances shrink at most by the relative motion of the four ends: t keeps half.
    EXPECT_GE(worst_closing(system, g, g + t * dg), 0.5 - 1e-12) << "trial " << trial << ", t " << t;
  }
  EXPECT_GT(limited, 5) << "large steps must be cut";
  EXPECT_GT(system.min_contact_distance(g), 0.0);
}

}  // namespace
}  // namespace yarnfit::yarn
