#pragma once
// The one Newton solver of both simulators (SPEC §3: "static equilibrium by Newton with a
// sparse direct solver, a line search and a safeguard against indefinite Hessians"; for the
// yarns the constrained Newton of (3.32) with the step control of A.2.3):
//
//   min_x E(x)   subject to   C x = 0   (C: a few dense rows, optional).
//
// Every iteration
//   1. assembles the lower triangle of the Hessian H (the exact one first), with an explicit
//      diagonal so that the pattern holds the shift μI;
//   2. factorises H + μ·d̄·I (d̄ the mean |diagonal|, so μ is unit-free) by a sparse LDLᵀ
//      whose symbolic analysis is redone only when the pattern changes; when that is not
//      positive definite the shift grows, and the per-element PSD projection of H replaces
//      the exact Hessian (the options say in which order);
//   3. solves for the direction: d = −(H+μI)⁻¹∇E, or with constraints the KKT step by a Schur
//      complement on the constraint rows, K δ0 = −∇E, K Y = Cᵀ, λ = (C Y)⁻¹ C δ0,
//      δ = δ0 − Y λ, with the round-off part of C δ removed so x stays exactly feasible;
//   4. starts the line search at the largest safe step the problem allows (a displacement
//      cap, a collision-free step) and backtracks by halves until the Armijo condition holds
//      and the energy is finite (a trial point outside the domain is never accepted);
//   5. shrinks the shift after a step (or grows it after a cut step, when asked).
// Converged when the residual — ‖∇E‖∞, or with constraints the projected gradient
// z = (I − Cᵀ(CCᵀ)⁻¹C)∇E of A.2.3 — is at most the tolerance. A failed solve leaves x at the
// last accepted state and says why in its summary (STYLE "Solvers report what happened").
//
// The two simulators were tuned separately and keep their own settings of the same
// algorithm, one preset each (NewtonPolicy::shell(), NewtonPolicy::yarn_tile()): which
// Hessian comes first after a failure, how the shift grows and shrinks, and what counts as
// the precision floor of the energy. Their fixed degrees of freedom, constraints, contact
// lists and load continuation stay with them, behind NewtonProblem.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "numerics/linear/shifted_ldlt.hpp"
#include "numerics/problems.hpp"
#include "numerics/terms/energy_term.hpp"

namespace yarnfit::numerics {

// What a Newton solve minimises. The solver calls these on states it has checked to be
// finite, except energy(), which tells it.
class NewtonProblem {
 public:
  virtual ~NewtonProblem() = default;
  [[nodiscard]] virtual int size() const = 0;
  // E(x) [J]: +inf outside the domain, NaN only for a broken contract.
  [[nodiscard]] virtual double energy(const Eigen::VectorXd& x) const = 0;
  // E(x) and ∇E(x) (gradient overwritten, #x).
  virtual double energy_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& gradient) const = 0;
  // Appends the lower triangle (row ≥ column) of ∇²E(x), per-element PSD-projected with
  // `project_psd`. Returns false with the reason in *why when an entry is not finite.
  virtual bool hessian(const Eigen::VectorXd& x, bool project_psd, Triplets& lower, std::string* why) const = 0;
  // Dense constraint rows C (x must satisfy C x = 0), or nullptr for none.
  [[nodiscard]] virtual const Eigen::MatrixXd* constraints() const { return nullptr; }

  // The largest step fraction t ∈ (0, 1] the line search may start from along dx, and
  // whether anything limited it (a limited step counts as cut for the shift's update).
  struct StepBound {
    double fraction = 1.0;
    bool limited = false;
  };
  [[nodiscard]] virtual StepBound max_step(const Eigen::VectorXd& /*x*/, const Eigen::VectorXd& /*dx*/) const {
    return {};
  }
  // Called before the first iteration and after every accepted step (a contact list is
  // rebuilt here before it could miss a pair).
  virtual void prepare(const Eigen::VectorXd& /*x*/) {}

