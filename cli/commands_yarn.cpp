// yarnfit yarn …: periodic yarn-level simulation of a knit tile under a uniform coarse
// deformation (SPEC §3 "Yarn", §5): one sample as JSON (`yarn sim`) or a stretch curve with
// free compression as CSV (`yarn curve`).
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
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>

#include "cli/commands.hpp"
#include "cli/progress_display.hpp"
#include "cli/yarn_scene.hpp"
#include "fabrics_db/text_util.hpp"
#include "numerics/util/clock.hpp"
#include "yarn_fit/scenes/sample_json.hpp"
#include "yarn_fit/scenes/stretch_sweep.hpp"

namespace yarnfit::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using numerics::Clock;


// Writes the optional OBJ dump; false (message on stderr) when the file cannot be written.
bool dump_obj(const std::string& file, const yarn::YarnScene& scene, const Eigen::VectorXd& g,
              const yarn::CoarseDeformation& chi, bool neighbours, bool converged, const std::string& what) {
  try {
    yarn::write_tile_obj(*scene.system, g, chi, file, neighbours ? 3 : 1,
                         what + (converged ? ", equilibrium" : ", NOT converged: the start state under this deformation"));
    return true;
  } catch (const std::exception& e) {
    std::cerr << file << ": file: " << e.what() << "\n";
    return false;
  }
}

// Places an output file named by `option` (creating its folder) before anything is simulated;
// a problem when it is a folder or its folder cannot be made.
void place_output_file(const std::string& option, const std::string& file, const std::string& kind,
                       std::vector<std::string>& problems) {
  std::error_code ec;
  if (fs::is_directory(file)) problems.push_back(option + ": " + file + ": is a folder; expected " + kind + " file name");
  else if (fs::path(file).has_parent_path()) fs::create_directories(fs::path(file).parent_path(), ec);
  if (ec) problems.push_back(option + ": " + file + ": cannot create its folder: " + ec.message());
}

// A stage of a yarn command on the progress display (no steps: the rest shape, a solve).
numerics::Progress stage_event(const std::string& stage, double seconds) {
  numerics::Progress p;
  p.stage = stage;
  p.step_name.clear();
  p.seconds = seconds;
  return p;
}

// Threads, then the rest shape (its stage shown on a terminal).
void start_run(yarn::YarnScene& scene, const YarnSceneArgs& a, const std::string& command, ProgressDisplay& progress,
               Clock::time_point start) {
  omp_set_num_threads(a.threads);
  if (a.rest_shape)
    progress.update(command, stage_event("rest shape (" + std::to_string(a.rest_rounds) + " rounds)", numerics::seconds_since(start)));
  yarn::prepare_rest_state(scene, scene_setup(a));
}

// ---------------------------------------------------------------------------------- sim

struct YarnSimArgs {
  YarnSceneArgs scene;
  double stretch = 0.0;
  double compression = 0.0;
  bool free_compression = false;
  double curvature = 0.0;
  bool json = false;
  std::string dump;
  bool dump_neighbours = false;
  CLI::Option* curvature_option = nullptr;
};

int run_yarn_sim(const YarnSimArgs& a) {
  const auto start = Clock::now();
  std::vector<std::string> problems;
  if (!(std::isfinite(a.stretch) && a.stretch > -1.0))
    problems.push_back("--stretch: " + db::format_g(a.stretch) + ": must be greater than -1 (s = l/l0 - 1)");
  if (!(std::isfinite(a.compression) && a.compression < 1.0))
    problems.push_back("--compression: " + db::format_g(a.compression) + ": must be less than 1 (c = 1 - w/w0)");
  if (!std::isfinite(a.curvature)) problems.push_back("--curvature: must be finite [1/m]");
  auto scene = load_yarn_scene(a.scene, problems);
  if (problems.empty() && !a.dump.empty()) place_output_file("--dump", a.dump, "an OBJ", problems);
  if (!problems.empty() || !scene) {
    for (const auto& p : problems) std::cerr << p << "\n";
    return k_exit_invalid_input;
  }
  const yarn::SceneSampleRequest request{a.stretch, a.compression, a.free_compression, a.curvature,
                                         a.curvature_option->count() > 0};
  ProgressDisplay progress = ProgressDisplay::for_stderr(a.scene.quiet);
  start_run(*scene, a.scene, "yarn sim", progress, start);
  progress.update("yarn sim", stage_event("equilibrium", numerics::seconds_since(start)));
  const yarn::SceneSample sample = yarn::simulate_scene_sample(*scene, request);
  progress.finish();
  const json out = yarn::sample_json(*scene, request, sample, a.scene.threads, numerics::seconds_since(start));

  bool dumped = true;
  if (!a.dump.empty()) {
    dumped = dump_obj(a.dump, *scene, sample.g, sample.state_chi(), a.dump_neighbours, sample.sample.ok,
                      "yarn sim " + a.scene.pattern + " " + a.scene.direction);
  }
  if (a.json) {
    std::cout << out.dump(2) << "\n";
  } else if (!a.scene.quiet) {
    const auto f = [](const json& v, int digits = 6) {
      return v.is_null() ? std::string("-") : db::format_g(v.get<double>(), digits);
    };
    std::cout << "yarn sim " << a.scene.pattern << ", " << a.scene.direction << ": s = " << db::format_g(a.stretch)
              << ", c = " << f(out["compression"]) << (a.free_compression ? " (free)" : " (fixed)")
              << (request.bending ? ", curvature " + db::format_g(a.curvature) + " 1/m" : std::string()) << "\n"
              << "  " << (sample.ok ? sample.termination : "NOT converged (" + sample.termination + ")") << ", "
              << sample.newton_iterations << " Newton iterations in " << sample.solves << " solve(s), "
              << db::format_g(sample.seconds, 3) << " s\n"
              << "  energy density " << f(out["energy_density"]) << " J/m^2, stress_s " << f(out["stress_s"])
              << " N/m, orthogonal stress " << f(out["stress_c"], 3) << " N/m\n";
    if (request.bending) std::cout << "  stress_kappa " << f(out["stress_kappa"]) << " N\n";
    if (scene->rest)
      std::cout << "  rest shape: " << scene->rest->rounds << " rounds, " << db::format_g(scene->rest->seconds, 3)
                << " s, largest rest-length change " << db::format_g(100 * scene->rest->max_length_change, 3)
                << " %\n";
    if (!a.dump.empty() && dumped) std::cout << "  wrote " << a.dump << "\n";
  }
  if (!sample.ok) std::cerr << "yarn sim: not converged: " << sample.message << "\n";
  if (!dumped) return k_exit_internal;
  return sample.ok ? k_exit_ok : k_exit_internal;
}

