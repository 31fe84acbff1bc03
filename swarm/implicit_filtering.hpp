#pragma once
// Local refinement of a least-squares objective g(x) = |r(x)|² whose values are rough at small
// scales: implicit filtering (Gilmore & Kelley 1995; Kelley, "Implicit Filtering", SIAM
// 2011) with Gauss–Newton steps on stencil differences.
//
// Why not COBYLA or Gauss–Newton with small finite differences: the yarn objective is a sum
// of squared errors of simulations that settle in one of several nearby equilibria. Moving a
// parameter by 1e-4 of its range can move g by 10–30 % (a compression search lands on
// another branch, the rest shape on another equilibrium), while over 1e-2 of the range g
// follows a smooth trend. COBYLA's linear models and a Jacobian from tiny differences follow
// the jumps; implicit filtering differences over a stencil of half-width h that starts large
// and shrinks only when the stencil finds nothing better than its centre, so at every scale it
// follows the trend the jumps sit on. For least squares the stencil gives the Jacobian of the
// residuals as well, and a Gauss–Newton step uses the curvature that the sum of squares
// carries (the parameters' trade-offs, e.g. a long valley between two stiffnesses).
//
// One iteration at scale h (unit cube of ParameterSpace, so h is a fraction of every range):
//  1. the residuals at the 2d stencil points u ± h eᵢ, in parallel (a point outside the box is
//     left out and its coordinate differenced one-sidedly);
//  2. J by central differences (one-sided where a side failed or lies outside the box);
//  3. the Gauss–Newton step d = −(JᵀJ + μ diag JᵀJ)⁻¹ Jᵀr, limited to max_step_scales · h in
//     every coordinate and clamped into the box, tried at d, d/2, d/4 …;
//  4. the first trial better than both the centre and the best stencil point becomes the
//     centre; otherwise the best stencil point does if it beats the centre; otherwise (a
//     stencil failure: the centre is the best point at this scale) h ← shrink · h.
// It stops when h falls below min_scale (converged at the resolution asked for), at the
// evaluation or time budget, or at stop_value. Like the COBYLA wrapper it returns the best
// point evaluated, never evaluates outside the bounds, and counts and reports failed
// evaluations (a failed stencil point is left out of the differences; a failed trial is
// rejected). Evaluations are pure functions of x and all choices are made in a fixed order,
// so the run does not depend on the number of threads.

#include <Eigen/Core>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "swarm/objective.hpp"
#include "swarm/parameter_space.hpp"

namespace yarnfit::swarm {

// r(x) with x in the caller's coordinates; g = |r|². Throws (or returns non-finite entries)
// when the evaluation fails; must return the same length at every x and be safe to call
// concurrently (the stencil points are evaluated in parallel).
using ResidualObjective = std::function<Eigen::VectorXd(const Eigen::VectorXd& x)>;

struct ImplicitFilteringSettings {
  int max_evaluations = 150;
  double max_seconds = 0.0;     // 0: no time limit
  double initial_scale = 0.02;  // stencil half-width h at the start (unit cube)
  double min_scale = 0.002;     // stop once h < this
  double shrink = 0.5;          // h ← shrink · h after a stencil failure
  double max_step_scales = 10.0;  // Gauss–Newton step ≤ this · h in every coordinate
  int line_search_steps = 3;    // trials d, d/2, …: at most this many per iteration
  // Levenberg term μ (relative to each diagonal entry of JᵀJ): keeps the step finite where
  // the residuals hardly depend on a parameter.
  double levenberg = 1e-6;
  double stop_value = -std::numeric_limits<double>::infinity();  // stop once g ≤ this
  int threads = 0;              // for the stencil; 0: OpenMP's default
  int max_failures_kept = 50;

  // Every setting out of range, under its field's name; empty when valid.
  [[nodiscard]] numerics::Problems problems() const;
};

enum class ImplicitFilteringStatus {
  converged,        // the stencil scale fell below min_scale
  stop_value,       // g ≤ stop_value reached
  max_evaluations,  // the evaluation budget would be exceeded by the next stencil or trial
  max_time,         // time budget spent
  start_failed,     // the start could not be evaluated
};
[[nodiscard]] const char* to_string(ImplicitFilteringStatus status);

// How an iteration ended.
enum class ImplicitFilteringMove { gauss_newton, stencil_point, shrink };
[[nodiscard]] const char* to_string(ImplicitFilteringMove move);

struct ImplicitFilteringIteration {
  int evaluations = 0;     // evaluations so far, after this iteration
  double scale = 0.0;      // h used by this iteration's stencil
  double value = 0.0;      // g at the centre after this iteration
  ImplicitFilteringMove move = ImplicitFilteringMove::shrink;
  int trials = 0;          // Gauss–Newton trials evaluated
};

struct ImplicitFilteringSummary {
  ImplicitFilteringStatus status = ImplicitFilteringStatus::start_failed;
  std::string message;
  Eigen::VectorXd best_point;  // caller's coordinates; the start when it failed
  double best_value = std::numeric_limits<double>::infinity();
  double start_value = std::numeric_limits<double>::infinity();
  double final_scale = 0.0;    // h when it stopped
  int evaluations = 0;
  int failed = 0;
  std::vector<FailedEvaluation> failures;  // the first max_failures_kept
  std::vector<ImplicitFilteringIteration> history;
  double seconds = 0.0;

  [[nodiscard]] bool usable() const;
  [[nodiscard]] std::string brief_report() const;
};

// Called after every iteration (and once after the start) with the run so far.
using ImplicitFilteringProgress = std::function<void(const ImplicitFilteringSummary&)>;

// Minimises |r|² from `start` (caller's coordinates, inside the bounds). Throws
// an input Error for invalid settings or a start outside the bounds; failed
// evaluations are reported in the summary, never thrown.
[[nodiscard]] ImplicitFilteringSummary run_implicit_filtering(const ParameterSpace& space,
                                                              const ResidualObjective& residuals,
                                                              const Eigen::VectorXd& start,
                                                              const ImplicitFilteringSettings& settings = {},
                                                              const ImplicitFilteringProgress& progress = {});

}  // namespace yarnfit::swarm