  // The quantities the caller reads from the solution (a homogenised stress), for the
  // read-out stopping test of NewtonOptions::readout_tolerance; false when there are none.
  virtual bool readout(const Eigen::VectorXd& /*x*/, Eigen::VectorXd& /*values*/) const { return false; }

  // Words for the summary when the start energy or a gradient is not finite.
  [[nodiscard]] virtual std::string describe_invalid_energy(const Eigen::VectorXd& /*x*/) const { return {}; }
  [[nodiscard]] virtual std::string describe_invalid_gradient(const Eigen::VectorXd& /*x*/) const { return {}; }
};

// What the solver takes as the energy's precision floor, where the predicted decrease
// ½gᵀH⁻¹g drowns in the rounding of E (which sums thousands of element energies, each exact
// to about 1e-16 of its size). Each simulator's preset picks one (NewtonPolicy):
enum class PrecisionFloor {
  // The shell's: when the first trial's change of E is below 1e-12·|E|, the step is taken if
  // it lowers the residual below floor_residual_factor times the current one; when no shift
  // gives an Armijo step and the predicted decrease is below 1e-12·|E|, the solve stops with
  // line_search_failed (the tolerance is below what the problem can resolve).
  first_trial_change,
  // The yarn tile's: when the predicted decrease along the (cut) step is below 1e-12·|E|, the
  // step is taken if it lowers the residual below floor_residual_factor times the current
  // one, and the iteration ends either way; an iteration that found no step ends the solve as
  // converged when the residual is within roundoff_converged_factor of the tolerance.
  predicted_decrease,
};

// How the solver safeguards its steps: which Hessian comes first after a failure, how the
// shift grows and shrinks, the line search, and what counts as the energy's precision floor.
// The two simulators were tuned separately; each takes its preset whole (shell(),
// shell_unprojected(), yarn_tile()) rather than setting these field by field. The member
// defaults are the shell's.
struct NewtonPolicy {
  int max_line_search_steps = 40;  // halvings before a direction is given up
  double armijo = 1e-4;            // c in E(x + t d) ≤ E(x) + c·t·gᵀd

  // Hessian. With project_psd the per-element PSD projection is the fallback when the exact
  // Hessian's step fails (false: the exact Hessian with the shift as the only safeguard).
  // Near equilibrium the exact Hessian is usually positive definite: it gives the true Newton
  // step and skips the per-element eigen-decompositions.
  bool project_psd = true;
  bool exact_hessian_first = true;
  // After an iteration whose exact Hessian failed, start the next one with the projection
  // (once; then the exact Hessian is tried again).
  bool remember_projection = true;
  // After a failed line search with the exact Hessian, switch to the projection before the
  // shift grows.
  bool project_after_failed_line_search = true;

  // The shift μ (relative to the mean |diagonal| of H).
  double shift_initial = 0.0;  // μ at the start of every solve
  double shift_start = 1e-8;   // the first non-zero μ
  double shift_growth = 2.0;   // after a failure with the projected Hessian
  double shift_max = 1e10;
  // Beyond shift_max: give up (true), or stay at shift_max until the attempts run out.
  bool fail_beyond_shift_max = true;
  int max_failed_attempts = 0;  // failed factorisations or line searches per iteration (0: no limit)
  // The exact Hessian is first shifted up to this μ (growing by exact_shift_growth, at least
  // to exact_shift_floor) before the projection replaces it: a shifted step still follows the
  // directions of negative curvature out of a saddle, which the projection discards.
  // 0: project at once.
  double exact_shift_limit = 0.0;
  double exact_shift_growth = 10.0;
  double exact_shift_floor = 1e-6;
  double shift_shrink = 0.25;  // after an accepted step
  // μ never shrinks below shift_floor; with shift_floor = 0, a μ below shift_start drops to
  // 0 (plain Newton, quadratic convergence near the solution).
  double shift_floor = 0.0;
  // After an accepted step that was cut (step bound or backtracking), μ grows by this factor
  // (1: it shrinks as after a full step).
  double limited_step_growth = 1.0;
  // A non-positive diagonal entry rules out positive definiteness: start μ past it.
  bool shift_past_nonpositive_diagonal = true;
  // With constraints: an exact Hessian that is indefinite but positive definite on C δ = 0
  // (positive_definite_on_constraints, shifted_ldlt.hpp) gives the constrained Newton step as
  // it is, without a shift. A shift large enough to make the whole Hessian positive definite
  // would slow convergence to a linear rate along the soft directions the constraints keep.
  bool accept_definite_on_constraints = false;

