#pragma once
// Static equilibrium of a scene: minimise the sum of its energy terms over the free degrees of
// freedom by Newton's method (SPEC §3 "Shell": sparse direct solver, line search, safeguard
// against indefinite Hessians), and load continuation for large loads.
//
// Every Newton iteration:
//   1. assembles the total gradient g and the sparse Hessian H restricted to the free DOFs:
//      the exact H first, and the per-element PSD projection (`project_psd`) when the exact
//      one is not positive definite or its step fails;
//   2. solves (H + μI) d = −g with a sparse LDLᵀ factorisation whose pattern is analysed once
//      per solve. μ = 0 first (or what a non-positive diagonal entry demands); if the
//      factorisation fails, is not positive definite or d is not a descent direction, μ grows
//      (Levenberg style) and the solve is repeated; after good steps μ shrinks back to 0, so
//      Newton's quadratic convergence returns near the solution;
//   3. backtracks from the full step (Armijo sufficient decrease) and rejects trial points
//      whose energy is not finite (barriers, inverted elements), so every iterate is valid.
// Converged when ‖g_free‖∞ ≤ gradient_tolerance. A failed solve leaves x at the last valid
// iterate and says what went wrong in its summary (STYLE "Solvers report what happened").

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <functional>
#include <string>
#include <vector>

#include "shell_fit/core/energy_term.hpp"

namespace yarnfit::shell {

struct NewtonOptions {
  int max_iterations = 200;
  // Absolute, on the max-norm of the free gradient [energy per unit of x, e.g. N]; the caller
  // scales it to the problem (e.g. a fraction of the expected clamp force per node).
  double gradient_tolerance = 1e-8;
  // Allow projecting every element's Hessian block to PSD (EnergyTerm::add_hessian). Far from
  // rest (compressed free edges, buckling) the exact Hessian is indefinite and its Newton step
  // points uphill; the projected one always gives a descent direction. False: exact Hessian
  // with the shift as the only safeguard.
  bool project_psd = true;
  // With project_psd: try the exact Hessian first in every iteration and project only when it
  // is not positive definite or its step fails (after such a failure the next iteration goes
  // straight to the projection). Near equilibrium in tension the exact Hessian is usually
  // positive definite: this gives the true Newton step and skips the per-element
  // eigen-decompositions, which dominate the cost of an iteration.
  bool exact_hessian_first = true;
  // Halvings of the step before the line search gives up on a direction.
  int max_line_search_steps = 40;
  // Armijo constant c in E(x + αd) ≤ E(x) + c·α·gᵀd.
  double armijo = 1e-4;
  // First shift tried when H is not positive definite, relative to the mean |diagonal| of the
  // free Hessian, so it is independent of the units of the energy.
  double regularisation_start = 1e-8;
  // Factor by which the shift grows after each failed factorisation or line search. Small, so
  // the shift overshoots what the Hessian needs by at most this factor (too large a shift
  // shortens the step towards a gradient step: 2 beat 10 by 2–5× in iterations on the
  // indefinite tests).
  double regularisation_growth = 2.0;
  // Factor applied to the shift after an accepted step; below regularisation_start it drops to
  // 0 (plain Newton).
  double regularisation_shrink = 0.25;
  // Relative shift at which we give up (the direction is then a scaled gradient step; if even
  // that fails, the energy cannot be decreased within rounding).
  double regularisation_max = 1e10;

  // False with the reason in *why when an option is out of range.
  [[nodiscard]] bool is_valid(std::string* why) const;
};

enum class NewtonStatus {
  converged,             // ‖g_free‖∞ ≤ gradient_tolerance
  max_iterations,        // iteration budget spent; x is the last (valid) iterate
  line_search_failed,    // no step decreased the energy, even with the largest shift
  invalid_start,         // the initial energy is not finite (or NaN)
  linear_solver_failed,  // the shifted Hessian could not be factorised at any shift
  non_finite,            // a gradient, Hessian or step was NaN/inf at a valid point
};

[[nodiscard]] const char* to_string(NewtonStatus status);

struct NewtonSummary {
  NewtonStatus status = NewtonStatus::max_iterations;
  std::string message;        // why it stopped, in words (names a failing term when known)
  int iterations = 0;         // accepted Newton steps (summed over continuation steps)
  double gradient_norm = 0.0; // ‖g_free‖∞ at the returned x
  double energy = 0.0;        // total energy at the returned x [J]
  double seconds = 0.0;       // wall time
  int regularised_steps = 0;  // accepted steps that needed a shift μ > 0
  int projected_steps = 0;    // accepted steps taken with the per-element projected Hessian
  // Continuation only (solve_continuation); 0 for a plain solve.
  int continuation_steps = 0; // accepted load steps
  int cut_backs = 0;          // failed load steps that were halved and retried
  double lambda = 1.0;        // load parameter reached (1 when the continuation finished)

