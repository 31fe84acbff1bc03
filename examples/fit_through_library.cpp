// Fitting a fabric through the library, without the command line: the whole pipeline (shell
// fit → uniform targets in memory → yarn fit) on one fabric record as a plan (pipeline/plan.hpp,
// the one way every front end runs a fit), its errors printed, and optionally the output
// folder `yarnfit fit` would write.
//
//   yarnfit_fit_through_library [FABRIC_FOLDER [OUT_DIR]]
//
// FABRIC_FOLDER defaults to the bundled example (examples/fabrics/stockinette_demo). The yarn
// fit runs with a tiny swarm so that the program ends in well under a minute; its errors are
// those of a rough fit (the README's example runs the quick and default budgets).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "yarn_fit/fit/budget.hpp"
#include "pipeline/plan.hpp"

#ifndef YARNFIT_SOURCE_DIR
#define YARNFIT_SOURCE_DIR "."
#endif

namespace {

// "12.3 %", or why there is no figure.
std::string pct(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g %%", v);
  return std::isfinite(v) ? text : "none";
}

}  // namespace

int main(int argc, char** argv) {
  using namespace yarnfit;
  const std::filesystem::path fabric =
      argc > 1 ? argv[1] : std::filesystem::path(YARNFIT_SOURCE_DIR) / "examples/fabrics/stockinette_demo";

  // No output folder: the plan writes nothing, and the result holds the stages' results.
  pipeline::FitPlan plan;
  plan.fabric = fabric;
  if (argc > 2) plan.out = argv[2];
  pipeline::PipelineOptions& options = plan.options;
  options.shell.threads = 2;
  // The smallest named search (budget.hpp), smaller still: the default budget is the one to trust.
  yarn::apply_budget(yarn::Budget::quick, options.yarn);
  options.yarn.staged.contact = {4, 2, 3, 6};
  options.yarn.staged.all = {4, 2, 3, 6};
  options.yarn.local_samples = 4;
  options.yarn.alternation.max_rounds = 2;
  options.yarn.threads = 2;

  // Everything that could refuse the run is checked before any simulation (pipeline::check_plan
  // lists the same problems without running anything).
  const pipeline::PipelineResult result = pipeline::run_plan(plan);
  if (result.status == pipeline::PipelineStatus::invalid_input) {
    std::cerr << result.problems.to_string();
    return 2;
  }
  const auto& shell = result.shell->inplane;
  std::cout << "fabric " << result.fabric_id << "\n"
            << "shell errors: force " << pct(shell.stretch_force_pct) << ", compression " << pct(shell.compression_pct)
            << ", aspect ratio " << pct(result.shell->bending ? result.shell->bending->bending_pct : NAN) << "\n";
  if (result.yarn) {
    for (const auto& d : result.yarn->final.directions)
      std::cout << "yarn errors (" << yarnfit::db::to_string(d.scale.direction) << "): stress comfort "
                << pct(d.stress_comfort_pct) << ", stress full " << pct(d.stress_full_pct) << ", compression "
                << pct(d.compression_pct) << "\n";
  }
  std::cout << "time: shell " << result.seconds_shell << " s, yarn " << result.seconds_yarn << " s\n";
  if (argc > 2) std::cout << "wrote " << result.outputs.files.size() << " files to " << argv[2] << "\n";
  if (!result.write_error.empty()) {
    std::cerr << result.write_error << "\n";
    return 1;
  }
  if (result.status != pipeline::PipelineStatus::ok) {
    std::cerr << result.message << "\n";
    return 1;
  }
  return 0;
}
