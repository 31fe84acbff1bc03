#pragma once
// The yarn fit's progress events (numerics/progress.hpp): every stage reports its best objective.

#include <string>

#include "numerics/progress.hpp"

namespace yarnfit::yarn {

// A progress event of the fit: the best objective of the stage and its planned steps (`budget`:
// the stage may stop before them, as the local step before its evaluation budget).
inline numerics::Progress fit_progress(const std::string& stage, const char* step_name, int step, int steps, bool budget,
                                      double best, double seconds) {
  numerics::Progress p;
  p.stage = stage;
  p.step_name = step_name;
  p.step = step;
  p.steps = steps;
  p.budget = budget;
  p.best = best;
  p.best_label = "objective";
  p.seconds = seconds;
  return p;
}

}  // namespace yarnfit::yarn
