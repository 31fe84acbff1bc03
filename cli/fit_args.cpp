#include "cli/fit_args.hpp"

#include <iostream>

#include "cli/commands.hpp"
#include "cli/option_names.hpp"
#include "cli/progress_display.hpp"

namespace yarnfit::cli {

int run_fit_command(FitArgs a) {
  a.request.report = !a.no_report && a.request.stages == "all";
  ProgressDisplay progress = ProgressDisplay::for_stderr(a.quiet);
  db::Problems problems;  // names in the request the library cannot use, refused with the plan's
  const pipeline::FitPlan plan = pipeline::fit_plan(a.request, problems);
  const auto observer = [&progress](const pipeline::StageEvent& e) {
    if (e.stage == pipeline::Stage::shell) progress.update("shell fit", e.progress);
    if (e.stage == pipeline::Stage::yarn) progress.update("yarn fit " + e.fabric_id, e.progress);
  };
  const pipeline::PipelineResult result = pipeline::run_plan(plan, observer, std::move(problems));
  progress.finish();
  if (result.status == pipeline::PipelineStatus::invalid_input) {
    std::cerr << as_options(result.problems).to_string();
    return k_exit_invalid_input;
  }
  if (!a.quiet) std::cout << result.outputs.text;
  if (!result.write_error.empty()) std::cerr << result.write_error << "\n";
  if (!result.message.empty()) std::cerr << result.message << "\n";
  if (result.status == pipeline::PipelineStatus::shell_failed && pipeline::runs_yarn(result.stages))
    std::cerr << "fit: the shell stage failed; no yarn fit\n";
  return result.ok() ? k_exit_ok : k_exit_internal;
}

}  // namespace yarnfit::cli
