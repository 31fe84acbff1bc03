// yarnfit shell …: fit the thin-shell model to a fabric's tests and write uniform targets.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>

#include "cli/commands.hpp"
#include "cli/shell_scene_args.hpp"
#include "fabrics_db/records/fabric_reader.hpp"
#include "fabrics_db/text_util.hpp"
#include "shell_fit/fit/bending_fit.hpp"
#include "shell_fit/fit/inplane_fit.hpp"
#include "shell_fit/fit/shell_fit_report.hpp"
#include "shell_fit/fit/synthetic_fabric.hpp"
#include "shell_fit/targets/uniform_targets.hpp"

namespace yarnfit::cli {
namespace {

namespace fs = std::filesystem;

struct ShellArgs {
  std::string fabric, out;
  double mesh_mm = 5.0;
  int refine = 0;
  int threads = 2;
  int max_iterations = 100;
  bool quiet = false;
  bool full_range = false;
};

// One status line on the terminal, rewritten in place: stage, iteration, best error, time.
void show_fit_progress(const shell::FitProgress& p) {
  char error[32] = "-";
  if (std::isfinite(p.best_error_pct)) std::snprintf(error, sizeof error, "%.2f %%", p.best_error_pct);
  std::fprintf(stderr, "\r\033[Kshell fit: %s, iteration %d, best rms error %s, %.1f s", p.stage.c_str(), p.iteration,
               error, p.seconds);
  std::fflush(stderr);
}

int run_shell_fit(const ShellArgs& a) {
  const auto load = db::load_fabric(a.fabric);
  if (!load.ok()) {
    for (const auto& p : load.problems.items()) std::cerr << p.to_string() << "\n";
    return k_exit_invalid_input;
  }
  const db::Fabric& fabric = *load.fabric;
  const bool show_progress = !a.quiet && ::isatty(STDERR_FILENO);

  shell::InplaneFitOptions options;
  options.target_edge = a.mesh_mm * 1e-3;
  options.refinements = a.refine;
  options.threads = a.threads;
  options.max_iterations = a.max_iterations;
  if (a.full_range) options.max_line_force = std::numeric_limits<double>::infinity();
  if (show_progress) options.progress = show_fit_progress;
  const auto fit = shell::fit_inplane(fabric, options);
  if (show_progress) std::fprintf(stderr, "\n");

  nlohmann::json report = shell::inplane_fit_json(fit);
  report["fabric"] = fabric.id;
  report["effects"] = {{"stretch", {"membrane"}}};
  for (const char* k : {"ktheta_weft", "ktheta_bias", "ktheta_warp"}) report["params"][k] = nullptr;
  report["errors"]["bending_pct"] = nullptr;

  shell::ShellParams params;
  params.inplane = fit.params;
  shell::TargetRanges ranges;
  for (const auto& d : fit.directions) ranges.max_stretch[static_cast<std::size_t>(d.direction)] = d.max_stretch;

  // Bending (6.3.2), fitted separately with the in-plane model held, as in the thesis.
  std::optional<shell::BendingFitResult> bend;
  if (fabric.bending_tests.empty()) {
    report["not_identified"].push_back("ktheta_weft, ktheta_bias, ktheta_warp: no bending test (not fitted)");
  } else if (fit.converged) {
    shell::BendingFitOptions bopt;
    bopt.threads = a.threads;
    if (show_progress) bopt.progress = show_fit_progress;
    bend = shell::fit_bending(fabric, fit.params, bopt);
    if (show_progress) std::fprintf(stderr, "\n");
    params.bending = bend->params;
    const char* names[3] = {"ktheta_weft", "ktheta_bias", "ktheta_warp"};
    for (std::size_t k = 0; k < 3; ++k) {
      report["params"][names[k]] = bend->params.ktheta[k];
      ranges.max_curvature[k] = bend->max_curvature[k];
    }
    report["errors"]["bending_pct"] = bend->bending_pct;
    for (const auto& s : bend->identified) report["identified"].push_back(s);
    for (const auto& s : bend->not_identified) report["not_identified"].push_back(s);
    for (const auto& s : bend->at_bounds) report["at_bounds"].push_back(s);
    report["effects"]["pear_loop"] = bend->effects;
    report["bending"] = {{"converged", bend->converged}, {"message", bend->message},
                         {"iterations", bend->iterations}, {"simulations", bend->simulations},
                         {"timing_s", bend->seconds}};
    report["timing_s"] = fit.seconds + bend->seconds;
  }
  try {
    fs::create_directories(a.out);
    db::write_text_file_atomically(fs::path(a.out) / "shell_fit.json", report.dump(2) + "\n");
    shell::write_uniform_targets_csv(shell::generate_uniform_targets(params, ranges),
                                     fs::path(a.out) / "uniform_targets.csv");
  } catch (const std::exception& e) {
    std::cerr << a.out << ": file: " << e.what() << "\n";
    return k_exit_internal;
  }
  if (!a.quiet) {
    std::cout << "shell fit of " << fabric.id << ": " << (fit.converged ? "converged" : "NOT converged")
              << " after " << fit.iterations << " iterations, " << db::format_g(fit.seconds, 3) << " s\n"
              << "  force error " << db::format_g(fit.stretch_force_pct, 3) << " %, compression error "
              << (fit.compression_measured ? db::format_g(fit.compression_pct, 3) + " %" : std::string("not measured")) << "\n";
    if (fit.starts.size() > 1 && fit.chosen_start >= 0)
      std::cout << "  best of " << fit.starts.size() << " data-based starts: "
                << fit.starts[static_cast<std::size_t>(fit.chosen_start)].name
                << (fit.restarts > 0 ? ", " + std::to_string(fit.restarts) + " restart(s) after stalls" : std::string())
                << "\n";
    for (const auto& d : fit.directions)
      std::cout << "  " << db::to_string(d.direction) << ": fitted up to s = " << db::format_g(d.max_stretch, 3)
                << " of " << db::format_g(d.measured_max_stretch, 3) << " measured\n";
    for (const auto& n : fit.not_identified) std::cout << "  not identified: " << n << "\n";
    for (const auto& n : fit.weakly_identified) std::cout << "  weakly identified: " << n << "\n";
    for (const auto& b : fit.at_bounds) std::cout << "  WARNING: " << b << " ended on a search bound\n";
    if (bend) {
      std::cout << "  bending: " << (bend->converged ? "converged" : "NOT converged") << ", aspect-ratio error "
                << db::format_g(bend->bending_pct, 3) << " %, " << db::format_g(bend->seconds, 3) << " s\n";
      for (const auto& b : bend->at_bounds) std::cout << "  WARNING: " << b << " ended on a search bound\n";
    }
    std::cout << "  wrote " << (fs::path(a.out) / "shell_fit.json").string() << " and uniform_targets.csv\n";
  }
  if (!fit.converged) {
    std::cerr << "shell fit did not converge: " << fit.message << "\n";
    return k_exit_internal;
  }
  if (bend && !bend->converged) {
    std::cerr << "bending fit did not converge: " << bend->message << "\n";
    return k_exit_internal;
  }
  return k_exit_ok;
}

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
  try {
    shell::write_synthetic_shell_fabric(o, a.out, a.force);
  } catch (const std::invalid_argument& e) {
    std::cerr << a.out << ": " << e.what() << "\n";
    return k_exit_invalid_input;
  } catch (const std::exception& e) {
    std::cerr << a.out << ": " << e.what() << "\n";
    return std::string(e.what()).find("exists") != std::string::npos ? k_exit_invalid_input : k_exit_internal;
  }
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

int run_shell_fit_command(const std::string& fabric, const std::string& out, double mesh_mm, int threads,
                          bool quiet) {
  ShellArgs a;
  a.fabric = fabric;
  a.out = out;
  a.mesh_mm = mesh_mm;
  a.threads = threads;
  a.quiet = quiet;
  return run_shell_fit(a);
}

void add_shell_commands(CLI::App& app, int& exit_code) {
  auto* shell = app.add_subcommand("shell", "Thin-shell model: fit to a fabric's tests, simulate scenes");
  shell->require_subcommand(1);
  auto args = std::make_shared<ShellArgs>();
  auto* fit = shell->add_subcommand(
      "fit", "Fit the in-plane shell parameters to the stretch tests by simulation in the loop; "
             "writes DIR/shell_fit.json and DIR/uniform_targets.csv");
  fit->add_option("FABRIC", args->fabric, "Fabric folder")->required();
  fit->add_option("-o,--out", args->out, "Output folder")->required();
  fit->add_option("--mesh", args->mesh_mm, "Mesh cell size [mm]")->check(CLI::PositiveNumber)->capture_default_str();
  fit->add_option("--refine", args->refine, "Midpoint subdivisions of the mesh")->check(CLI::Range(0, 4))->capture_default_str();
  fit->add_option("--threads", args->threads, "Test directions simulated in parallel")->check(CLI::Range(1, 64))->capture_default_str();
  fit->add_option("--max-iterations", args->max_iterations, "Ceres iterations of the in-plane fit after its multi-start")->check(CLI::Range(1, 1000))->capture_default_str();
  fit->add_flag("--full-range", args->full_range,
                "Fit every measured point, not only up to the power range (83.3 N/m line force)");
  fit->add_flag("-q,--quiet", args->quiet, "No progress or summary");
  fit->callback([args, &exit_code] { exit_code = run_shell_fit(*args); });
  add_shell_sim_command(*shell, exit_code);
}

}  // namespace yarnfit::cli
