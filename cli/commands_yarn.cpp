// yarnfit yarn …: periodic yarn-level simulation of a knit tile under a uniform coarse
// deformation (SPEC §3 "Yarn", §5): one sample as JSON (`yarn sim`) or a stretch curve with
// free compression as CSV (`yarn curve`); pipeline/tools/simulate_yarn.hpp runs both.
//
// Conventions. --stretch is s = l/l̄ − 1 and --compression c = 1 − w/w̄ (SPEC §2, the
// library's CoarseDeformation). By default the tile first goes through the rest-shape
// heuristic (6.5.2), as the yarn fit simulates it, so the response starts near zero stress;
// --no-rest-shape simulates the rest lengths and curvatures of the pyp file. `seconds` and
// `newton_iterations` count the solves of the sample itself (with the compression search and
// the bending stencil); the rest shape is reported on its own, and `total_seconds` holds
// everything. A solve that does not converge is a status, not an error: the JSON (or CSV row)
// is still written with converged false and the reason, and the exit code is 1; invalid input
// exits 2 before anything is simulated.
#include <iostream>
#include <memory>

#include "cli/commands.hpp"
#include "cli/progress_display.hpp"
#include "cli/yarn_scene.hpp"

namespace yarnfit::cli {
namespace {

struct YarnSimArgs {
  pipeline::YarnSimRequest request;
  double curvature = 0.0;
  bool json = false;
  bool quiet = false;
  CLI::Option* curvature_option = nullptr;
};

int run_yarn_sim(YarnSimArgs& a) {
  if (a.curvature_option->count() > 0) a.request.curvature = a.curvature;
  db::Problems problems;
  ProgressDisplay progress = ProgressDisplay::for_stderr(a.quiet);
  const auto outcome = pipeline::simulate_yarn_sample(a.request, problems, progress.callback("yarn sim"));
  progress.finish();
  if (!problems.empty()) return invalid_input(problems);
  if (a.json) std::cout << outcome.json.dump(2) << "\n";
  else if (!a.quiet) std::cout << outcome.summary;
  if (!outcome.converged) std::cerr << "yarn sim: not converged: " << outcome.failure << "\n";
  if (!outcome.dump_failure.empty()) std::cerr << outcome.dump_failure << "\n";
  return outcome.converged && outcome.dump_failure.empty() ? k_exit_ok : k_exit_internal;
}

struct YarnCurveArgs {
  pipeline::YarnCurveRequest request;
  bool quiet = false;
};

int run_yarn_curve(const YarnCurveArgs& a) {
  db::Problems problems;
  ProgressDisplay progress = ProgressDisplay::for_stderr(a.quiet);
  pipeline::YarnCurveOutcome outcome;
  const bool written = write_files(a.request.out, [&] {
    outcome = pipeline::sweep_yarn_stretch(a.request, problems,
                                           progress.callback("yarn curve " + a.request.scene.setup.direction));
  });
  progress.finish();
  if (!problems.empty()) return invalid_input(problems);
  if (!written) return k_exit_internal;
  if (!a.quiet) std::cout << outcome.summary;
  for (const auto& failure : outcome.failures) std::cerr << "yarn curve: " << failure << "\n";
  return outcome.ok ? k_exit_ok : k_exit_internal;
}

}  // namespace

void add_yarn_commands(CLI::App& app, int& exit_code) {
  auto* yarn = app.add_subcommand("yarn", "Yarn-level model: periodic tile simulations under uniform deformations");
  yarn->require_subcommand(1);

  auto sim_args = std::make_shared<YarnSimArgs>();
  auto* sim = yarn->add_subcommand(
      "sim", "Simulate the periodic tile under a uniform coarse deformation (stretch s along the direction, "
             "compression c across it, curvature along it) and print the homogenised energy density and "
             "stresses. JSON: energy_density [J/m^2], stress_s and stress_c (dPsi/ds, dPsi/dc) [N/m], "
             "compression, converged, termination (converged, or converged_readout when the solve ended once the "
             "coarse stress had settled), newton_iterations, solves and seconds of this sample's solves, "
             "effects, stress_kappa [N] with --curvature, rest_shape, params, tile, units. Exit 1 when a solve "
             "does not converge (the JSON says why, with converged=false).");
  add_yarn_scene_options(*sim, sim_args->request.scene);
  sim->add_option("--stretch", sim_args->request.stretch, "Stretch s = l/l0 - 1 along the direction (0.3 = 30 %)")->required();
  auto* fixed = sim->add_option("--compression", sim_args->request.compression,
                                "Fixed compression c = 1 - w/w0 across the direction (default 0)");
  sim->add_flag("--free-compression", sim_args->request.free_compression,
                "Find the compression with zero orthogonal stress (minimises Psi over c)")
      ->excludes(fixed);
  sim_args->curvature_option = sim->add_option(
      "--curvature", sim_args->curvature,
      "Curvature along the direction [1/m]; when given, stress_kappa = dPsi/dkappa is reported (central differences)");
  sim->add_flag("--json", sim_args->json, "Print the result as JSON");
  sim->add_flag("-q,--quiet", sim_args->quiet, "No progress and no summary (JSON output is still printed)");
  sim->add_option("--dump", sim_args->request.dump, "Write the simulated tile state as OBJ polylines (one per yarn)");
  sim->add_flag("--dump-neighbours", sim_args->request.dump_neighbours, "Dump the 3x3 block of periodic copies");
  sim->callback([sim_args, &exit_code] { exit_code = run_yarn_sim(*sim_args); });

  auto curve_args = std::make_shared<YarnCurveArgs>();
  auto* curve = yarn->add_subcommand(
      "curve", "Sweep the stretch from 0 to --max-stretch along one direction with free compression, each point "
               "warm-started from the previous one, and write a CSV (direction, stretch, compression, "
               "energy_density_J_per_m2, stress_s_N_per_m, converged, newton_iterations, seconds, ...). A point "
               "that fails is written with converged=0 and the sweep carries on; exit 1 then.");
  add_yarn_scene_options(*curve, curve_args->request.scene);
  curve->add_option("--max-stretch", curve_args->request.max_stretch, "Largest stretch s = l/l0 - 1")->required();
  curve->add_option("--points", curve_args->request.points, "Points, evenly spaced from 0 to the largest stretch")
      ->check(CLI::Range(2, 1000))
      ->capture_default_str();
  curve->add_option("-o,--out", curve_args->request.out, "CSV file to write (replaced if it exists)")->required();
  curve->add_option("--dump-dir", curve_args->request.dump_dir,
                    "Folder for one OBJ of the tile state per point (DIRECTION_INDEX_sSTRETCH.obj)");
  curve->add_flag("--dump-neighbours", curve_args->request.dump_neighbours, "Dump the 3x3 block of periodic copies");
  curve->add_flag("-q,--quiet", curve_args->quiet, "No progress and no summary");
  curve->callback([curve_args, &exit_code] { exit_code = run_yarn_curve(*curve_args); });
}

}  // namespace yarnfit::cli
