// Real FAB measurements end to end (issue 51's goals), printed against them:
//   the 8 cm stretch (S2) loading branches, fitted        ≤ 10 % each direction (moonshot 5 %)
//   the 2 cm stretch (S1), held out and predicted         ≤ 20 %              (moonshot 10 %)
//   the bends U1, D1, D2 after fitting k_θ from them       ≤ 20 % or ≤ 0.1 gf
//   import + shell fit of one file, 2 threads              ≤ 60 s              (moonshot 20 s)
// Each file is imported (db import-fab) and shell-fitted as `yarnfit shell fit` fits it: the
// in-plane law to S2's loading branches, k_θ to the bends, S1 held out and predicted, every
// loading branch of every cycle compared.
// Usage: bench_fab [FAB_FILE…] (default: the two public examples in tests/data/fab)
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "fabrics_db/fab/fab_import.hpp"
#include "fabrics_db/records/fabric_reader.hpp"
#include "numerics/util/clock.hpp"
#include "shell_fit/fit/shell_fit.hpp"

namespace {

namespace fs = std::filesystem;
using namespace yarnfit;

const char* verdict(bool met) { return met ? "met" : "MISSED"; }

void run_file(const fs::path& file) {
  const fs::path scratch = fs::temp_directory_path() / "yarnfit-bench-fab";
  fs::remove_all(scratch);
  fs::create_directories(scratch);
  const auto t0 = numerics::Clock::now();
  db::FabImportOptions o;
  o.input = file;
  o.output = scratch / "record";
  o.denier = 100.0;  // the shell stage does not use it
  const auto imported = db::import_fab(o);
  if (!imported.written) {
    std::printf("%s: import failed\n%s", file.string().c_str(), imported.problems.to_string().c_str());
    return;
  }
  const auto load = db::load_fabric(scratch / "record");
  shell::ShellFitOptions so;
  so.threads = 2;
  const auto fit = shell::fit_shell(*load.fabric, so);
  const double seconds = numerics::seconds_since(t0);
  const double stretch_seconds = seconds - (fit.fab ? fit.fab->seconds : 0.0);
  std::printf("\n%s (%s): %.1f s in all: import + in-plane fit %.1f s (goal <= 60 s: %s), bends and comparisons %.1f s; %s\n",
              file.filename().string().c_str(), imported.measurement->name.c_str(), seconds, stretch_seconds,
              verdict(stretch_seconds <= 60.0), fit.fab ? fit.fab->seconds : 0.0,
              fit.converged() ? "converged" : fit.failure().c_str());
  if (!fit.fab) return;
  std::printf("  %-5s %-34s %-28s %-40s %s\n", "dir", "S2 fitted: first 2 cycles / all", "S1 held out (goal <= 20 %)",
              "bends after k_theta (goal <= 20 % or 0.1 gf)", "k_theta");
  const double gf = db::k_gram_force;
  for (const auto& b : fit.fab->bends) {
    std::string s1, s2, bends;
    for (const auto& t : fit.fab->tests) {
      if (t.direction != b.direction) continue;
      const auto& e = t.error;
      char cell[96];
      if (e.test == "S2")
        std::snprintf(cell, sizeof cell, "%5.1f %% (goal 10: %s) / %4.1f %%", e.first_cycles_force_pct,
                      verdict(e.first_cycles_force_pct <= 10.0), e.force_pct);
      else if (e.test == "S1")
        std::snprintf(cell, sizeof cell, "%5.1f %% (%.2f gf) %s", e.force_pct, e.mean_abs_error / gf, verdict(e.force_pct <= 20.0));
      else
        std::snprintf(cell, sizeof cell, "%s %.0f%%/%.2fgf ", e.test.c_str(), e.force_pct, e.mean_abs_error / gf);
      (e.test == "S2" ? s2 : e.test == "S1" ? s1 : bends) += cell;
    }
    bends += verdict(b.force_pct <= 20.0 || b.mean_abs_error <= 0.1 * gf);
    std::printf("  %-5s %-34s %-28s %-40s %.3g N m (misfit x2 at %.2g, %.2g)%s (%d evaluations, %.0f s)%s\n",
                std::string(db::to_string(b.direction)).c_str(), s2.c_str(), s1.c_str(), bends.c_str(), b.ktheta,
                b.ktheta_low, b.ktheta_high, b.on_bound ? " ON BOUND" : "", b.evaluations, b.seconds,
                b.converged ? "" : (" " + b.message).c_str());
  }
  for (const auto& t : fit.fab->tests)
    std::printf("  %s %-3s cycles spread %5.1f %%, hysteresis %5.1f %%\n", std::string(db::to_string(t.direction)).c_str(),
                t.error.test.c_str(), t.cycles.spread_pct, t.cycles.hysteresis_pct);
  fs::remove_all(scratch);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<fs::path> files;
  for (int i = 1; i < argc; ++i) files.emplace_back(argv[i]);
  if (files.empty())
    for (const char* name : {"cupro_physics.json", "shirley_knit_physics.json"})
      files.push_back(fs::path(YARNFIT_SOURCE_DIR) / "tests/data/fab" / name);
  for (const auto& f : files) run_file(f);
  return 0;
}
