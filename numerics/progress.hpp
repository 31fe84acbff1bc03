#pragma once
// Progress of a long computation (SPEC §5: "Long work shows progress on a terminal (stage,
// iteration, best error, time left)"). The shell fits, the yarn fit and the yarn commands
// report these events through a ProgressFn; what to show, and whether, is the caller's
// business (the command line rewrites one terminal line, cli/progress_display.hpp).

#include <functional>
#include <limits>
#include <string>

namespace yarnfit::numerics {

struct Progress {
  // What runs now, e.g. "in-plane (weft, warp) start 2/3", "bending (weft)", "swarm", "local";
  // empty when the computation has a single stage.
  std::string stage;
  std::string step_name = "iteration";  // what `step` counts: "iteration", "evaluation", "point"
  int step = 0;                         // within the stage
  int steps = 0;                        // planned in the stage; 0 when unknown
  // `steps` is a budget the stage may stop short of (an iteration limit): a time left from it
  // is an upper bound.
  bool budget = false;
  // Best error so far (NaN before the first), what it is and its unit: e.g. 1.2 "rms error"
  // "%" for the shell fits, 0.013 "objective" "" for the yarn fit. Empty label: no error.
  double best = std::numeric_limits<double>::quiet_NaN();
  std::string best_label;
  std::string best_unit;
  double seconds = 0.0;  // since the computation began [s]
  std::string detail;    // anything else worth a glance, e.g. "s = 0.05"
};

using ProgressFn = std::function<void(const Progress&)>;

}  // namespace yarnfit::numerics
