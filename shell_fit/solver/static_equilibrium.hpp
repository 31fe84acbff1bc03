#pragma once
// Static equilibrium of a shell scene: minimise the sum of its energy terms over the free
// degrees of freedom (the clamped ones keep their values exactly) with the one Newton solver
// (numerics/newton/newton_solver.hpp), and load continuation for large loads (SPEC §3
// "Shell": sparse direct solver, line search, safeguard against indefinite Hessians).
//
// The shell's Newton settings are its preset (numerics::NewtonOptions::for_shell(), also
// NewtonOptions{}): the exact Hessian first
// in every iteration and the per-element PSD projection when it is not positive definite or
// its step fails (the next iteration then starts projected); the shift μ = 0 first (or what a
// non-positive diagonal entry demands), ×2 from 1e-8 after every failure up to 1e10, ×1/4
// after a step and back to 0 below 1e-8, so Newton's quadratic convergence returns near the
// solution (×2 took fewer iterations than ×10 on the indefinite tests: docs/shell-fit.md).
// Converged when ‖g_free‖∞ ≤ tolerance, in force units [N] the caller scales to the problem
// (a fraction of the expected clamp force per node).

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <functional>
#include <string>
#include <vector>

#include "numerics/newton/newton_solver.hpp"
#include "numerics/terms/energy_term.hpp"
#include "numerics/terms/scene.hpp"

namespace yarnfit::shell {

using numerics::EnergyTerm;
using numerics::NewtonOptions;
using numerics::NewtonStatus;
using numerics::NewtonSummary;
using numerics::total_energy;
using numerics::total_gradient;
using numerics::total_hessian;
using numerics::Triplets;
using TermList = numerics::TermList;

// Minimises the total energy over the DOFs not listed in fixed_dofs (entries of x; duplicates
// allowed), which keep their values exactly. x is updated in place and always holds a state
// with finite energy on return unless the status is invalid_start (then it is unchanged).
// Throws an input Error for invalid options, an empty term list, a null term or a fixed
// DOF out of range; numerical trouble is reported in the summary, never thrown.
NewtonSummary solve_static(const TermList& terms, Eigen::VectorXd& x, const std::vector<int>& fixed_dofs,
                           const NewtonOptions& options);

// Clamp reactions. Sign convention: the returned values are the force the clamp applies ON
// THE BODY at the given DOFs, equal to +∂E/∂x there. At equilibrium the elastic force on a
// clamped node (−∂E/∂x) is balanced by the clamp, so the clamp pushes with +∂E/∂x. The force
// the body applies on the clamp (what a tensile tester's load cell reads) is the negative.
// Example: a swatch stretched along +x pulls its right clamp back towards −x; the right clamp
// pulls the swatch towards +x, so the x-reactions there are positive and their sum is the
// tension.
[[nodiscard]] Eigen::VectorXd clamp_reaction(const TermList& terms, const Eigen::VectorXd& x,
                                             const std::vector<int>& dofs);
// Sum over `vertices` of the clamp reaction component `axis` (x: 0, y: 1, z: 2) for positions
// with `dim` entries per vertex; same sign convention as clamp_reaction.
[[nodiscard]] double clamp_force(const TermList& terms, const Eigen::VectorXd& x, const std::vector<int>& vertices,
                                 int dim, int axis);

// The DOFs dim·v + k (k < dim) of the given vertices: a clamped edge's fixed DOFs.
[[nodiscard]] std::vector<int> vertex_dofs(const std::vector<int>& vertices, int dim);

// The free DOFs of a scene, numbered: per DOF (of dof_count) its index among the DOFs not in
// fixed_dofs, in order, or −1 when fixed; `free_count` receives their number.
[[nodiscard]] std::vector<int> free_dof_index(int dof_count, const std::vector<int>& fixed_dofs, int& free_count);

// The free–free block H_ff of a matrix over all DOFs (free_index from free_dof_index): the
// Hessian the implicit function theorem's sensitivities solve with.
[[nodiscard]] Eigen::SparseMatrix<double> free_block(const Eigen::SparseMatrix<double>& h,
                                                     const std::vector<int>& free_index, int free_count);

// Newton options for one load step of a continuation: the defaults with a smaller iteration
// budget, so a load step that struggles fails fast and is halved instead of grinding on.
[[nodiscard]] inline NewtonOptions continuation_step_defaults() {
  NewtonOptions o = NewtonOptions::for_shell();
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

  // Every invalid field, named "ContinuationOptions.<field>" (the Newton options' as
  // "ContinuationOptions.newton.<field>"); empty when valid.
  [[nodiscard]] numerics::Problems problems() const;
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
// reached; energy and residual of the last converged state. On failure x holds the last
// converged state (at summary.lambda), or is unchanged if the start itself did not converge.
NewtonSummary solve_continuation(const TermList& terms, Eigen::VectorXd& x, const std::vector<int>& fixed_dofs,
                                 const SetBoundary& set_boundary, const ContinuationOptions& options);

}  // namespace yarnfit::shell