// -------------------------------------------------------------------------------- curve

struct YarnCurveArgs {
  YarnSceneArgs scene;
  double max_stretch = 0.0;
  int points = 20;
  std::string out;
  std::string dump_dir;
  bool dump_neighbours = false;
};

int run_yarn_curve(const YarnCurveArgs& a) {
  const auto start = Clock::now();
  std::vector<std::string> problems;
  if (!(std::isfinite(a.max_stretch) && a.max_stretch > 0.0))
    problems.push_back("--max-stretch: " + db::format_g(a.max_stretch) + ": must be positive (the sweep runs from 0)");
  auto scene = load_yarn_scene(a.scene, problems);
  if (problems.empty()) {
    // Fail before the simulation, not after it, when the outputs cannot be placed.
    place_output_file("--out", a.out, "a CSV", problems);
    std::error_code ec;
    if (!a.dump_dir.empty()) fs::create_directories(a.dump_dir, ec);
    if (ec) problems.push_back("--dump-dir: " + a.dump_dir + ": cannot create: " + ec.message());
  }
  if (!problems.empty() || !scene) {
    for (const auto& p : problems) std::cerr << p << "\n";
    return k_exit_invalid_input;
  }
  ProgressDisplay progress = ProgressDisplay::for_stderr(a.scene.quiet);
  start_run(*scene, a.scene, "yarn curve", progress, start);
  const std::string task = "yarn curve " + a.scene.direction;

  const std::vector<double> stretches = yarn::even_stretches(a.max_stretch, a.points);
  const int width = static_cast<int>(std::to_string(a.points - 1).size());
  bool dumps_ok = true;
  const auto sweep_start = Clock::now();
  yarn::StretchSweepOptions options;
  options.compression = scene->compression;
  options.solve = scene->solve;
  options.on_point = [&](std::size_t i, const yarn::Sample& s, const Eigen::VectorXd& g) {
    if (!a.dump_dir.empty()) {
      char name[96];
      std::snprintf(name, sizeof name, "%s_%0*zu_s%.4f.obj", a.scene.direction.c_str(), width, i, s.chi.stretch);
      dumps_ok = dump_obj((fs::path(a.dump_dir) / name).string(), *scene, g, s.chi, a.dump_neighbours, s.ok,
                          "yarn curve " + a.scene.pattern + " " + a.scene.direction) &&
                 dumps_ok;
    }
    if (!s.ok) {
      progress.finish();
      std::cerr << "yarn curve: s = " << db::format_g(s.chi.stretch) << ": not converged: " << s.message << "\n";
    }
    numerics::Progress p;
    p.step_name = "point";
    p.step = static_cast<int>(i) + 1;
    p.steps = static_cast<int>(stretches.size());
    p.detail = "s = " + db::format_g(s.chi.stretch, 4);
    p.seconds = numerics::seconds_since(sweep_start);
    progress.update(task, p);
  };
  const yarn::StretchSweep sweep = yarn::sweep_stretch(*scene->system, scene->angle, stretches, scene->g, options);
  progress.finish();
  try {
    db::write_text_file_atomically(a.out, yarn::sweep_csv(a.scene.direction, sweep));
  } catch (const std::exception& e) {
    std::cerr << a.out << ": file: " << e.what() << "\n";
    return k_exit_internal;
  }
  const bool rest_ok = !scene->rest || scene->rest->converged;
  if (!a.scene.quiet) {
    std::cout << "yarn curve " << a.scene.pattern << ", " << a.scene.direction << ", s from 0 to "
              << db::format_g(a.max_stretch) << " with free compression: " << sweep.points.size() - static_cast<std::size_t>(sweep.failures)
              << " of " << sweep.points.size() << " points converged, " << sweep.newton_iterations
              << " Newton iterations, " << db::format_g(sweep.seconds, 3) << " s";
    if (scene->rest) std::cout << " (rest shape " << db::format_g(scene->rest->seconds, 3) << " s before)";
    std::cout << "\n  " << std::setw(9) << "stretch" << std::setw(13) << "compression" << std::setw(13) << "Psi [J/m2]"
              << std::setw(15) << "sigma_s [N/m]" << std::setw(12) << "iterations" << std::setw(9) << "seconds" << "\n";
    for (const auto& s : sweep.points) {
      const auto f = [&](double v) { return s.ok ? db::format_g(v, 5) : std::string("-"); };
      std::cout << "  " << std::setw(9) << db::format_g(s.chi.stretch, 4) << std::setw(13) << f(s.chi.compression)
                << std::setw(13) << f(s.energy_density) << std::setw(15) << f(s.stress_s) << std::setw(12)
                << s.newton_iterations << std::setw(9) << db::format_g(s.seconds, 3);
      if (s.ok && s.flat)
        std::cout << "  flat in c over [" << db::format_g(s.band_lower, 4) << ", " << db::format_g(s.band_upper, 4)
                  << "]: c of smallest |c|";
      std::cout << "\n";
    }
    std::cout << "  wrote " << a.out << (a.dump_dir.empty() ? "" : " and OBJ states in " + a.dump_dir) << " ("
              << db::format_g(numerics::seconds_since(start), 3) << " s in all)\n";
  }
  if (!rest_ok)
    std::cerr << "yarn curve: rest shape not converged: " << yarn::to_string(scene->rest->last_solve.status) << ": "
              << scene->rest->last_solve.message << "\n";
  if (sweep.failures > 0) std::cerr << "yarn curve: " << sweep.failures << " point(s) did not converge (converged=0 in the CSV)\n";
  return sweep.ok() && rest_ok && dumps_ok ? k_exit_ok : k_exit_internal;
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
  add_yarn_scene_options(*sim, sim_args->scene);
  sim->add_option("--stretch", sim_args->stretch, "Stretch s = l/l0 - 1 along the direction (0.3 = 30 %)")->required();
  auto* fixed = sim->add_option("--compression", sim_args->compression,
                                "Fixed compression c = 1 - w/w0 across the direction (default 0)");
  sim->add_flag("--free-compression", sim_args->free_compression,
                "Find the compression with zero orthogonal stress (minimises Psi over c)")
      ->excludes(fixed);
  sim_args->curvature_option = sim->add_option(
      "--curvature", sim_args->curvature,
      "Curvature along the direction [1/m]; when given, stress_kappa = dPsi/dkappa is reported (central differences)");
  sim->add_flag("--json", sim_args->json, "Print the result as JSON");
  sim->add_option("--dump", sim_args->dump, "Write the simulated tile state as OBJ polylines (one per yarn)");
  sim->add_flag("--dump-neighbours", sim_args->dump_neighbours, "Dump the 3x3 block of periodic copies");
  sim->callback([sim_args, &exit_code] { exit_code = run_yarn_sim(*sim_args); });

  auto curve_args = std::make_shared<YarnCurveArgs>();
  auto* curve = yarn->add_subcommand(
      "curve", "Sweep the stretch from 0 to --max-stretch along one direction with free compression, each point "
               "warm-started from the previous one, and write a CSV (direction, stretch, compression, "
               "energy_density_J_per_m2, stress_s_N_per_m, converged, newton_iterations, seconds, ...). A point "
               "that fails is written with converged=0 and the sweep carries on; exit 1 then.");
  add_yarn_scene_options(*curve, curve_args->scene);
  curve->add_option("--max-stretch", curve_args->max_stretch, "Largest stretch s = l/l0 - 1")->required();
  curve->add_option("--points", curve_args->points, "Points, evenly spaced from 0 to the largest stretch")
      ->check(CLI::Range(2, 1000))
      ->capture_default_str();
  curve->add_option("-o,--out", curve_args->out, "CSV file to write (replaced if it exists)")->required();
  curve->add_option("--dump-dir", curve_args->dump_dir,
                    "Folder for one OBJ of the tile state per point (DIRECTION_INDEX_sSTRETCH.obj)");
  curve->add_flag("--dump-neighbours", curve_args->dump_neighbours, "Dump the 3x3 block of periodic copies");
  curve->callback([curve_args, &exit_code] { exit_code = run_yarn_curve(*curve_args); });
}

}  // namespace yarnfit::cli
