#include "cli/progress_display.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <iostream>

#include "fabrics_db/text_util.hpp"

namespace yarnfit::cli {

ProgressDisplay::ProgressDisplay(std::ostream& out, bool enabled) : m_out(out), m_enabled(enabled) {}

ProgressDisplay ProgressDisplay::for_stderr(bool quiet) { return ProgressDisplay(std::cerr, !quiet && ::isatty(STDERR_FILENO)); }

std::string ProgressDisplay::line(const std::string& task, const numerics::Progress& p) {
  if (task != m_task) {  // another task's clock: its seconds count from its own start
    m_task = task;
    m_stage.clear();
    m_last_seconds = 0.0;
    m_first_step = p.step;
    m_stage_start = 0.0;
  } else if (p.stage != m_stage) {
    // The stage began when the previous one last reported.
    m_stage = p.stage;
    m_stage_start = m_last_seconds;
    m_first_step = p.step;
  }
  m_stage = p.stage;
  m_last_seconds = p.seconds;

  std::string text = task + ":";
  std::string sep = " ";
  const auto part = [&](const std::string& s) {
    text += sep + s;
    sep = ", ";
  };
  if (!p.stage.empty()) part(p.stage);
  if (!p.step_name.empty()) part(p.step_name + " " + std::to_string(p.step) + (p.steps > 0 ? "/" + std::to_string(p.steps) : ""));
  if (!p.detail.empty()) part(p.detail);
  if (!p.best_label.empty()) {
    char best[32] = "-";
    if (std::isfinite(p.best)) std::snprintf(best, sizeof best, "%.4g%s%s", p.best, p.best_unit.empty() ? "" : " ", p.best_unit.c_str());
    part("best " + p.best_label + " " + best);
  }
  char elapsed[32];
  std::snprintf(elapsed, sizeof elapsed, "%.1f s", p.seconds);
  part(elapsed);
  const int done = p.step - m_first_step + 1;
  if (p.steps > 0 && p.step < p.steps && done > 0 && p.seconds > m_stage_start) {
    const double per_step = (p.seconds - m_stage_start) / done;
    part(std::string(p.budget ? "at most " : "about ") + db::format_g(std::ceil(per_step * (p.steps - p.step)), 4) +
         " s left" + (p.stage.empty() ? "" : " in this stage"));
  }
  return text;
}

void ProgressDisplay::update(const std::string& task, const numerics::Progress& p) {
  if (!m_enabled) return;
  const std::lock_guard lock(m_mutex);
  const bool new_task = m_shown && task != m_task;
  const std::string text = line(task, p);
  if (new_task) m_out << "\n";
  m_out << "\r\033[K" << text << std::flush;
  m_shown = true;
}

numerics::ProgressFn ProgressDisplay::callback(const std::string& task) {
  if (!m_enabled) return {};
  return [this, task](const numerics::Progress& p) { update(task, p); };
}

void ProgressDisplay::finish() {
  const std::lock_guard lock(m_mutex);
  if (m_shown) m_out << "\n" << std::flush;
  m_shown = false;
  m_task.clear();
}

}  // namespace yarnfit::cli
