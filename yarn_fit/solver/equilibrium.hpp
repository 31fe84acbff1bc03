#pragma once
// The periodic yarn equilibrium (6.9; thesis 3.32 and A.2.3):
//
//   min_g E(g)  s.t.  C g = 0,
//
// solved by the one Newton solver (numerics/newton/newton_solver.hpp) with the yarn tile's
// preset (NewtonPolicy::yarn_tile()): the KKT step by a Schur complement on the few
// constraint rows; the exact Hessian first, shifted by up to 1e-3 of its mean diagonal before the per-element PSD projection
// replaces it; a shift that adapts (×1/4 after a full step, ×4 after a cut one, ×100 after a
// failure) between 1e-10 and 1e2 of the mean diagonal, which plays the role of the thesis's
// decaying α̂; at most 8 failed attempts per iteration. Steps are limited so that no vertex
// moves more than `max_step_radii` yarn radii and no contact pair closes by more than half
// its distance (the contact term's collision-free step: the barrier is never stepped
// through), then backtracked until the energy decreases (Armijo). The stopping test is the
// projected gradient of A.2.3, z = (I − Cᵀ(CCᵀ)⁻¹C) ∇E, in force units:
// ‖z‖∞ ≤ force_tolerance (default 1e-9 · ks2, the tension of a 1e-9 strain of the stiff
// phase), which a warm start meets as well as a cold one. The contact list is rebuilt
// before a step could move a vertex by half its skin.

#include <Eigen/Core>
#include <string>

#include "numerics/newton/newton_solver.hpp"
#include "yarn_fit/periodic/yarn_system.hpp"

namespace yarnfit::yarn {

struct EquilibriumOptions {
  int max_iterations = 300;
  double force_tolerance = 0.0;  // [N]; 0 = 1e-9 · ks2
  double max_step_radii = 0.3;   // per-step vertex displacement limit, in yarn radii
  double time_limit_s = 0.0;     // 0 = none
  // After loose_after iterations, a state with ‖z‖∞ ≤ loose_tolerance [N] (0 = off) ends the
  // solve as converged_loosely instead of running on to max_iterations. A loose, nearly
  // stress-free tile has mechanisms (yarns that barely touch) along which Newton creeps with
  // a residual far below any stress a fit compares; a caller that can bound the read-out
  // error it accepts says so here, and the status keeps it visible.
  double loose_tolerance = 0.0;
  int loose_after = 60;
  // The stress read-out test [N/m] (0 = off; < 0 = default_stress_tolerance of the system,
  // the default): an in-plane solve (κ = 0) also ends, as
  // converged_readout, once the coarse stress P (3.23) has settled within this tolerance
  // (NewtonOptions::readout_tolerance: three accepted steps in a row each move P by at most
  // a quarter of it, the last a full Newton step). On slack tiles Newton creeps along
  // mechanisms for hundreds of iterations with residual forces far above force_tolerance
  // while the stress barely moves; a later slide can still move it by a few tolerances
  // (satin_small, 3 % weft: 0.016 N/m against 4.4e-3), so set it well below what is compared.
  double stress_tolerance = -1.0;
};

// 1e-6 · ks1 / (shorter tile period) [N/m]: the line force of a 1e-6 strain of the soft yarn
// phase, one yarn per period — 4.4e-3 N/m for the 0.1 mm tiles' parameters, a thousandth of
// their stress at 8 % stretch.
double default_stress_tolerance(const YarnSystem& system);

using Termination = numerics::NewtonStatus;
using numerics::to_string;

// The Newton summary (status, iterations, residual ‖z‖∞ [N], energy [J], …) and what the
// yarn system adds to it.
struct EquilibriumResult : numerics::NewtonSummary {
  double constraint_violation = 0.0;  // ‖C g‖∞ [m]
  double min_contact_distance = 0.0;  // closest candidate segments at the end [m]
  int contact_rebuilds = 0;
};

// The Newton settings solve_equilibrium uses for these options and this system: the yarn
// tile's preset with these budgets and tolerances.
numerics::NewtonOptions equilibrium_newton_options(const YarnSystem& system, const EquilibriumOptions& options);

// Relaxes `g` in place (a warm start is whatever `g` holds; zeros = the affine state).
// Never returns NaN: on failure `g` holds the last accepted (finite-energy) state.
EquilibriumResult solve_equilibrium(YarnSystem& system, Eigen::VectorXd& g, const EquilibriumOptions& options = {});

// Projected gradient z of A.2.3 for the current system state.
Eigen::VectorXd projected_gradient(const YarnSystem& system, const Eigen::VectorXd& gradient);

}  // namespace yarnfit::yarn
