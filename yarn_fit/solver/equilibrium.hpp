#pragma once
// Constrained Newton for the periodic yarn equilibrium (6.9; thesis 3.32 and A.2.3):
//
//   min_g E(g)  s.t.  C g = 0.
//
// Each iteration solves the KKT system of (3.32) by a Schur complement on the few constraint
// rows: K δ0 = −∇E, K Y = Cᵀ, λ = (C Y)⁻¹ (C δ0 + C g), δ = δ0 − Y λ, with K the per-element
// PSD-projected Hessian plus a regulariser α I. The regulariser adapts (×1/4 after a full
// step, ×4 after a cut step) between 1e-10 and 1e2 of the mean diagonal, which plays the role
// of the thesis's decaying α̂ for a solver whose Hessian is already PSD. Steps are limited so
// that no vertex moves more than `max_step_radii` yarn radii and no contact pair closes by
// more than half its distance (a conservative collision-free step: the barrier is never
// stepped through), then backtracked until the energy decreases (Armijo). The stopping test
// is the projected gradient of A.2.3, z = (I − Cᵀ(CCᵀ)⁻¹C) ∇E, in force units:
// ‖z‖∞ ≤ force_tolerance (default 1e-9 · ks2, the tension of a 1e-9 strain of the stiff
// phase), which a warm start meets as well as a cold one.

#include <Eigen/Core>
#include <string>

#include "yarn_fit/periodic/yarn_system.hpp"

namespace yarnfit::yarn {

struct EquilibriumOptions {
  int max_iterations = 300;
  double force_tolerance = 0.0;  // [N]; 0 = 1e-9 · ks2
  double max_step_radii = 0.3;   // per-step vertex displacement limit, in yarn radii
  double time_limit_s = 0.0;     // 0 = none
  // After loose_after iterations, a state with ‖z‖∞ ≤ loose_tolerance [N] (0 = off) ends the
  // solve as converged_loosely instead of running on to max_iterations. A loose, nearly
  // stress-free tile
  // has mechanisms (yarns that barely touch) along which Newton creeps with a residual far
  // below any stress a fit compares; a caller that can bound the read-out error it accepts
  // says so here, and the status keeps it visible.
  double loose_tolerance = 0.0;
  int loose_after = 60;
};

enum class Termination { converged, converged_loosely, max_iterations, line_search_failed, non_finite, invalid_start, time_limit };
const char* to_string(Termination t);

struct EquilibriumResult {
  bool converged = false;
  Termination reason = Termination::max_iterations;
  int iterations = 0;
  double energy = 0.0;            // E at the returned state [J]
  double residual = 0.0;          // ‖z‖∞ at the returned state [N]
  double initial_residual = 0.0;  // ‖z‖∞ at the start [N]
  double tolerance = 0.0;         // the force tolerance used [N]
  double constraint_violation = 0.0;  // ‖C g‖∞ [m]
  double min_contact_distance = 0.0;  // closest candidate segments at the end [m]
  int contact_rebuilds = 0;
  double seconds = 0.0;
  std::string message;  // human-readable reason when not converged
};

// Relaxes `g` in place (a warm start is whatever `g` holds; zeros = the affine state).
// Never returns NaN: on failure `g` holds the last accepted (finite-energy) state.
EquilibriumResult solve_equilibrium(YarnSystem& system, Eigen::VectorXd& g,
                                    const EquilibriumOptions& options = {});

// Projected gradient z of A.2.3 for the current system state.
Eigen::VectorXd projected_gradient(const YarnSystem& system, const Eigen::VectorXd& gradient);

}  // namespace yarnfit::yarn
