#include "cli/batch_progress.hpp"

#include <cmath>

#include "fabrics_db/text_util.hpp"

namespace yarnfit::cli {

std::string duration_text(double seconds) {
  if (seconds < 10) return db::format_g(std::round(seconds * 10) / 10, 2) + " s";
  if (seconds < 90) return std::to_string(static_cast<int>(std::lround(seconds))) + " s";
  if (seconds < 5400) return db::format_g(seconds / 60, 2) + " min";
  return db::format_g(seconds / 3600, 2) + " h";
}

std::string batch_progress_line(const batch::BatchProgress& p) {
  std::string line = "batch: " + std::to_string(p.done) + "/" + std::to_string(p.selected) + " done";
  if (p.failed > 0) line += ", " + std::to_string(p.failed) + " failed";
  if (!p.running.empty()) {
    line += ", running ";
    for (std::size_t i = 0; i < p.running.size(); ++i)
      line += (i ? ", " : "") + p.running[i].fabric_id + " (" + p.running[i].stage + ")";
  }
  if (p.queued > 0) line += ", " + std::to_string(p.queued) + " queued";
  line += ", " + duration_text(p.seconds);
  if (p.seconds_left >= 0 && (p.queued > 0 || !p.running.empty()))
    line += ", about " + duration_text(p.seconds_left) + " left";
  return line;
}

}  // namespace yarnfit::cli
