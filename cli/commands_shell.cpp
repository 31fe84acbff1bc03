// yarnfit shell …: fit the thin-shell model to a fabric's tests and write uniform targets.
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>

#include "cli/commands.hpp"
#include "fabrics_db/records/fabric_reader.hpp"
#include "fabrics_db/text_util.hpp"
#include "shell_fit/fit/bending_fit.hpp"
#include "shell_fit/fit/inplane_fit.hpp"
#include "shell_fit/fit/shell_fit_report.hpp"
#include "shell_fit/targets/uniform_targets.hpp"

namespace yarnfit::cli {
namespace {

namespace fs = std::filesystem;

struct ShellArgs {
  std::string fabric, out;
  double mesh_mm = 5.0;
  int refine = 0;
  int threads = 2;
  int max_iterations = 60;
  bool quiet = false;
  bool full_range = false;
};

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
  if (show_progress) {
    options.progress = [](int iteration, double cost, double seconds) {
      std::fprintf(stderr, "\rshell fit: in-plane, iteration %3d, cost %.4g, %.1f s   ", iteration, cost, seconds);
      std::fflush(stderr);
    };
  }
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
    if (show_progress) {
      bopt.progress = [](int iteration, double cost, double seconds) {
        std::fprintf(stderr, "\rshell fit: bending, iteration %3d, cost %.4g, %.1f s   ", iteration, cost, seconds);
        std::fflush(stderr);
      };
    }
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

}  // namespace

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
  fit->add_option("--max-iterations", args->max_iterations, "Ceres iterations")->check(CLI::Range(1, 1000))->capture_default_str();
  fit->add_flag("--full-range", args->full_range,
                "Fit every measured point, not only up to the power range (83.3 N/m line force)");
  fit->add_flag("-q,--quiet", args->quiet, "No progress or summary");
  fit->callback([args, &exit_code] { exit_code = run_shell_fit(*args); });
}

}  // namespace yarnfit::cli
