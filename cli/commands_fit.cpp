// yarnfit yarn fit / yarnfit fit: the yarn-level calibration (thesis 6.5.3; SPEC §1 step 3–4,
// §5) on uniform targets, and the whole pipeline shell fit → uniform targets → yarn fit. The
// work is the libraries' (calibration/problem/yarn_fit_problem.hpp, pipeline/pipeline.hpp);
// this file turns the command line into their options, checks everything before any work,
// shows progress and writes the output folders (pipeline/outputs.hpp).
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
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "calibration/problem/generated_pattern.hpp"
#include "calibration/problem/yarn_fit_problem.hpp"
#include "cli/commands.hpp"
#include "cli/fit_args.hpp"
#include "cli/option_names.hpp"
#include "cli/progress_display.hpp"
#include "fabrics_db/records/fabric_reader.hpp"
#include "fabrics_db/targets/uniform_targets.hpp"
#include "pipeline/outputs.hpp"
#include "pipeline/pipeline.hpp"
#include "reports/report.hpp"

namespace yarnfit::cli {
namespace {

namespace fs = std::filesystem;

int refuse(const db::Problems& problems) {
  std::cerr << as_options(problems).to_string();
  return k_exit_invalid_input;
}

int run_yarn_fit(const YarnFitArgs& a) {
  db::Problems problems;
  const auto load = db::load_fabric(a.fabric);
  problems.append(load.problems);
  std::optional<calibration::YarnFitProblem> problem;
  if (load.ok()) {
    db::Fabric fabric = *load.fabric;  // a knit's tile is generated into the output folder
    if (calibration::make_generated_pattern(fabric, a.out, problems))
      problem = calibration::make_yarn_fit_problem(fabric, problems);
  }
  calibration::YarnFitSettings settings = settings_from(a, problems);
  if (problem && !a.start.empty()) calibration::read_start(*problem, a.start, a.linear_stretch, problems);
  auto targets = db::read_uniform_targets(a.targets, problems);
  if (!a.resume) problems.append(pipeline::output_problems(a.out, pipeline::yarn_output_files(), a.force));
  problems.append(settings.problems());
  if (!problems.empty() || !problem || !targets) return refuse(problems);
  problem->targets = std::move(*targets);
  problem->targets_source = a.targets;

  ProgressDisplay progress = ProgressDisplay::for_stderr(a.quiet);
  settings.progress = progress.callback("yarn fit " + problem->fabric_id);
  calibration::YarnFitResult result;
  try {
    result = calibration::fit_yarn(*problem, settings);
  } catch (const std::invalid_argument& e) {
    progress.finish();
    std::cerr << a.targets << ": " << e.what() << "\n";
    return k_exit_invalid_input;
  }
  progress.finish();
  std::string summary;
  if (!write_files(a.out, [&] { summary = pipeline::write_yarn_outputs(calibration::to_json(*problem, result, settings), a.out); }))
    return k_exit_internal;
  if (!a.quiet) {
    std::cout << "yarn fit of " << problem->fabric_id << "\n" << summary;
    std::cout << "results in " << a.out << ": yarn_fit.json, yarn_curves.csv, yarn_summary.txt\n";
  }
  if (!result.ok) {
    std::cerr << "yarn fit failed: " << result.message << "\n";
    return k_exit_internal;
  }
  return k_exit_ok;
}

// ---------------------------------------------------------------------------- fit (pipeline)

// The one-fabric report's files, under the output folder.
const std::vector<std::string>& report_files() {
  static const std::vector<std::string> files{"report/index.html", "report/fabrics.csv", "report/families.csv",
                                              "report/report.json"};
  return files;
}

// DIR/report/ from the files just written (what `yarnfit report DIR` writes).
bool write_fit_report(const YarnFitArgs& a) {
  std::vector<reports::RunOutputs> runs{reports::read_fit_folders(a.out)};
  const reports::ReportData data = reports::make_report_data(std::move(runs));
  fs::path index;
  if (!write_files(a.out, [&] { index = reports::write_report(data, fs::path(a.out) / "report"); })) return false;
  if (!a.quiet) print_report_written(data, index);
  return true;
}

int run_fit(const YarnFitArgs& a) {
  db::Problems problems;
  const auto load = db::load_fabric(a.fabric);
  problems.append(load.problems);
  pipeline::PipelineOptions options = pipeline_options(a, problems);
  options.tile_cache = a.out;  // a tile generated for a knit is kept with the outputs
  problems.append(load.ok() ? pipeline::pipeline_problems(*load.fabric, options) : options.problems());
  problems.append(pipeline::output_problems(a.out, pipeline::pipeline_output_files(), a.force));
  if (!a.no_report) problems.append(pipeline::output_problems(a.out, report_files(), a.force));
  if (!problems.empty()) return refuse(problems);

  ProgressDisplay progress = ProgressDisplay::for_stderr(a.quiet);
  options.shell.progress = progress.callback("shell fit");
  options.yarn.progress = progress.callback("yarn fit " + load.fabric->id);
  const pipeline::PipelineResult result = pipeline::run_pipeline(*load.fabric, options);
  progress.finish();
  if (result.status == pipeline::PipelineStatus::invalid_input) return refuse(result.problems);
  pipeline::PipelineOutputs written;
  if (!write_files(a.out, [&] { written = pipeline::write_pipeline_outputs(result, a.out); })) return k_exit_internal;
  if (!a.quiet) print_shell_report(pipeline::shell_fit_file(result), a.out);
  if (!a.no_report && !write_fit_report(a)) return k_exit_internal;
  if (result.status == pipeline::PipelineStatus::shell_failed) {
    std::cerr << result.message << "\n" << "fit: the shell stage failed; no yarn fit\n";
    return k_exit_internal;
  }
  if (!a.quiet && !written.summary.empty()) {
    std::cout << "\n" << written.summary;
    std::cout << "results in " << a.out
              << ": summary.txt, shell_fit.json, uniform_targets.csv, shell_curves.csv, yarn_fit.json, "
                 "yarn_curves.csv\n";
  }
  if (result.status != pipeline::PipelineStatus::ok) {
    std::cerr << result.message << "\n";
    return k_exit_internal;
  }
  return k_exit_ok;
}

// Options shared by `yarn fit` and `fit`: the fabric, the folder, the settings `batch` shares
// (cli/fit_args.hpp), threads, a start and the terminal.
void add_yarn_fit_options(CLI::App& cmd, YarnFitArgs& a) {
  cmd.add_option("FABRIC", a.fabric, "Fabric folder (needs pattern and a yarn stiffness_N)")->required();
  cmd.add_option("-o,--out", a.out, "Output folder")->required();
  add_fit_setting_options(cmd, a);
  cmd.add_option("--threads", a.threads, "OpenMP threads evaluating particles (0: OpenMP's default)")
      ->capture_default_str();
  cmd.add_option("--start", a.start,
                 "Skip the swarm and start the local step from these parameters (Y.yaml with yarn_fit.json's params "
                 "keys, or a yarn_fit.json): to refine an earlier fit");
  cmd.add_flag("-q,--quiet", a.quiet, "No progress or summary on the terminal");
  cmd.add_flag("--force", a.force, "Replace existing output files in the folder");
}

}  // namespace

void add_fit_commands(CLI::App& app, CLI::App& yarn, int& exit_code) {
  auto yargs = std::make_shared<YarnFitArgs>();
  auto* y = yarn.add_subcommand(
      "fit", "Fit the yarn parameters {ks1, eps_s, kb, R1, kc1} to uniform targets (a staged global search, "
             "then Gauss-Newton on exact Jacobians alternating with the rest-shape heuristic; --budget names the "
             "search's size); writes DIR/yarn_fit.json, yarn_curves.csv and yarn_summary.txt");
  add_yarn_fit_options(*y, *yargs);
  y->add_option("--targets", yargs->targets, "uniform_targets.csv (as `shell fit` or `synth yarn` write it)")
      ->required();
  auto* checkpoint = y->add_option("--checkpoint", yargs->checkpoint,
                                   "Fit checkpoint file (its swarm stages write FILE.<stage> beside it), written after "
                                   "every swarm iteration and local run");
  y->add_flag("--resume", yargs->resume, "Continue from --checkpoint (give the same settings: each swarm stage goes "
                                         "on with its stored particles); output files may exist")
      ->needs(checkpoint);
  y->callback([yargs, &exit_code] { exit_code = run_yarn_fit(*yargs); });

  auto fargs = std::make_shared<YarnFitArgs>();
  auto* f = app.add_subcommand(
      "fit", "The whole pipeline: shell fit (shell_fit.json, uniform_targets.csv, shell_curves.csv), then the yarn "
             "fit on its targets (yarn_fit.json, yarn_curves.csv), and DIR/summary.txt for both");
  add_yarn_fit_options(*f, *fargs);
  f->add_option("--mesh", fargs->mesh_mm, "Shell stage: mesh cell size [mm]")->capture_default_str();
  add_shell_model_option(*f, fargs->shell_model);
  f->add_flag("--no-report", fargs->no_report, "Do not write the one-fabric HTML report DIR/report/");
  f->callback([fargs, &exit_code] { exit_code = run_fit(*fargs); });
}

}  // namespace yarnfit::cli
