#include "cli/fit_args.hpp"

#include <iostream>

#include "cli/commands.hpp"
#include "cli/option_names.hpp"
#include "cli/progress_display.hpp"

namespace yarnfit::cli {

void add_shell_model_option(CLI::App& cmd, std::string& model) {
  cmd.add_option("--shell-model", model,
                 "In-plane shell law: stiffening (eq. 6.1 plus exponential lock-up per material direction with "
                 "lateral shares, fitted from the thesis model's fit) or thesis (eq. 6.1 alone)")
      ->capture_default_str();
}

void add_fab_held_out_option(CLI::App& cmd, std::vector<std::string>& tests) {
  cmd.add_option("--fab-held-out", tests,
                 "A FAB record's tests held out of the shell fit and predicted: exactly one of S1 and S2, and any "
                 "of the bends U1, D1, D2 but not all three; comma-separated (docs/fab.md)")
      ->delimiter(',')
      ->capture_default_str();
}

void add_export_option(CLI::App& cmd, std::vector<std::string>& formats) {
  cmd.add_option("--export", formats,
                 "Also export the fitted fabric, into DIR/exports/: u3m (<id>.u3ma, U3M 1.1), arcsim (<id>_arcsim.json, "
                 "ARCSim's material data), table (table/, CSV and JSON); comma-separated (docs/exports.md)")
      ->delimiter(',');
}

void add_fit_setting_options(CLI::App& cmd, pipeline::FitRequest& a) {
  // Values are checked by the library (pipeline::pipeline_options, YarnFitSettings::problems and
  // the options of the shell stage), so that one run names every invalid option, not only the
  // first.
  cmd.add_option("--budget", a.budget,
                 "Named search settings: quick, default or thorough (the options below override them; "
                 "bench_calibration and the report's 'What accuracy costs' show what each costs and reaches)")
      ->capture_default_str();
  cmd.add_option("--global", a.global_method,
                 "Global step: staged (R1 and kc1 first on few samples, then every parameter near that R1, the "
                 "best distinct candidates rescored on the local samples) or swarm (the thesis's: --particles x "
                 "--iterations on --samples)")
      ->capture_default_str();
  // The settings a request with no numbers of its own gets (the default budget's), for the help.
  const yarn::YarnFitSettings d = [] {
    db::Problems none;
    return pipeline::pipeline_options(pipeline::FitRequest{}, none).yarn;
  }();
  cmd.add_option("--particles", a.particles, "Swarm particles of --global swarm (default " +
                                                 std::to_string(d.particles) + ")");
  cmd.add_option("--iterations", a.iterations, "Swarm iterations of --global swarm (default " +
                                                   std::to_string(d.iterations) + ")");
  cmd.add_option("--samples", a.samples, "Stretch samples per direction in --global swarm (default " +
                                             std::to_string(d.swarm_samples) + ")");
  cmd.add_option("--local-samples", a.local_samples,
                 "Stretch samples per direction in the local step, the rescore and the final evaluation (default " +
                     std::to_string(d.local_samples) + ")");
  cmd.add_option("--starts", a.starts,
                 "Local runs of --global staged, from its best distinct candidates (default " +
                     std::to_string(d.staged.starts) + ")");
  cmd.add_option("--local-evaluations", a.local_evaluations,
                 "Budget of objective evaluations of --local implicit-filtering or cobyla, and of the Gauss-Newton "
                 "step's fallback (default " + std::to_string(d.local_evaluations) + ")");
  cmd.add_option("--local,--local-method", a.local_method,
                 "Local step: gauss-newton (the rest state held within rounds, Gauss-Newton on exact Jacobians, "
                 "relaxed again between rounds), implicit-filtering (Gauss-Newton on stencil differences) or "
                 "cobyla (the thesis's choice)")
      ->capture_default_str();
  cmd.add_option("--seed", a.seed, "Swarm seed (same seed, same result whatever --threads)")->capture_default_str();
  cmd.add_option("--compression-nodes", a.compression_nodes,
                 "Where the zero-orthogonal-stress compression is solved: 0 at every stretch sample; N >= 2 at N "
                 "samples with linear interpolation between them (2: the thesis's both ends)")
      ->capture_default_str();
  cmd.add_option("--compression-weight", a.compression_weight,
                 "Weight of the compression errors beside the stress errors in the yarn objective (1: the thesis's "
                 "eq. 6.11; 0: the stresses alone)")
      ->capture_default_str();
  cmd.add_flag("--no-swarm", a.no_swarm, "The local step alone from the middle of the bounds (ablation, Fig. 6.11)");
  cmd.add_flag("--linear-stretch", a.linear_stretch, "ks1 = ks2, eps_s = 0: no biphasic stretch (ablation, Fig. 6.16)");
  cmd.add_flag("--no-rest-shape", a.no_rest_shape, "Keep the tile's own rest shape (ablation, Fig. 6.17)");
  cmd.add_flag("--relax-period", a.relax_period,
               "Relax the tile period per candidate until its coarse stress at rest vanishes (the rest-period "
               "relaxation, after the rest shape, whose own few period chord steps leave about a tenth of that "
               "stress). Off by default: on the acrylic records with generated tiles it removed the stockinette's "
               "7.7 N/m at zero stretch but raised g on every knit tried, at 1.3-1.8x the time");
  cmd.add_flag("--no-shape", a.no_shape,
               "Keep a generated tile at its prior loop shape instead of fitting its course/wale aspect (records "
               "whose pattern is a knit without a knitting_gauge)");
  cmd.add_flag("--no-profile", a.no_profile,
               "Skip the identifiability profile (each fitted parameter moved 10 % both ways, 2 local-step "
               "evaluations per parameter)");
}

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
