// yarnfit shell …: fit the thin-shell model to a fabric's tests and write uniform targets.
#include <filesystem>
#include <iostream>
#include <memory>

#include "cli/commands.hpp"
#include "cli/fit_args.hpp"
#include "cli/option_names.hpp"
#include "cli/shell_scene_args.hpp"
#include "shell_fit/fit/synthetic_fabric.hpp"

namespace yarnfit::cli {
namespace {

namespace fs = std::filesystem;

struct SynthArgs {
  std::string out, id = "synthetic_shell", family = "synthetic";
  ShellSceneArgs scene;
  double weft = 0.8, bias = 0.6, warp = 0.4;  // largest stretch; ≤ 0 omits
  std::vector<std::string> bending{"weft", "bias", "warp"};  // pear-loop tests, when k_theta is given
  double noise = 0.0;
  int points = 13, bend_points = shell::SyntheticShellOptions{}.bending_points;
  unsigned seed = 1;
  bool force = false;
};

int run_synth_shell(const SynthArgs& a) {
  const bool any_ktheta = a.scene.ktheta_weft > 0 || a.scene.ktheta_bias > 0 || a.scene.ktheta_warp > 0;
  const bool with_bending = any_ktheta && !a.bending.empty();
  auto problems = check_shell_scene_args(a.scene, with_bending);
  shell::SyntheticShellOptions o = synthetic_options(a.scene);
  o.id = a.id;
  o.family = a.family;
  o.max_stretch.clear();
  if (a.weft > 0) o.max_stretch[db::Direction::weft] = a.weft;
  if (a.bias > 0) o.max_stretch[db::Direction::bias] = a.bias;
  if (a.warp > 0) o.max_stretch[db::Direction::warp] = a.warp;
  if (o.max_stretch.empty()) problems.push_back("--weft/--bias/--warp: at least one direction needs a positive stretch");
  if (with_bending) {
    for (const auto& name : a.bending) {
      const auto dir = db::parse_direction(name);
      if (!dir) problems.push_back("--bending: " + name + ": not a direction (weft, bias, warp)");
      else o.bending_directions.push_back(*dir);
    }
  }
  if (!problems.empty()) {
    for (const auto& p : problems) std::cerr << p << "\n";
    return k_exit_invalid_input;
  }
  o.noise = a.noise;
  o.seed = a.seed;
  o.points = a.points;
  o.bending_points = a.bend_points;
  const int code = exit_code_of_writing(a.out, [&] { shell::write_synthetic_shell_fabric(o, a.out, a.force); });
  if (code != k_exit_ok) return code;
  std::cout << "wrote synthetic fabric " << a.id << " to " << a.out << "\n";
  return k_exit_ok;
}

}  // namespace

void add_synth_commands(CLI::App& app, int& exit_code) {
  auto* synth = app.add_subcommand("synth", "Synthetic fabric records simulated from known parameters");
  synth->require_subcommand(1);
  auto args = std::make_shared<SynthArgs>();
  auto* sh = synth->add_subcommand(
      "shell", "Simulate clamped stretch tests (and, with k_theta, pear-loop bending tests) from shell "
               "parameters and write a fabric record with them under ground_truth");
  sh->add_option("-o,--out", args->out, "Fabric folder to write")->required();
  sh->add_option("--id", args->id, "Fabric id")->capture_default_str();
  sh->add_option("--family", args->family, "Fabric family")->capture_default_str();
  add_shell_parameter_options(*sh, args->scene);
  sh->add_option("--weft", args->weft, "Largest weft stretch (<= 0 omits the test)")->capture_default_str();
  sh->add_option("--bias", args->bias, "Largest bias stretch (<= 0 omits the test)")->capture_default_str();
  sh->add_option("--warp", args->warp, "Largest warp stretch (<= 0 omits the test)")->capture_default_str();
  sh->add_option("--bending", args->bending,
                 "Directions of the pear-loop tests, written when k_theta is given (all three must be positive)")
      ->delimiter(',')
      ->capture_default_str();
  add_shell_scene_options(*sh, args->scene);
  sh->add_option("--noise", args->noise, "Relative Gaussian noise on force, compression and aspect ratio")
      ->check(CLI::Range(0.0, 0.5));
  sh->add_option("--seed", args->seed, "Noise seed")->capture_default_str();
  sh->add_option("--points", args->points, "Points per stretch curve")->check(CLI::Range(3, 1000))->capture_default_str();
  sh->add_option("--bend-points", args->bend_points, "Clamp distances per pear-loop curve, evenly over 3-34 mm")
      ->check(CLI::Range(2, 100))
      ->capture_default_str();
  sh->add_flag("--force", args->force, "Replace an existing record in the folder");
  sh->callback([args, &exit_code] { exit_code = run_synth_shell(*args); });
}

bool write_files(const std::string& out, const std::function<void()>& write) {
  try {
    write();
    return true;
  } catch (const std::exception& e) {
    std::cerr << out << ": file: " << e.what() << "\n";
    return false;
  }
}

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
  fit->add_option("--mesh", r.mesh_mm, "Mesh cell size [mm]")->capture_default_str();
  add_shell_model_option(*fit, r.shell_model);
  add_fab_held_out_option(*fit, r.fab_held_out);
  fit->add_option("--refine", r.refinements, "Midpoint subdivisions of the mesh (0-4)")->capture_default_str();
  fit->add_option("--threads", r.shell_threads, "Test directions simulated in parallel (1-64, default 2)");
  fit->add_option("--max-iterations", r.max_iterations,
                  "Ceres iterations of the in-plane fit after its multi-start (1-1000)")
      ->capture_default_str();
  fit->add_flag("--full-range", r.full_range,
                "Fit every measured point, not only up to the power range (83.3 N/m line force)");
  fit->add_flag("-q,--quiet", args->quiet, "No progress or summary");
  fit->callback([args, &exit_code] { exit_code = run_fit_command(*args); });
  add_shell_sim_command(*shell, exit_code);
}

}  // namespace yarnfit::cli
