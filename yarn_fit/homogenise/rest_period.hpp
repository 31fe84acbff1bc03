#pragma once
// The rest-period relaxation (`yarnfit fit --relax-period`, ObjectiveOptions::rest_period;
// not the rest-shape heuristic's period chord steps, RestShapeOptions::period_chord_steps,
// which take a fixed few steps towards it as part of every rest shape).
//
// The rest period of a tile (HYLC's rest-state step, thesis Appendix A.2.4): the in-plane
// period stretch E = diag(E00, E11) at which the relaxed tile carries no coarse normal
// stress at χ = 0, so that the course and wale spacings come out of the mechanics. The rest
// lengths and curvatures stay as they are (a generated tile keeps its yarn length per stitch);
// the tile's reference positions and lattice are mapped by I + E (transformed_tile).
//
// The rest period minimises the tile's energy W(E) = min_g E(g; E), whose gradient is the
// coarse stress (A P_ii / (1 + E_ii), A the current area): Newton steps on W
// (numerics/newton/few_dof_newton.hpp) with a forward-difference Hessian (two extra
// equilibria per step), shifted until positive definite where W is not convex, capped at
// max_step per component and halved until W decreases (Armijo), each equilibrium
// warm-started from the last accepted state. (Newton on
// P(E) = 0 with a max-norm merit stalled on the acrylic stockinette: its Jacobian was
// indefinite at +25 % while the rest stress was still −3000 N/m.) The shear E01 is not relaxed (the generated charts
// are mirror-symmetric, so their rest shear stress vanishes by symmetry; rest_shape.hpp says
// why relaxing it hurts on real tiles).

#include <Eigen/Core>
#include <string>

#include "yarn_fit/periodic/yarn_system.hpp"
#include "yarn_fit/solver/equilibrium.hpp"

namespace yarnfit::yarn {

struct RestPeriodOptions {
  // |P00| ≤ tolerance[0] and |P11| ≤ tolerance[1] [N/m] ends the relaxation.
  Eigen::Vector2d tolerance = Eigen::Vector2d::Constant(1e-3);
  int max_steps = 40;
  double max_step = 0.05;           // |ΔE_ii| per step
  double jacobian_step = 2e-3;      // forward-difference step of E
  int halvings = 6;
  // A loose tile creeps along mechanisms at rest (thin yarns, long loops): the stress read-out
  // test (its default) ends such a solve once P has settled, well below the tolerance above.
  EquilibriumOptions solve;
};

struct RestPeriodResult {
  bool converged = false;
  std::string message;               // why not converged
  int steps = 0;
  int solves = 0;
  int newton_iterations = 0;
  Eigen::Matrix2d period_stretch = Eigen::Matrix2d::Zero();  // E applied to the input tile
  Eigen::Matrix2d rest_stress = Eigen::Matrix2d::Zero();     // P at χ = 0 after [N/m]
  Eigen::Matrix2d initial_stress = Eigen::Matrix2d::Zero();  // P at χ = 0 before [N/m]
  double seconds = 0.0;
};

// Relaxes the system's tile period in place (set_tile) and `g` with it; on failure the tile
// and `g` are those of the best accepted step (the input when none was).
RestPeriodResult relax_rest_period(YarnSystem& system, Eigen::VectorXd& g, const RestPeriodOptions& options = {});

}  // namespace yarnfit::yarn