  [[nodiscard]] bool converged() const { return status == NewtonStatus::converged; }
  // One line: status, iterations, gradient norm, energy, time (and steps, cut-backs).
  [[nodiscard]] std::string brief() const;
};

// Sums of the terms at x. total_energy is +inf if any term is infinite, NaN if any is NaN.
[[nodiscard]] double total_energy(const std::vector<const EnergyTerm*>& terms,
                                  const Eigen::VectorXd& x);
[[nodiscard]] Eigen::VectorXd total_gradient(const std::vector<const EnergyTerm*>& terms,
                                             const Eigen::VectorXd& x);
// Full (#x × #x, both triangles stored) Hessian.
[[nodiscard]] Eigen::SparseMatrix<double> total_hessian(
    const std::vector<const EnergyTerm*>& terms, const Eigen::VectorXd& x, bool project_psd);

// Minimises the total energy over the DOFs not listed in fixed_dofs (entries of x; duplicates
// allowed), which keep their values exactly. x is updated in place and always holds a state
// with finite energy on return unless the status is invalid_start (then it is unchanged).
// Throws std::invalid_argument for invalid options, an empty term list, a null term or a fixed
// DOF out of range; numerical trouble is reported in the summary, never thrown.
NewtonSummary solve_static(const std::vector<const EnergyTerm*>& terms, Eigen::VectorXd& x,
                           const std::vector<int>& fixed_dofs, const NewtonOptions& options);

// Clamp reactions. Sign convention: the returned values are the force the clamp applies ON
// THE BODY at the given DOFs, equal to +∂E/∂x there. At equilibrium the elastic force on a
// clamped node (−∂E/∂x) is balanced by the clamp, so the clamp pushes with +∂E/∂x. The force
// the body applies on the clamp (what a tensile tester's load cell reads) is the negative.
// Example: a swatch stretched along +x pulls its right clamp back towards −x; the right clamp
// pulls the swatch towards +x, so the x-reactions there are positive and their sum is the
// tension.
[[nodiscard]] Eigen::VectorXd clamp_reaction(const std::vector<const EnergyTerm*>& terms,
                                             const Eigen::VectorXd& x,
                                             const std::vector<int>& dofs);
// Sum over `vertices` of the clamp reaction component `axis` (x: 0, y: 1, z: 2) for positions
// with `dim` entries per vertex; same sign convention as clamp_reaction.
[[nodiscard]] double clamp_force(const std::vector<const EnergyTerm*>& terms,
                                 const Eigen::VectorXd& x, const std::vector<int>& vertices,
                                 int dim, int axis);

// The DOFs dim·v + k (k < dim) of the given vertices: a clamped edge's fixed DOFs.
[[nodiscard]] std::vector<int> vertex_dofs(const std::vector<int>& vertices, int dim);

// Newton options for one load step of a continuation: the defaults with a smaller iteration
// budget, so a load step that struggles fails fast and is halved instead of grinding on.
[[nodiscard]] inline NewtonOptions continuation_step_defaults() {
  NewtonOptions o;
  o.max_iterations = 40;
  return o;
}

struct ContinuationOptions {
  NewtonOptions newton = continuation_step_defaults();  // options of every load step's solve
  double start_lambda = 0.0;  // load parameter of the state passed in
  double initial_step = 0.25; // first Δλ
  double max_step = 1.0;      // Δλ never grows beyond this
  double min_step = 1e-4;     // the continuation fails when a halved Δλ falls below this
  // After a load step converged within easy_iterations Newton iterations, Δλ grows by this
  // factor (the next step is likely easy too).
  double step_growth = 2.0;
  int easy_iterations = 6;
  // Predict the free DOFs of the next step by linear extrapolation from the last two
  // converged steps; the warm start is then usually within Newton's quadratic basin.
  bool extrapolate = true;

  [[nodiscard]] bool is_valid(std::string* why) const;
};

// Moves the boundary of a scene to load parameter λ: writes the fixed DOFs (and only those) of
// x for that load. Called with λ between start_lambda and 1.
using SetBoundary = std::function<void(double lambda, Eigen::VectorXd& x)>;

// Walks λ from options.start_lambda to 1: at every step set_boundary(λ, x) moves the clamps,
// the free DOFs are warm-started from the previous solution (extrapolated linearly when two
// are known), and solve_static finds the equilibrium. A failed step restores the last good
// state and is halved, down to min_step. The first solve is at start_lambda itself, so x need
// not be an equilibrium there, only valid.
// Returns the summary of the whole walk: status converged only if λ = 1 was reached;
// iteration and step counts and seconds summed; continuation_steps, cut_backs and the λ
// reached; energy and gradient_norm of the last converged state. On failure x holds the last
// converged state (at summary.lambda), or is unchanged if the start itself did not converge.
NewtonSummary solve_continuation(const std::vector<const EnergyTerm*>& terms, Eigen::VectorXd& x,
                                 const std::vector<int>& fixed_dofs,
                                 const SetBoundary& set_boundary,
                                 const ContinuationOptions& options);

}  // namespace yarnfit::shell
