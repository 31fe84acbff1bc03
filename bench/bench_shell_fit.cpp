// Shell-fit speed and accuracy figures (issue 3, acceptance 7), printed against the goals:
//   one clamped-stretch equilibrium at the default mesh        ≤ 50 ms
//   one pear-loop equilibrium at the default mesh              ≤ 500 ms
//   the whole in-plane fit of one acrylic swatch               ≤ 20 s
// the acrylic swatches fitted with both in-plane laws side by side, against issue 21's goal
// (mean force and mean compression error ≤ 10 % with the default law),
// and accuracy versus time for three mesh resolutions (error against a finer mesh).
// Usage: bench_shell_fit [SHARED_DIR]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "fabrics_db/records/fabric_reader.hpp"
#include "numerics/util/clock.hpp"
#include "results/metrics/error_metrics.hpp"
#include "shell_fit/fit/inplane_fit.hpp"
#include "shell_fit/scenes/clamped_stretch.hpp"
#include "shell_fit/scenes/pear_loop.hpp"

namespace {

namespace fs = std::filesystem;
using namespace yarnfit;

double seconds_of(const std::function<void()>& fn) {
  const auto t0 = numerics::Clock::now();
  fn();
  return numerics::seconds_since(t0);
}

// Median of `repeats` timings.
double median_seconds(int repeats, const std::function<void()>& fn) {
  std::vector<double> t;
  for (int i = 0; i < repeats; ++i) t.push_back(seconds_of(fn));
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

void verdict(const char* what, double measured, double goal, const char* unit, double scale) {
  std::printf("%-52s %9.3f %s   goal <= %g %s   %s\n", what, measured * scale, unit, goal * scale, unit,
              measured <= goal ? "met" : "MISSED");
}

const shell::InplaneParams k_knit{120.0, 35.0, 400.0, 30.0, 5.0, 8.0};

}  // namespace

int main(int argc, char** argv) {
  const fs::path shared = argc > 1 ? fs::path(argv[1]) : fs::path(YARNFIT_SHARED_DIR);

  // 1. One clamped-stretch equilibrium (10 × 6 cm, 5 mm cells, 30 % from rest).
  {
    const shell::ClampedStretchScene scene(shell::ClampedStretchSetup{});
    const double t = median_seconds(15, [&] { (void)scene.run(k_knit, {0.3}); });
    verdict("clamped stretch, one equilibrium (20 x 12 cells)", t, 0.05, "ms", 1e3);
  }
  // 2. One pear-loop equilibrium at the default mesh.
  {
    shell::PearLoopSetup setup;
    const shell::PearLoopScene scene(setup);
    shell::ShellParams p;
    p.inplane = k_knit;
    p.bending.ktheta = {2e-6, 2e-6, 2e-6};
    bool ok = true;
    const double t = median_seconds(5, [&] { ok = scene.run(p, {0.02}).ok && ok; });
    verdict(ok ? "pear loop, one equilibrium (d = 20 mm)" : "pear loop, one equilibrium (FAILED)", t, 0.5, "ms", 1e3);
  }
  // 3. The whole in-plane fit of one acrylic swatch, for each of the four knits and both laws
  // (issue 3's per-swatch table, issue 21's side-by-side study), with the means.
  {
    const fs::path out = fs::temp_directory_path() / "yarnfit-bench-shell";
    fs::remove_all(out);
    const std::string cmd = "python3 '" + std::string(YARNFIT_SOURCE_DIR) + "/scripts/build_acrylic_records.py' '" +
                            out.string() + "' --shared '" + shared.string() + "' >/dev/null";
    if (std::system(cmd.c_str()) == 0) {
      double worst = 0;
      std::printf("\nin-plane fit of the acrylic swatches over the power range (default mesh, 2 threads),\n"
                  "force / compression error in %% (whole record, then weft and warp):\n");
      std::printf("  %-12s %-11s %15s %15s %15s %6s %8s  %s\n", "swatch", "model", "record", "weft", "warp",
                  "iters", "seconds", "status");
      for (const shell::InplaneModel model : {shell::InplaneModel::thesis, shell::InplaneModel::stiffening}) {
        double sum_force = 0, sum_comp = 0;
        int n = 0;
        for (const char* knit : {"garter", "rib", "seed", "stockinette"}) {
          const auto load = db::load_fabric(out / (std::string("acrylic_") + knit));
          if (!load.ok()) continue;
          shell::InplaneFitOptions o;
          o.threads = 2;
          o.model = model;
          shell::InplaneFitResult r;
          const double t = seconds_of([&] { r = shell::fit_inplane(*load.fabric, o); });
          std::string split[2];
          for (const auto& d : r.directions) {
            const double f = results::shell_error_pct(d.measured_force, d.simulated_force);
            const double c = results::shell_error_pct(d.measured_compression, d.simulated_compression);
            char cell[64];
            std::snprintf(cell, sizeof cell, "%5.1f / %5.1f", f, c);
            if (d.direction == db::Direction::weft) split[0] = cell;
            if (d.direction == db::Direction::warp) split[1] = cell;
          }
          std::string on_bound;
          for (const auto& name : r.at_bounds) on_bound += (on_bound.empty() ? ", on a bound: " : " ") + name;
          std::printf("  %-12s %-11s %6.1f / %5.1f %15s %15s %6d %8.2f  %s%s\n", knit, shell::to_string(model),
                      r.stretch_force_pct, r.compression_pct, split[0].c_str(), split[1].c_str(), r.iterations, t,
                      r.converged ? "converged" : "NOT converged", on_bound.c_str());
          sum_force += r.stretch_force_pct;
          sum_comp += r.compression_pct;
          worst = std::max(worst, t);
          ++n;
        }
        if (n > 0) {
          const double mf = sum_force / n, mc = sum_comp / n;
          std::printf("  %-12s %-11s %6.1f / %5.1f   goal <= 10 / 10 %%: %s\n", "mean", shell::to_string(model), mf, mc,
                      mf <= 10.0 && mc <= 10.0 ? "met" : "MISSED");
        }
      }
      verdict("in-plane fit of one acrylic swatch (slowest)", worst, 20.0, "s", 1.0);
      fs::remove_all(out);
    } else {
      std::printf("in-plane fit: skipped (no acrylic data under %s)\n", shared.string().c_str());
    }
  }
  // 4. Accuracy versus time: clamped stretch (bias, gauge marks) at three resolutions against
  // a mesh refined once more than the finest.
  {
    std::printf("\naccuracy vs time, bias clamped stretch to s = 0.5 with gauge marks:\n");
    std::printf("  %-12s %10s %14s %18s %10s\n", "cells", "vertices", "force err %", "compression err %", "seconds");
    auto setup = [](int refinements) {
      shell::ClampedStretchSetup s;
      s.material_angle = -M_PI / 4;
      s.gauge_length = 0.07;
      s.gauge_width = 0.04;
      s.target_edge = 1e-2;
      s.refinements = refinements;
      return s;
    };
    const std::vector<double> targets{0.1, 0.2, 0.3, 0.4, 0.5};
    const auto reference = shell::ClampedStretchScene(setup(3)).run(k_knit, targets);
    for (int refinements = 0; refinements < 3; ++refinements) {
      const shell::ClampedStretchScene scene(setup(refinements));
      shell::ClampedStretchRun run;
      const double t = seconds_of([&] { run = scene.run(k_knit, targets); });
      double ef = 0, ec = 0;
      for (std::size_t i = 0; i < targets.size(); ++i) {
        ef = std::max(ef, std::abs(run.samples[i].force / reference.samples[i].force - 1));
        ec = std::max(ec, std::abs(run.samples[i].compression / reference.samples[i].compression - 1));
      }
      const int cells = 10 << refinements;
      std::printf("  %3d x %-6d %10d %14.3f %18.3f %10.3f\n", cells, cells * 6 / 10, scene.vertex_count(),
                  100 * ef, 100 * ec, t);
    }
  }
  return 0;
}
