#pragma once
// The derivative check of one yarn term in the tile's DOFs g, on the real stockinette tile
// at a perturbed state under an in-plane and a curved coarse deformation (the curved map
// turns every element's derivatives back into g-space).

#include <Eigen/Core>
#include <cstdio>
#include <random>
#include <string>

#include "tests/support/derivative_check.hpp"
#include "tests/yarn_fit/yarn_fixtures.hpp"

namespace yarnfit::yarn::fixtures {

// A state near the affine one: fluctuations of ±5 % of the yarn radius.
inline Eigen::VectorXd perturbed_state(const YarnSystem& system, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> small(-0.05, 0.05);
  Eigen::VectorXd g(system.dof_count());
  for (int i = 0; i < g.size(); ++i) g[i] = small(rng) * system.tile().radius;
  return g;
}

// Checks the term named `name` of a stockinette system in the listed states.
inline void expect_yarn_term_derivatives(const db::PeriodicTile& tile, const YarnParams& params, const std::string& name) {
  YarnSystem system(make_yarn_tile(tile), params);
  const Eigen::VectorXd g = perturbed_state(system, 11);
  for (const CoarseDeformation& chi : {CoarseDeformation{0.2, 0.05, 0.0, weft_angle()},
                                       CoarseDeformation{0.05, 0.0, 40.0, warp_angle() + 0.2}}) {
    system.set_deformation(chi);
    system.rebuild_contacts(g);
    const numerics::EnergyTerm* term = nullptr;
    for (const auto* t : system.terms())
      if (t->name() == name) term = t;
    ASSERT_NE(term, nullptr) << name;
    testing::DerivativeCheckOptions o;
    o.length_scale = system.tile().radius;
    o.relative_steps = {1e-3, 1e-4, 1e-5, 1e-6};
    SCOPED_TRACE(name + (chi.curved() ? " (curved)" : " (in-plane)"));
    const auto r = testing::expect_derivatives_match(*term, g, o);
    std::printf("%s term, %s: gradient %.2e, Hessian %.2e\n", name.c_str(), chi.curved() ? "curved" : "in-plane",
                r.gradient_error, r.hessian_error);
  }
}

}  // namespace yarnfit::yarn::fixtures