  PrecisionFloor precision_floor = PrecisionFloor::first_trial_change;
  double floor_residual_factor = 0.5;
  double roundoff_converged_factor = 0.0;  // predicted_decrease only (0: never)

  // The shell's (shell_fit/solver/static_equilibrium.hpp): the exact Hessian first in every
  // iteration and the per-element PSD projection when it is not positive definite or its step
  // fails (the next iteration then starts projected); μ = 0 first (or what a non-positive
  // diagonal entry demands), ×2 from 1e-8 after every failure up to 1e10 (then the solve
  // fails), ×1/4 after a step and back to 0 below 1e-8; the precision floor of the first
  // trial's change. The member defaults.
  [[nodiscard]] static NewtonPolicy shell();
  // The shell's without the projection: the exact Hessian with the shift as the only
  // safeguard (a bending-dominated scene, whose projection drops the θ∇²θ part that turns it).
  [[nodiscard]] static NewtonPolicy shell_unprojected();
  // The yarn tile's (yarn_fit/solver/equilibrium.hpp): the exact Hessian first in every
  // iteration, shifted by up to 1e-3 of its mean diagonal before the projection replaces it;
  // μ from 1e-8, ×1/4 after a full step, ×4 after a cut one, ×100 after a failure, between
  // 1e-10 and 1e2, at most 8 failed attempts per iteration; the exact step where the Hessian
  // is definite on the constraints; the precision floor of the predicted decrease.
  [[nodiscard]] static NewtonPolicy yarn_tile();

  // Adds every invalid field to `out`, named prefix + field.
  void add_problems(Problems& out, const std::string& prefix) const;
};

// A Newton solve: its budget and stopping tests, which the caller sets, and the safeguards of
// its simulator, which it takes from a preset:
//   NewtonOptions o = NewtonOptions::for_yarn_tile();
//   o.tolerance = …;
// NewtonOptions{} is for_shell().
struct NewtonOptions {
  int max_iterations = 200;
  // On the residual (∞-norm of the free or projected gradient), in the problem's units:
  // the caller scales it to the problem (a fraction of a clamp force per node, a strain of
  // the stiff yarn phase).
  double tolerance = 1e-8;
  double time_limit_s = 0.0;  // 0: none
  // After loose_after iterations, a residual ≤ loose_tolerance (0: off) ends the solve as
  // converged_loosely: a caller that can bound the read-out error it accepts says so here,
  // and the status keeps it visible.
  double loose_tolerance = 0.0;
  int loose_after = 60;

  // The read-out test (0: off), in the read-out's units: the solve ends as
  // converged_readout once the problem's read-out changed by at most readout_tolerance / 4
  // (∞-norm) over each of the last readout_steps accepted steps, the last of them a full
  // Newton step. Near a degenerate minimum Newton converges only linearly — a contact barrier
  // that enters as (1 − x)⁶ gives the ratio (n − 2)/(n − 1) = 0.8 — and then the change still
  // to come is at most 0.8/(1 − 0.8) = 4 times the last one, within readout_tolerance,
  // although the residual may be far above `tolerance`. That bound does not hold when the
  // state then slides along a mechanism (slack yarns: tests/yarn_fit, SlackTile; figures in
  // docs/slack-tiles.md). Callers choose the tolerance a decade below what they compare.
  double readout_tolerance = 0.0;
  int readout_steps = 3;

  // The simulator's safeguards (a preset of NewtonPolicy).
  NewtonPolicy policy;

