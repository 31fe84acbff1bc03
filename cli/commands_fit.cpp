// yarnfit yarn fit / yarnfit fit: the yarn-level calibration (thesis 6.5.3; SPEC §1 step 3–4,
// §5) on uniform targets, and the whole pipeline shell fit → uniform targets → yarn fit. Each
// is a plan of the library's (pipeline/plan.hpp) that checks everything before any work and
// writes the output folder (pipeline/outputs.hpp); this file binds the options to its request,
// shows the progress and prints the outcome.
//
// Files. `yarn fit FABRIC --targets CSV --out DIR` writes DIR/yarn_fit.json, yarn_curves.csv
// and yarn_summary.txt; `fit FABRIC --out DIR` writes shell_fit.json, uniform_targets.csv,
// shell_curves.csv, yarn_fit.json, yarn_curves.csv and summary.txt.
//
// Overwriting. These commands never replace an existing output file without --force: every
// file they would write is checked before any work starts, and each one found is reported
// (exit 2). Invalid input (fabric without a pattern or a yarn stiffness, unreadable targets,
// bad settings) exits 2 with one `file: field: message` or `--option: message` line per
// problem, all of them at once; a calibration whose every candidate failed exits 1 after
// writing what it has.
#include <memory>
#include <string>

#include "cli/commands.hpp"
#include "cli/fit_args.hpp"

namespace yarnfit::cli {
namespace {

// Options shared by `yarn fit` and `fit`: the fabric, the folder, the search settings `batch`
// shares (pipeline/fit_request_fields.hpp), threads, a start and the terminal.
void add_yarn_fit_options(CLI::App& cmd, FitArgs& a) {
  pipeline::FitRequest& r = a.request;
  cmd.add_option("FABRIC", r.fabric, "Fabric folder (needs pattern and a yarn stiffness_N)")->required();
  cmd.add_option("-o,--out", r.out, "Output folder")->required();
  add_request_options(cmd, r, pipeline::RequestGroup::search);
  cmd.add_option("--threads", r.threads, "OpenMP threads evaluating particles (0: OpenMP's default)")
      ->capture_default_str();
  cmd.add_option("--start", r.start,
                 "Skip the swarm and start the local step from these parameters (Y.yaml with yarn_fit.json's params "
                 "keys, or a yarn_fit.json): to refine an earlier fit");
  cmd.add_flag("-q,--quiet", a.quiet, "No progress or summary on the terminal");
  cmd.add_flag("--force", r.overwrite, "Replace existing output files in the folder");
}

}  // namespace

void add_fit_commands(CLI::App& app, CLI::App& yarn, int& exit_code) {
  auto yargs = std::make_shared<FitArgs>();
  yargs->request.stages = "yarn";
  auto* y = yarn.add_subcommand(
      "fit", "Fit the yarn parameters {ks1, eps_s, kb, R1, kc1} to uniform targets (a staged global search, "
             "then Gauss-Newton on exact Jacobians alternating with the rest-shape heuristic; --budget names the "
             "search's size); writes DIR/yarn_fit.json, yarn_curves.csv and yarn_summary.txt");
  add_yarn_fit_options(*y, *yargs);
  y->add_option("--targets", yargs->request.targets, "uniform_targets.csv (as `shell fit` or `synth yarn` write it)")
      ->required();
  auto* checkpoint = y->add_option("--checkpoint", yargs->request.checkpoint,
                                   "Fit checkpoint file (its swarm stages write FILE.<stage> beside it), written after "
                                   "every swarm iteration and local run");
  y->add_flag("--resume", yargs->request.resume, "Continue from --checkpoint (give the same settings: each swarm stage goes "
                                         "on with its stored particles); output files may exist")
      ->needs(checkpoint);
  y->callback([yargs, &exit_code] { exit_code = run_fit_command(*yargs); });

  auto fargs = std::make_shared<FitArgs>();
  auto* f = app.add_subcommand(
      "fit", "The whole pipeline: shell fit (shell_fit.json, uniform_targets.csv, shell_curves.csv), then the yarn "
             "fit on its targets (yarn_fit.json, yarn_curves.csv), and DIR/summary.txt for both");
  add_yarn_fit_options(*f, *fargs);
  add_request_options(*f, fargs->request, pipeline::RequestGroup::shell);
  f->add_flag("--no-report", fargs->no_report, "Do not write the one-fabric HTML report DIR/report/");
  add_request_options(*f, fargs->request, pipeline::RequestGroup::outputs);
  f->callback([fargs, &exit_code] { exit_code = run_fit_command(*fargs); });
}

}  // namespace yarnfit::cli
