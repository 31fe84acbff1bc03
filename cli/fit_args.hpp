#pragma once
// The fit settings of `yarnfit yarn fit`, `yarnfit fit` and `yarnfit batch`: one set of
// options, turned into the libraries' settings in one place, so that a batch fits every
// fabric exactly as `fit` would.

#include <CLI/CLI.hpp>

#include <cstdint>
#include <optional>
#include <string>

#include "calibration/fit/yarn_calibration.hpp"
#include "fabrics_db/problems.hpp"
#include "pipeline/pipeline.hpp"

namespace yarnfit::cli {

struct YarnFitArgs {
  std::string fabric, targets, out, checkpoint, start;
  calibration::YarnFitSettings defaults;
  // The budget's settings first (budget.hpp), then every detailed option given.
  std::string budget = "default";
  std::string global_method = calibration::to_string(defaults.global_method);
  std::optional<int> particles, iterations, samples, local_samples, local_evaluations, starts;
  std::string local_method = calibration::to_string(defaults.local_method);
  std::uint64_t seed = defaults.seed;
  int threads = 0;
  int compression_nodes = defaults.local_compression_nodes;
  bool no_swarm = false, linear_stretch = false, no_rest_shape = false, relax_period = false, resume = false, no_profile = false;
  bool quiet = false, force = false;
  bool no_report = false;  // `fit` and `batch`: no report/ folder
  // `fit` and `batch`: the shell stage.
  double mesh_mm = 5.0;
  std::string shell_model = shell::to_string(shell::ShellFitOptions{}.model);
};

// --shell-model thesis|stiffening (`shell fit`, `fit`, `batch`).
void add_shell_model_option(CLI::App& cmd, std::string& model);
// The model named by --shell-model; an unknown name is a problem (and the default is kept).
shell::InplaneModel shell_model_from(const std::string& name, db::Problems& problems);

// The library's settings for these arguments; an unknown --local-method is a problem. --start
// skips the swarm (the local step refines the given parameters).
calibration::YarnFitSettings settings_from(const YarnFitArgs& a, db::Problems& problems);
// Both stages' options (`fit`, `batch`).
pipeline::PipelineOptions pipeline_options(const YarnFitArgs& a, db::Problems& problems);

// The settings options: swarm, local step, samples, seed, compression nodes, ablations, the
// profile (not the shell stage's --mesh, the fabric, the output folder, --threads,
// --start, --quiet or --force, which differ between the commands).
void add_fit_setting_options(CLI::App& cmd, YarnFitArgs& a);

}  // namespace yarnfit::cli
