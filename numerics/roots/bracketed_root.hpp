#pragma once
// The 1-D root finder of the project: a root of an increasing function f on [lower, upper],
// from a guess (a crossing known only by its side: bisection.hpp), for
//  * the zero-orthogonal-stress compression of the yarn tile, ∂Ψ/∂c = 0 (readouts.hpp: each
//    evaluation an equilibrium solve);
//  * the same for the fitted shell model (shell_fit/targets: the uniform targets);
//  * the clamp stretch that gives a measured gauge stretch (clamped_stretch.hpp: each
//    evaluation an equilibrium solve, warm-started from the last);
//  * the bulge of the pear loop's start shape that closes the loop (pear_loop.hpp).
//
// Bracket, then Illinois. From the guess a, the first step goes towards the root (up when
// f(a) < 0) by `initial_step`, or by −f(a)/initial_slope when a slope is known; every further
// step doubles, and after two evaluations on one side it aims past the secant's root by 10 %
// (within ¼ to 4 times the step it would have taken): warm searches start close to the root,
// where the secant is accurate. Once f changes sign, Illinois (regula falsi that halves the
// kept end's value when the same end is kept twice) narrows the bracket and converges
// superlinearly; an end where f is ±inf (past a barrier) is split in half instead.
// Evaluations are never outside [lower, upper] and never more than max_evaluations.
//
// Stops when |f| ≤ f_tolerance at an evaluated point (0: the exact root), when the bracket is
// narrower than x_tolerance, or when an iterate moves by less than a tenth of it.

#include <functional>
#include <limits>
#include <optional>
#include <string>

#include "numerics/problems.hpp"

namespace yarnfit::numerics {

struct RootFindOptions {
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
  double initial_step = 0.05;  // first bracketing step [units of x]
  double initial_slope = 0.0;  // > 0: a known df/dx for the first step (0: unknown)
  double x_tolerance = 1e-5;
  double f_tolerance = 0.0;
  int max_evaluations = 60;

  // Every invalid field, under its name; empty when valid.
  [[nodiscard]] Problems problems() const;
};

enum class RootStatus {
  converged,             // a point within the tolerances
  not_bracketed,         // f kept its sign up to a bound of [lower, upper]
  evaluation_failed,     // f could not be evaluated at a point the search needed
  evaluation_limit,      // max_evaluations before the tolerances were met
};
[[nodiscard]] const char* to_string(RootStatus status);

struct RootResult {
  RootStatus status = RootStatus::evaluation_failed;
  double x = 0.0;        // the last point evaluated successfully (the root when converged)
  double f = 0.0;        // f there
  int evaluations = 0;
  [[nodiscard]] bool converged() const { return status == RootStatus::converged; }
};

// f(x), or nothing when it cannot be evaluated there (a failed equilibrium: the search stops).
// ±inf is a valid value: its sign places x on one side of the root.
using RootFunction = std::function<std::optional<double>(double x)>;

// Throws an input Error for invalid options.
RootResult find_root(const RootFunction& f, double guess, const RootFindOptions& options);

}  // namespace yarnfit::numerics
