// yarnfit shell …: fit the thin-shell model to a fabric's tests and write uniform targets.
#include <iostream>
#include <memory>

#include "cli/commands.hpp"
#include "cli/fit_args.hpp"
#include "cli/option_names.hpp"

namespace yarnfit::cli {

void add_shell_commands(CLI::App& app, int& exit_code) {
  auto* shell = app.add_subcommand("shell", "Thin-shell model: fit to a fabric's tests, simulate scenes");
  shell->require_subcommand(1);
  auto args = std::make_shared<FitArgs>();
  // The shell stage's files are replaced when they exist (`fit` and `yarn fit` refuse that
  // without --force).
  args->request.stages = "shell";
  args->request.shell_threads = 2;
  args->request.overwrite = true;
  auto* fit = shell->add_subcommand(
      "fit", "Fit the in-plane shell parameters to the stretch tests by simulation in the loop; "
             "writes DIR/shell_fit.json, DIR/uniform_targets.csv and DIR/shell_curves.csv");
  pipeline::FitRequest& r = args->request;
  fit->add_option("FABRIC", r.fabric, "Fabric folder")->required();
  fit->add_option("-o,--out", r.out, "Output folder")->required();
  // Ranges are checked by the library (ShellFitOptions::problems), which names every problem.
  add_request_options(*fit, r, pipeline::RequestGroup::shell);
  add_request_options(*fit, r, pipeline::RequestGroup::shell_solve);
  fit->add_option("--threads", r.shell_threads, "Test directions simulated in parallel (1-64, default 2)");
  fit->add_flag("-q,--quiet", args->quiet, "No progress or summary");
  fit->callback([args, &exit_code] { exit_code = run_fit_command(*args); });
  add_shell_sim_command(*shell, exit_code);
}

}  // namespace yarnfit::cli
