#pragma once
// The one progress display of the command line (SPEC §5): every long command shows its
// numerics::Progress events as one terminal line, rewritten in place —
//   TASK: STAGE, STEP_NAME STEP/STEPS[, DETAIL][, best LABEL VALUE UNIT], ELAPSED s[, TIME LEFT]
// e.g. "yarn fit A2: swarm, iteration 3/10, best objective 0.0123, 41.0 s, about 96 s left in
// this stage". The time left is the stage's mean time per step so far times the steps
// planned that remain; where the steps are a budget the stage may stop short of (Ceres'
// iteration limit, the local step's evaluations) it is an upper bound, "at most". A new task
// starts a new line. Nothing is shown when disabled: with --quiet, or when stderr is not a
// terminal (for_stderr).

#include <iosfwd>
#include <mutex>
#include <string>

#include "numerics/progress.hpp"

namespace yarnfit::cli {

class ProgressDisplay {
 public:
  // Writes to `out` when `enabled`.
  ProgressDisplay(std::ostream& out, bool enabled);
  // On stderr, enabled unless `quiet` or stderr is not a terminal.
  static ProgressDisplay for_stderr(bool quiet);

  [[nodiscard]] bool enabled() const { return m_enabled; }
  // Shows `p` of `task` ("shell fit", "yarn fit A2"); safe to call from several threads.
  void update(const std::string& task, const numerics::Progress& p);
  // A callback for the libraries that shows their events under `task`.
  [[nodiscard]] numerics::ProgressFn callback(const std::string& task);
  // Ends the line (a newline when one was shown).
  void finish();

  // The line `p` makes after the events so far (what update writes after "\r\033[K"); it
  // updates the stage's timing as update does.
  [[nodiscard]] std::string line(const std::string& task, const numerics::Progress& p);

 private:
  std::ostream& m_out;
  bool m_enabled;
  std::mutex m_mutex;
  std::string m_task, m_stage;
  double m_stage_start = 0.0;   // seconds when the stage began (its first event's predecessor)
  double m_last_seconds = 0.0;  // of the task's last event
  int m_first_step = 0;
  bool m_shown = false;
};

}  // namespace yarnfit::cli
