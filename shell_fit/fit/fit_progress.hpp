#pragma once
// Progress of a shell fit, for a display on a terminal (SPEC §5: stage, iteration, best
// error, time). The fits call a FitProgressFn after every Ceres iteration and at the steps of
// their start searches; the caller decides whether and how to show it.

#include <functional>
#include <limits>
#include <string>

namespace yarnfit::shell {

struct FitProgress {
  // What runs now, e.g. "in-plane start 2/3", "in-plane refine", "bending start (weft)",
  // "bending".
  std::string stage;
  int iteration = 0;  // Ceres iteration (or trial of a start search) within the stage
  // Best root-mean-square residual so far in the fit, as a percentage of the mean measured
  // value (force and compression residuals are normalised by theirs; the aspect ratio by the
  // mean measured ratio). NaN before the first evaluation.
  double best_error_pct = std::numeric_limits<double>::quiet_NaN();
  double seconds = 0.0;  // since the fit began
};

using FitProgressFn = std::function<void(const FitProgress&)>;

}  // namespace yarnfit::shell
