#include "reports/summaries/fit_summary.hpp"

#include <sstream>

#include "fabrics_db/text_util.hpp"
#include "reports/summaries/shell_summary.hpp"
#include "reports/summaries/yarn_summary.hpp"

namespace yarnfit::reports {

std::string fit_summary(const std::string& fabric_id, const std::string& fabric_folder,
                        const results::ShellFitFile& shell_fit, const results::YarnFitFile& yarn_fit, const StageSeconds& seconds) {
  std::ostringstream summary;
  summary << "fabric " << fabric_id << " (" << fabric_folder << ")\n\n"
          << shell_summary(shell_fit, seconds.shell) << "\n"
          << yarn_summary(yarn_fit) << "\n"
          << "time per stage: shell " << db::format_g(seconds.shell, 3) << " s, yarn " << db::format_g(seconds.yarn, 3)
          << " s, total " << db::format_g(seconds.total, 3) << " s\n";
  return summary.str();
}

std::string yarn_summary_file(const std::string& fabric_id, const std::string& targets, const results::YarnFitFile& yarn_fit) {
  return "fabric " + fabric_id + ", targets " + targets + "\n" + yarn_summary(yarn_fit);
}

}  // namespace yarnfit::reports
