// Periodic yarn simulation speed and robustness figures (one core), printed against the goals
// of issue 50 (docs/yarn-solve.md):
//   rest-shape heuristic: stockinette ≤ 0.1 s, rib ≤ 1 s
//   one equilibrium from the rest state to 30 % weft stretch: stockinette ≤ 8 ms (moonshot
//   5 ms), rib ≤ 80 ms (moonshot 40 ms)
//   the same warm-started from the 25 % solution, as it is and moved along the equilibrium's
//   own tangent dg*/ds (a first-order predictor): ≥ 5× faster than cold (moonshot 10×)
//   everything but the factorisation in a Newton iteration of that cold solve ÷ one numeric
//   factorisation of its Hessian: ≤ 1 (moonshot 0.5)
//   a 20-point free-compression stretch curve;
// with `loose`, the warm-started free-compression sweeps 0–22 % (23 points) in weft, bias and
// warp of the small woven satin (../shared/data/patterns/satin_small.pyp, the 0.1 mm yarn
// parameters) and of the stockinette and rib: every point converged, ≤ 50 iterations each;
// and, with `sweeps`, the 0–50 % free-compression curves in weft, bias and warp of the real
// stockinette and cartridge-belt rib tiles (issue 4, acceptance 5); with `slack` (not part of
// `all`), issue 37's table for satin_small and every slack reproducer
// (yarn_fit/generate/slack_tiles.hpp): the 0–22 % sweeps in three directions, points
// converged, Newton iterations per point (median ≤ 30, max ≤ 200) and the energy–stress
// consistency (median ≤ 1 %, 90th percentile ≤ 5 %).
// Usage: bench_yarn_fit [timing|loose|sweeps|slack|profile|all] [SHARED_DIR]
// (`profile`: 300 cold stockinette solves and nothing else, to run under perf)
// Parameters: default_params with ks2 = 400 N and R1 from the tile (the tests' defaults), or
// the shared 0.1 mm parameter file for the satin.
#include <omp.h>

#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "fabrics_db/tile/periodic_tile.hpp"
#include "numerics/util/clock.hpp"
#include "yarn_fit/homogenise/readouts.hpp"
#include "yarn_fit/homogenise/rest_shape.hpp"
#include "yarn_fit/generate/slack_figures.hpp"
#include "yarn_fit/generate/slack_tiles.hpp"
#include "yarn_fit/scenes/stretch_sweep.hpp"

