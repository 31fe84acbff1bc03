#pragma once
// What a user asks of a fit, in the user's words: names and numbers as the command line, a
// batch's ledger or a service request gives them. `yarnfit fit`, `shell fit`, `yarn fit` and
// `batch` bind their options to these fields, so every front end asks the same questions and
// a fabric is fitted the same way whichever one asked. The library turns a request into a
// plan (pipeline/plan.hpp), naming every field it cannot use.
//
//   pipeline::FitRequest request{"examples/fabrics/stockinette_demo", "out/demo"};
//   request.budget = "quick";
//   db::Problems problems;  // the request's own: names it cannot use
//   const pipeline::FitPlan plan = pipeline::fit_plan(request, problems);
//   const pipeline::PipelineResult r = pipeline::run_plan(plan, {}, std::move(problems));
//   if (r.status == pipeline::PipelineStatus::invalid_input) std::cerr << r.problems.to_string();

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "yarn_fit/fit/yarn_fit.hpp"
#include "fabrics_db/problems.hpp"
#include "pipeline/pipeline.hpp"
#include "pipeline/plan.hpp"
#include "shell_fit/fit/shell_fit.hpp"

namespace yarnfit::pipeline {

struct FitRequest {
  std::filesystem::path fabric;  // the record's folder
  std::filesystem::path out;     // the output folder
  bool report = false;           // the one-fabric report out/report/
  bool overwrite = false;        // replace output files that exist
  // Which stages (stages_from_string): "all", "shell" or "yarn" (on `targets`).
  std::string stages = "all";
  // Formats to export the fit to (exports::export_format_from_string): "u3m", "arcsim", "table".
  std::vector<std::string> exports;

  // The shell stage (shell::ShellFitOptions).
  double mesh_mm = 5.0;
  int refinements = 0;
  int max_iterations = shell::ShellFitOptions{}.max_iterations;
  bool full_range = false;
  std::string shell_model = shell::to_string(shell::ShellFitOptions{}.model);
  std::vector<std::string> fab_held_out = shell::k_default_fab_held_out;  // a FAB record's tests predicted, not fitted

  // The yarn stage (yarn::YarnFitSettings): the budget's settings first
  // (yarn_fit/fit/budget.hpp), then every number given here.
  std::string budget = "default";
  std::string global_method = yarn::to_string(yarn::YarnFitSettings{}.global_method);
  std::optional<int> particles, iterations, samples, local_samples, local_evaluations, starts;
  std::string local_method = yarn::to_string(yarn::YarnFitSettings{}.local_method);
  std::uint64_t seed = yarn::YarnFitSettings{}.seed;
  int compression_nodes = yarn::YarnFitSettings{}.local_compression_nodes;
  double compression_weight = yarn::ObjectiveOptions{}.compression_weight;
  bool no_swarm = false, linear_stretch = false, no_rest_shape = false, relax_period = false, no_profile = false;
  bool no_shape = false;  // keep a generated tile's prior shape instead of fitting it
  std::filesystem::path targets;     // "yarn": the uniform targets to fit
  std::filesystem::path start;       // parameters the local step starts from; skips the swarm
  std::filesystem::path checkpoint;  // the yarn fit's checkpoint file
  bool resume = false;               // continue from `checkpoint`

  // Threads of both stages: the shell stage's test directions (≤ 0: 2) and the yarn stage's
  // OpenMP threads (0: OpenMP's default).
  int threads = 0;
  // The shell stage's test directions when given on their own (`shell fit --threads`), checked
  // as given (1–64).
  std::optional<int> shell_threads;
};

// The stages' settings for `request`; every name it cannot use is a problem (field named as
// the request's: "stages", "shell_model", "budget", "global_method", "local_method", "export"), the
// default kept in its place. The settings' own ranges are checked by PipelineOptions::problems.
[[nodiscard]] PipelineOptions pipeline_options(const FitRequest& request, db::Problems& problems);

// The plan of `request` (its options from pipeline_options; a resumed yarn fit may find its
// output files).
[[nodiscard]] FitPlan fit_plan(const FitRequest& request, db::Problems& problems);

}  // namespace yarnfit::pipeline
