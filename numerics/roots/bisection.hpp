#pragma once
// Bisection and bracketing on a monotone predicate: the root finder's forms for a crossing
// known only by its side (bracketed_root.hpp, find_root, is for a root of a function whose
// values guide the search), for
//  * the wale spacing and the loop bulges of a generated knit tile (fabrics_db/tile/knit_tile:
//    a polyline length against the stitch length, to a relative 1e-12);
//  * the shear stiffness kss that gives the data's small-stretch bias modulus (shell_fit's
//    in-plane start, 60 halvings in log kss);
//  * the bending length whose pear loop has the data's aspect ratio (shell_fit's bending
//    start: a bracket by doubling, then 4 halvings in log ℓ; each trial an equilibrium solve).
//
// The predicate below(x) says on which side of the crossing x lies: true when x lies below it
// (the crossing is above x), false when x lies at or above it, nothing when it cannot be
// evaluated at x (a failed equilibrium: the search stops there). It must be monotone: true up
// to the crossing, false beyond it.
//
// Both are written so that they give the same bits as the loops they replaced; bisect is
//     for (k = 0; k < halvings && (relative_width == 0 || upper − lower > relative_width · upper); ++k)
//       m = midpoint(lower, upper); (below(m) ? lower : upper) = m;
// and returns midpoint(lower, upper) of the bracket reached.

#include <functional>
#include <optional>
#include <string>

namespace yarnfit::numerics {

using SidePredicate = std::function<std::optional<bool>(double x)>;

enum class Midpoint {
  arithmetic,  // (lower + upper)/2, computed as 0.5 · (lower + upper)
  geometric,   // √(lower · upper): halves the bracket in log x (0 < lower ≤ upper)
};
[[nodiscard]] double midpoint(double lower, double upper, Midpoint rule);

struct BisectionOptions {
  Midpoint midpoint = Midpoint::arithmetic;
  int halvings = 60;            // at most this many, one evaluation each
  double relative_width = 0.0;  // > 0: stop before a halving once upper − lower ≤ relative_width · upper

  [[nodiscard]] std::string problem() const;  // empty when valid
};

struct BisectionResult {
  double lower = 0.0, upper = 0.0;  // the bracket reached (the one before a failed evaluation)
  double x = 0.0;                   // its midpoint by options.midpoint
  int halvings = 0;                 // evaluations that moved an end
  bool evaluation_failed = false;   // below() gave nothing at the next midpoint: the search stopped
};

// [lower, upper] brackets the crossing: below(lower) and !below(upper) are assumed, never
// evaluated. Throws an input Error for invalid options or a reversed bracket (or, with
// geometric midpoints, one that is not positive).
BisectionResult bisect(const SidePredicate& below, double lower, double upper, const BisectionOptions& options);

struct FactorBracketOptions {
  double lower = 0.0, upper = 0.0;  // 0 < lower ≤ upper, finite: the range searched
  double factor = 2.0;              // > 1: each step multiplies x by it (up) or divides by it (down)

  [[nodiscard]] std::string problem() const;  // empty when valid
};

struct FactorBracket {
  std::optional<double> below;      // the last point evaluated below the crossing
  std::optional<double> above;      // the last point evaluated at or above it
  std::optional<double> failed_at;  // the point where below() gave nothing (the search stopped)
  int evaluations = 0;
  [[nodiscard]] bool bracketed() const { return below && above; }
};

// From start (clamped to [lower, upper]), steps towards the crossing by the factor (up while
// x lies below it, down while above, each step clamped to the range) until it has evaluated a
// point on each side, x lies below the crossing at upper (or above it at lower), or an
// evaluation failed. Throws an input Error for invalid options.
FactorBracket bracket_by_factor(const SidePredicate& below, double start, const FactorBracketOptions& options);

}  // namespace yarnfit::numerics