namespace {

using namespace yarnfit;
using namespace yarnfit::yarn;

struct Prepared {
  std::string name;
  YarnParams params;
  YarnTile tile;             // after the rest-shape heuristic
  Eigen::VectorXd rest;      // relaxed state at χ = 0
  RestShapeResult rest_shape;
};

// `tile` after the rest-shape heuristic, with `params`.
Prepared prepare_tile(const std::string& name, const db::PeriodicTile& tile, const YarnParams& params) {
  Prepared p;
  p.name = name;
  p.params = params;
  YarnSystem system(make_yarn_tile(tile), p.params);
  p.rest = Eigen::VectorXd::Zero(system.dof_count());
  p.rest_shape = relax_rest_shape(system, p.rest);
  p.tile = system.tile();
  return p;
}

// The tile `name` of ../shared after the rest-shape heuristic, with the tests' default
// parameters or those of `params_file`.
Prepared prepare(const std::string& shared, const std::string& name, const std::string& params_file = "") {
  db::Problems problems;
  const auto tile = db::read_pyp(shared + "/data/patterns/" + name + ".pyp", problems);
  if (!tile) throw std::runtime_error(problems.to_string());
  if (params_file.empty()) return prepare_tile(name, *tile, default_params({400.0, db::compute_tile_facts(*tile).r_est}));
  const auto params = read_yarn_params(shared + "/" + params_file, std::nullopt, problems);
  if (!params) throw std::runtime_error(problems.to_string());
  return prepare_tile(name, *tile, *params);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

void verdict(const std::string& what, double ms, double goal_ms, double moonshot_ms = 0.0) {
  std::printf("  %-50s %9.1f ms   goal <= %g ms   %s", what.c_str(), ms, goal_ms, ms <= goal_ms ? "met" : "MISSED");
  if (moonshot_ms > 0.0) std::printf(" (moonshot <= %g ms: %s)", moonshot_ms, ms <= moonshot_ms ? "met" : "missed");
  std::printf("\n");
}

// Best time of one numeric LDLᵀ factorisation of the (projected) Hessian at g, as the Newton
// solver factorises it (lower triangle, AMD ordering analysed once beforehand) [ms].
double factorisation_ms(const YarnSystem& system, const Eigen::VectorXd& g) {
  const int n = system.dof_count();
  YarnSystem::Triplets t;
  for (int i = 0; i < n; ++i) t.emplace_back(i, i, 0.0);
  system.hessian(g, t, /*project_psd=*/true, /*lower_only=*/true);
  Eigen::SparseMatrix<double> k(n, n);
  k.setFromTriplets(t.begin(), t.end());
  const double shift = 1e-8 * k.diagonal().cwiseAbs().mean();
  for (int i = 0; i < n; ++i) k.coeffRef(i, i) += shift;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> ldlt;
  ldlt.analyzePattern(k);
  double best = 1e300;
  for (int repeat = 0; repeat < 20; ++repeat) {
    const auto start = numerics::Clock::now();
    ldlt.factorize(k);
    best = std::min(best, 1e3 * numerics::seconds_since(start));
  }
  return best;
}

void timing(const Prepared& p, double goal_ms, double moonshot_ms, double rest_goal_s) {
  const RestShapeResult& r = p.rest_shape;
  std::printf("%s (%d vertices)\n", p.name.c_str(), static_cast<int>(p.tile.reference.size()));
  std::printf("  rest-shape heuristic: %.2f s, %d rounds, %d Newton iterations, %s;\n"
              "    rest lengths moved up to %.1f %%, period stretch (%.2f, %.2f, %.2f) %%, rest stress "
              "(%.3g, %.3g) N/m (before the period stage (%.3g, %.3g))\n",
              r.seconds, r.rounds, r.newton_iterations, r.converged ? "converged" : "NOT converged",
              100 * r.max_length_change, 100 * r.period_stretch(0, 0), 100 * r.period_stretch(1, 1),
              100 * r.period_stretch(0, 1), r.rest_stress(0, 0), r.rest_stress(1, 1),
              r.stress_before_period(0, 0), r.stress_before_period(1, 1));
  std::printf("  %-50s %9.2f s    goal <= %g s    %s\n", "rest-shape heuristic", r.seconds, rest_goal_s,
              r.seconds <= rest_goal_s ? "met" : "MISSED");
  YarnSystem system(p.tile, p.params);
  const CoarseDeformation at30{0.3, 0.0, 0.0, weft_angle()};
  const CoarseDeformation at25{0.25, 0.0, 0.0, weft_angle()};
  std::vector<double> cold, warm, predicted;
  int cold_its = 0, warm_its = 0, predicted_its = 0, cold_factorisations = 0;
  Eigen::VectorXd cold_state;
  bool ok = true;
  for (int repeat = 0; repeat < 3; ++repeat) {
    Eigen::VectorXd g = p.rest;
    const Sample c = simulate_sample(system, at30, g);
    cold.push_back(c.seconds);
    cold_its = c.newton_iterations;
    cold_factorisations = c.last_solve.factorisations;
    cold_state = g;
    Eigen::VectorXd g25 = p.rest;
    const Sample s25 = simulate_sample(system, at25, g25);
    Eigen::VectorXd from25 = g25;
    const Sample w = simulate_sample(system, at30, from25);
    warm.push_back(w.seconds);
    warm_its = w.newton_iterations;
    // The predictor: the 25 % state moved by dg*/ds · 5 %, its cost (one more assembly and
    // factorisation at 25 %, four solves) counted with the solve.
    const auto start = numerics::Clock::now();
    Eigen::VectorXd moved = g25;
    const bool predicted_ok = predict_equilibrium(system, at25, at30, moved);
    const double predictor_s = numerics::seconds_since(start);
    const Sample pw = simulate_sample(system, at30, moved);
    predicted.push_back(predictor_s + pw.seconds);
    predicted_its = pw.newton_iterations;
    ok = ok && c.ok && s25.ok && w.ok && pw.ok && predicted_ok;
  }
  const double cold_ms = 1e3 * median(cold), warm_ms = 1e3 * median(warm), predicted_ms = 1e3 * median(predicted);
  verdict("rest state -> 30 % weft (" + std::to_string(cold_its) + " iterations)" + (ok ? "" : " FAILED"),
          cold_ms, goal_ms, moonshot_ms);
  const auto warm_line = [&](const std::string& what, double ms) {
    std::printf("  %-50s %9.1f ms   speed-up %.1fx (goal >= 5x, moonshot 10x)   %s\n", what.c_str(), ms, cold_ms / ms,
                cold_ms / ms >= 5.0 ? "met" : "MISSED");
  };
  warm_line("25 % -> 30 % weft, warm (" + std::to_string(warm_its) + " iterations)", warm_ms);
  warm_line("25 % -> 30 % weft, predicted (" + std::to_string(predicted_its) + " iterations)", predicted_ms);
  // The factorisation at the cold solve's end state: the matrix of its last iterations.
  const double factor_ms = factorisation_ms(system, cold_state);
  const double per_iteration = cold_ms / std::max(cold_its, 1);
  const double rest_of_iteration =
      (cold_ms - cold_factorisations * factor_ms) / std::max(cold_its, 1);
  std::printf("  %-50s %9.3f ms   of which the factorisations %.3f ms (%.2f an iteration)\n",
              "time per Newton iteration of the cold solve", per_iteration,
              cold_factorisations * factor_ms / std::max(cold_its, 1),
              static_cast<double>(cold_factorisations) / std::max(cold_its, 1));
  std::printf("  %-50s %9.3f ms   one factorisation %.3f ms: ratio %.1f (goal <= 1, moonshot 0.5)   %s\n",
              "the rest of an iteration (assembly, line search)", rest_of_iteration, factor_ms,
              rest_of_iteration / factor_ms, rest_of_iteration / factor_ms <= 1.0 ? "met" : "MISSED");
}

// `count` cold solves rest -> 30 % weft, for a profiler to look at one solve's parts without
// the rest-shape heuristic around them.
void repeated_cold_solves(const Prepared& p, int count) {
  YarnSystem system(p.tile, p.params);
  const CoarseDeformation at30{0.3, 0.0, 0.0, weft_angle()};
  int iterations = 0;
  double seconds = 0.0;
  EquilibriumResult last;
  for (int k = 0; k < count; ++k) {
    Eigen::VectorXd g = p.rest;
    const Sample s = simulate_sample(system, at30, g);
    iterations += s.newton_iterations;
    seconds += s.seconds;
    last = s.last_solve;
  }
  std::printf("%s: %d cold solves rest -> 30 %% weft, %.2f ms and %.1f Newton iterations each\n", p.name.c_str(), count,
              1e3 * seconds / count, static_cast<double>(iterations) / count);
  std::printf("  each: %d assemblies, %d factorisations, %d symbolic analyses, %d trial energies, %d contact rebuilds\n",
              last.assemblies, last.factorisations, last.analyses, last.energy_evaluations, last.contact_rebuilds);
}

// Warm-started free-compression sweep, 0–22 % in 23 points, per direction: how many points
// converge and the Newton iterations each took (goal: all, ≤ 50 each).
void loose_sweeps(const Prepared& p) {
  std::printf("%s (%d vertices), rest shape %.2f s:\n", p.name.c_str(), static_cast<int>(p.tile.reference.size()),
              p.rest_shape.seconds);
  for (const auto& [angle, direction] : {std::pair{weft_angle(), "weft"}, {bias_angle(), "bias"}, {warp_angle(), "warp"}}) {
    YarnSystem system(p.tile, p.params);
    Eigen::VectorXd g = p.rest;
    const StretchSweep sweep = sweep_stretch(system, angle, even_stretches(0.22, 23), g);
    int converged = 0, most = 0;
    std::string per_point;
    for (const Sample& s : sweep.points) {
      converged += s.ok ? 1 : 0;
      most = std::max(most, s.newton_iterations);
      per_point += " " + std::to_string(s.newton_iterations) + (s.ok ? "" : "!");
    }
    const bool met = converged == static_cast<int>(sweep.points.size()) && most <= 50;
    std::printf("  %-4s %2d of %zu converged, at most %4d iterations a point, %5d in all, %.1f s   goal: all, <= 50   %s\n"
                "       iterations per point (! = not converged):%s\n",
                direction, converged, sweep.points.size(), most, sweep.newton_iterations, sweep.seconds,
                met ? "met" : "MISSED", per_point.c_str());
  }
}

void curve(const Prepared& p, double angle, const char* direction, double max_stretch, int points,
           bool print_points) {
  YarnSystem system(p.tile, p.params);
  Eigen::VectorXd g = p.rest;
  const StretchSweep sweep = sweep_stretch(system, angle, even_stretches(max_stretch, points), g);
  std::printf("  %s %s 0-%.0f %%, %d points, free compression: %.2f s (%.0f ms per point), %d solves, "
              "%d Newton iterations, %d failed\n",
              p.name.c_str(), direction, 100 * max_stretch, points, sweep.seconds,
              1e3 * sweep.seconds / points, sweep.solves, sweep.newton_iterations, sweep.failures);
  if (!print_points) return;
  std::printf("    stretch  compression  sigma_s [N/m]   Psi [J/m^2]  solves  status\n");
  for (const Sample& s : sweep.points)
    std::printf("    %6.3f  %11.4f  %13.4f  %12.5g  %6d  %s\n", s.chi.stretch, s.chi.compression,
                s.stress_s, s.energy_density, s.solves, s.ok ? "ok" : s.message.c_str());
}


// Issue 37's table for one tile (yarn_fit/generate/slack_figures.hpp), with its per-point
// iterations.
SlackFigures slack_sweeps(const Prepared& p, bool print_points) {
  std::printf("%s (%d vertices): rest shape %.2f s, %d Newton iterations, %s\n", p.name.c_str(),
              static_cast<int>(p.tile.reference.size()), p.rest_shape.seconds, p.rest_shape.newton_iterations,
              p.rest_shape.converged ? "converged" : ("NOT converged: " + p.rest_shape.last_solve.message).c_str());
  const SlackFigures f = sweep_slack_tile(p.tile, p.params, p.rest);
  for (const SlackDirection& d : f.directions) {
    std::string per_point;
    int converged = 0, most = 0;
    for (const Sample& s : d.sweep.points) {
      converged += s.ok ? 1 : 0;
      most = std::max(most, s.newton_iterations);
      per_point += " " + std::to_string(s.newton_iterations) + (s.ok ? "" : "!");
      if (print_points && !s.ok) std::printf("       s %.2f: %s\n", s.chi.stretch, s.message.c_str());
    }
    std::printf("  %-4s %2d of %zu converged, at most %5d iterations a point, %6d in all, %.2f s\n"
                "       iterations per point (! = not converged):%s\n",
                d.direction.c_str(), converged, d.sweep.points.size(), most, d.sweep.newton_iterations,
                d.sweep.seconds, per_point.c_str());
  }
  return f;
}

void slack_table(const std::string& shared, bool print_points) {
  std::vector<std::pair<std::string, SlackFigures>> rows;
  const auto run = [&](const Prepared& p) { rows.emplace_back(p.name, slack_sweeps(p, print_points)); };
  run(prepare(shared, "satin_small", "data/yarn_params_0.1mm.yaml"));
  for (const std::string& name : slack_reproducer_names()) {
    const SlackReproducer r = make_slack_reproducer(name);
    std::printf("%s: %s\n", r.name.c_str(), r.construction.c_str());
    run(prepare_tile(r.name, r.tile, r.params));
  }
  std::printf("\nissue 37 goals (0-22 %% free-compression sweeps, weft, bias, warp; one core):\n"
              "  %-16s %9s %12s %12s %14s %9s   %s\n", "tile", "converged", "median its", "max its",
              "consistency", "90th", "verdict");
  for (const auto& [name, f] : rows) {
    std::printf("  %-16s %4d/%-4d %12.0f %12.0f %12.2f %% %7.2f %%   %s (%.1f s)\n", name.c_str(), f.converged, f.points,
                f.median_iterations(), f.max_iterations(), 100 * f.consistency_median(), 100 * f.consistency_90th(),
                f.meets() ? "met" : "MISSED", f.seconds);
  }
  std::printf("  goals: all converge; iterations per point median <= 30, max <= 200; consistency median <= 1 %%, "
              "90th <= 5 %%\n");
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "all";
  const std::string shared = argc > 2 ? argv[2] : YARNFIT_SHARED_DIR;
  if (mode != "timing" && mode != "loose" && mode != "sweeps" && mode != "slack" && mode != "all" &&
      mode != "profile") {
    std::fprintf(stderr, "usage: bench_yarn_fit [timing|loose|sweeps|slack|profile|all] [SHARED_DIR]\n");
    return 2;
  }
  omp_set_num_threads(1);
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // figures as they come, also into a file
  try {
    if (mode == "slack") {
      slack_table(shared, true);
      return 0;
    }
    const Prepared stockinette = prepare(shared, "stockinette");
    if (mode == "profile") {
      repeated_cold_solves(stockinette, 300);
      return 0;
    }
    const Prepared rib = prepare(shared, "cartridge_belt_rib");
    if (mode == "timing" || mode == "all") {
      std::printf("one core; default parameters (ks2 = 400 N, R1 from the tile)\n");
      timing(stockinette, 8.0, 5.0, 0.1);
      timing(rib, 80.0, 40.0, 1.0);
      std::printf("20-point stretch curve:\n");
      curve(stockinette, weft_angle(), "weft", 0.5, 20, false);
    }
    if (mode == "loose" || mode == "all") {
      std::printf("warm-started free-compression sweeps 0-22 %%, 23 points:\n");
      loose_sweeps(prepare(shared, "satin_small", "data/yarn_params_0.1mm.yaml"));
      loose_sweeps(stockinette);
      loose_sweeps(rib);
    }
    if (mode == "sweeps" || mode == "all") {
      std::printf("free-compression stretch curves 0-50 %% (acceptance 5):\n");
      for (const Prepared* p : {&stockinette, &rib}) {
        curve(*p, weft_angle(), "weft", 0.5, 11, true);
        curve(*p, bias_angle(), "bias", 0.5, 11, true);
        curve(*p, warp_angle(), "warp", 0.5, 11, true);
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_yarn_fit: %s\n", e.what());
    return 1;
  }
  return 0;
}
