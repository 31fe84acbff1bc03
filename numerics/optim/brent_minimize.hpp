#pragma once
// The minimum of a function of one variable on an interval by Brent's method (R. P. Brent,
// "Algorithms for Minimization without Derivatives", 1973, ch. 5): golden-section steps that
// keep the minimum bracketed, parabolic steps through the three best points where the function
// is smooth enough to trust them. A smooth minimum is found in about half the evaluations of
// golden section alone. Used where each evaluation is a set of equilibrium solves (the loop
// bends' k_θ, shell_fit/fit/fab_fit).
//
// A value that is not finite (an evaluation that failed) counts as worse than any finite one,
// and the parabola is not trusted while one of its points has such a value.

#include <functional>

namespace yarnfit::numerics {

struct ScalarMinimum {
  double x = 0.0;
  double value = 0.0;   // f(x); not finite when no evaluation was
  int evaluations = 0;
  bool converged = false;  // the bracket shrank to the tolerance within max_evaluations
};

// The minimum of `f` on [lower, upper] to an absolute tolerance `tolerance` in x (> 0), in at
// most `max_evaluations` evaluations.
ScalarMinimum brent_minimize(const std::function<double(double)>& f, double lower, double upper, double tolerance,
                             int max_evaluations = 100);

}  // namespace yarnfit::numerics
