// Periodic yarn simulation speed and robustness figures (issue 4, acceptance 5 and 7), printed
// against the goals (one core):
//   one equilibrium from the rest state to 30 % weft stretch: stockinette ≤ 20 ms, rib ≤ 150 ms
//   the same warm-started from the 25 % solution: ≥ 3× faster than cold
//   a 20-point free-compression stretch curve; the rest-shape heuristic
// and, with `sweeps`, the 0–50 % free-compression curves in weft, bias and warp of the real
// stockinette and cartridge-belt rib tiles (acceptance 5).
// Usage: bench_yarn_fit [timing|sweeps|all] [SHARED_DIR]
// Parameters: default_params with ks2 = 400 N and R1 from the tile (the tests' defaults).
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "fabrics_db/tile/periodic_tile.hpp"
#include "yarn_fit/homogenise/readouts.hpp"
#include "yarn_fit/homogenise/rest_shape.hpp"
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

Prepared prepare(const std::string& shared, const std::string& name) {
  db::Problems problems;
  const auto tile = db::read_pyp(shared + "/data/patterns/" + name + ".pyp", problems);
  if (!tile) throw std::runtime_error(problems.to_string());
  Prepared p;
  p.name = name;
  p.params = default_params({400.0, db::compute_tile_facts(*tile).r_est});
  YarnSystem system(make_yarn_tile(*tile), p.params);
  p.rest = Eigen::VectorXd::Zero(system.dof_count());
  p.rest_shape = relax_rest_shape(system, p.rest);
  p.tile = system.tile();
  return p;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

void verdict(const std::string& what, double ms, double goal_ms) {
  std::printf("  %-50s %9.1f ms   goal <= %g ms   %s\n", what.c_str(), ms, goal_ms,
              ms <= goal_ms ? "met" : "MISSED");
}

void timing(const Prepared& p, double goal_ms) {
  const RestShapeResult& r = p.rest_shape;
  std::printf("%s (%d vertices)\n", p.name.c_str(), static_cast<int>(p.tile.reference.size()));
  std::printf("  rest-shape heuristic: %.2f s, %d rounds, %d Newton iterations, %s;\n"
              "    rest lengths moved up to %.1f %%, period stretch (%.2f, %.2f, %.2f) %%, rest stress "
              "(%.3g, %.3g) N/m (before the period stage (%.3g, %.3g))\n",
              r.seconds, r.rounds, r.newton_iterations, r.converged ? "converged" : "NOT converged",
              100 * r.max_length_change, 100 * r.period_stretch(0, 0), 100 * r.period_stretch(1, 1),
              100 * r.period_stretch(0, 1), r.rest_stress(0, 0), r.rest_stress(1, 1),
              r.stress_before_period(0, 0), r.stress_before_period(1, 1));
  YarnSystem system(p.tile, p.params);
  const CoarseDeformation at30{0.3, 0.0, 0.0, weft_angle()};
  const CoarseDeformation at25{0.25, 0.0, 0.0, weft_angle()};
  std::vector<double> cold, warm;
  int cold_its = 0, warm_its = 0;
  bool ok = true;
  for (int repeat = 0; repeat < 3; ++repeat) {
    Eigen::VectorXd g = p.rest;
    const Sample c = simulate_sample(system, at30, g);
    cold.push_back(c.seconds);
    cold_its = c.newton_iterations;
    Eigen::VectorXd g25 = p.rest;
    const Sample s25 = simulate_sample(system, at25, g25);
    const Sample w = simulate_sample(system, at30, g25);
    warm.push_back(w.seconds);
    warm_its = w.newton_iterations;
    ok = ok && c.ok && s25.ok && w.ok;
  }
  const double cold_ms = 1e3 * median(cold), warm_ms = 1e3 * median(warm);
  verdict("rest state -> 30 % weft (" + std::to_string(cold_its) + " iterations)" + (ok ? "" : " FAILED"),
          cold_ms, goal_ms);
  std::printf("  %-50s %9.1f ms   speed-up %.1fx (goal >= 3x)   %s\n",
              ("25 % -> 30 % weft, warm (" + std::to_string(warm_its) + " iterations)").c_str(), warm_ms,
              cold_ms / warm_ms, cold_ms / warm_ms >= 3.0 ? "met" : "MISSED");
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

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "all";
  const std::string shared = argc > 2 ? argv[2] : YARNFIT_SHARED_DIR;
  if (mode != "timing" && mode != "sweeps" && mode != "all") {
    std::fprintf(stderr, "usage: bench_yarn_fit [timing|sweeps|all] [SHARED_DIR]\n");
    return 2;
  }
  omp_set_num_threads(1);
  try {
    const Prepared stockinette = prepare(shared, "stockinette");
    const Prepared rib = prepare(shared, "cartridge_belt_rib");
    if (mode != "sweeps") {
      std::printf("one core; default parameters (ks2 = 400 N, R1 from the tile)\n");
      timing(stockinette, 20.0);
      timing(rib, 150.0);
      std::printf("20-point stretch curve:\n");
      curve(stockinette, weft_angle(), "weft", 0.5, 20, false);
    }
    if (mode != "timing") {
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