  // The presets with the default budget and tolerance (NewtonPolicy's of the same names).
  [[nodiscard]] static NewtonOptions for_shell();
  [[nodiscard]] static NewtonOptions for_shell_unprojected();
  [[nodiscard]] static NewtonOptions for_yarn_tile();

  // Every invalid field, named "NewtonOptions.<field>" ("NewtonOptions.policy.armijo");
  // empty when valid.
  [[nodiscard]] Problems problems() const;
  // The same under another name: prefix + field ("newton.tolerance" for prefix "newton.").
  void add_problems(Problems& out, const std::string& prefix) const;
};

enum class NewtonStatus {
  converged,             // residual ≤ tolerance
  converged_loosely,     // residual ≤ loose_tolerance after loose_after iterations
  converged_readout,     // the read-out settled within readout_tolerance (residual above tolerance)
  max_iterations,        // iteration budget spent; x is the last (valid) iterate
  line_search_failed,    // no step decreased the energy, even with the largest shift
  invalid_start,         // the initial energy is not finite (or NaN)
  linear_solver_failed,  // the shifted Hessian could not be factorised at any shift
  non_finite,            // a gradient or Hessian was NaN/inf at a state of finite energy
  time_limit,            // time_limit_s reached before convergence
};

[[nodiscard]] const char* to_string(NewtonStatus status);

struct NewtonSummary {
  NewtonStatus status = NewtonStatus::max_iterations;
  std::string message;            // why it stopped, in words (empty when converged)
  int iterations = 0;             // accepted Newton steps (summed over a continuation)
  double residual = 0.0;          // at the returned x
  double initial_residual = 0.0;  // at the start
  double tolerance = 0.0;         // the tolerance used
  double energy = 0.0;            // E at the returned x [J]
  double seconds = 0.0;           // wall time
  int regularised_steps = 0;      // accepted steps that needed a shift μ > 0
  int projected_steps = 0;        // accepted steps taken with the projected Hessian
  int analyses = 0;               // symbolic analyses of the sparsity pattern
  int factorisations = 0;         // numeric factorisations (several per iteration when shifted)
  int assemblies = 0;             // Hessian assemblies (a second one when the projection replaces the exact)
  int energy_evaluations = 0;     // trial energies of the line searches
  // Filled by callers that walk a load parameter (shell_fit's continuation); 0 otherwise.
  int continuation_steps = 0;     // accepted load steps
  int cut_backs = 0;              // failed load steps that were halved and retried
  double lambda = 1.0;            // load parameter reached
  double readout_change = 0.0;    // ∞-norm change of the read-out over the last accepted step (0 without)

  [[nodiscard]] bool converged() const {
    return status == NewtonStatus::converged || status == NewtonStatus::converged_loosely ||
           status == NewtonStatus::converged_readout;
  }
  // One line: status, iterations, residual, energy, time (and load steps, cut-backs).
  [[nodiscard]] std::string brief() const;
};

// Minimises problem's energy from x (updated in place; resized to problem.size() with zeros
// when its size differs). With constraints x is first projected onto C x = 0. On return x
// holds a state of finite energy unless the status is invalid_start (then the start, after
// that projection). Throws an input Error for invalid options; numerical trouble is
// reported in the summary, never thrown. A caller that solves the same system again and
// again passes a `workspace` it keeps: its symbolic analysis and triplet slots carry over
// (shifted_ldlt.hpp), and it holds the last factorisation on return.
NewtonSummary solve_newton(NewtonProblem& problem, Eigen::VectorXd& x, const NewtonOptions& options,
                           ShiftedLdlt* workspace = nullptr);

// The residual of a gradient: ‖z‖∞ with z = (I − Cᵀ(CCᵀ)⁻¹C) g, or ‖g‖∞ without C.
[[nodiscard]] Eigen::VectorXd projected_gradient(const Eigen::MatrixXd* constraints, const Eigen::VectorXd& gradient);

}  // namespace yarnfit::numerics
