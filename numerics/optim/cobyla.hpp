#pragma once
// The one COBYLA of the project (NLopt's LN_COBYLA): the thesis's local step after the swarm
// (6.5.3, through swarm/cobyla.hpp on the unit cube of a ParameterSpace) and the thesis's
// zero-orthogonal-stress compression search (yarn_fit/homogenise/readouts.hpp), wrapped so
// that the pitfalls NLopt users report never reach the caller:
//   * the result is the best point evaluated, not COBYLA's last iterate;
//   * every evaluated point lies inside the bounds (COBYLA's trial points are clamped into
//     the box before the objective sees them);
//   * max_evaluations is never exceeded and max_seconds is checked before every evaluation
//     (the wrapper stops NLopt itself rather than trusting its counters);
//   * a failed evaluation (throw, NaN, inf) is counted, its message kept, and COBYLA is given
//     a finite penalty worse than anything seen, never NaN (which would poison its linear
//     models) and never an exception through NLopt's C code;
//   * the termination reason is an enum with a sentence, not a bare "nlopt failure", and an
//     NLopt failure carries NLopt's own message out.
//
// The box is [lower, upper] per coordinate; initial_step and x_tolerance are in the units of
// x (the swarm's adapter works in its unit cube, where they are fractions of each range).

#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "numerics/optim/objective.hpp"

namespace yarnfit::numerics {

struct CobylaSettings {
  int max_evaluations = 200;
  double max_seconds = 0.0;   // 0: no time limit
  double initial_step = 0.1;  // step of the first simplex, per coordinate [units of x]
  // Stop when a step changes no unit coordinate by more than this (NLopt xtol_abs).
  double x_tolerance = 1e-8;
  // Stop when an iteration changes f by less than this, relative / absolute (0: off).
  double f_tolerance_relative = 0.0;
  double f_tolerance_absolute = 0.0;
  // Stop as soon as f ≤ stop_value (-inf: off).
  double stop_value = -std::numeric_limits<double>::infinity();
  int max_failures_kept = 50;

  // Every setting out of range, under its field's name; empty when valid.
  [[nodiscard]] Problems problems() const;
};

enum class CobylaStatus {
  converged,           // NLopt's generic success
  x_tolerance,         // steps below x_tolerance
  f_tolerance,         // changes of f below f_tolerance_*
  stop_value,          // f ≤ stop_value reached
  max_evaluations,     // evaluation budget spent
  max_time,            // time budget spent
  roundoff_limited,    // NLopt: round-off prevented progress (the best point is still usable)
  nlopt_failure,       // NLopt reported a failure; the message carries its text
};
[[nodiscard]] const char* to_string(CobylaStatus status);
// True for the statuses that mean a (local) minimum was reached rather than a budget spent.
[[nodiscard]] bool is_converged(CobylaStatus status);

struct CobylaSummary {
  CobylaStatus status = CobylaStatus::nlopt_failure;
  std::string message;          // the status in a sentence, with NLopt's own text if any
  Eigen::VectorXd best_point;   // the start when every evaluation failed
  double best_value = std::numeric_limits<double>::infinity();  // +inf when every one failed
  double start_value = std::numeric_limits<double>::infinity(); // f(start); +inf if it failed
  int evaluations = 0;
  int failed = 0;
  std::vector<FailedEvaluation> failures;  // the first max_failures_kept failures
  double seconds = 0.0;

  [[nodiscard]] bool usable() const;
  [[nodiscard]] std::string brief_report() const;
};

// Minimises objective over the box [lower, upper] from `start` (inside it). Throws
// an input Error for invalid settings, bounds or a start outside them; failed
// evaluations and NLopt failures are reported in the summary, never thrown.
[[nodiscard]] CobylaSummary run_cobyla(const Objective& objective, const Eigen::VectorXd& start,
                                       const Eigen::VectorXd& lower, const Eigen::VectorXd& upper,
                                       const CobylaSettings& settings = {});

}  // namespace yarnfit::numerics
