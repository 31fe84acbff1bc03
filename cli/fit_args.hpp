#pragma once
// The fit options of `yarnfit fit`, `shell fit`, `yarn fit` and `batch`, bound straight to the
// fields of one pipeline::FitRequest (pipeline/fit_request.hpp), so that a batch fits every
// fabric exactly as `fit` would; the library names every value it cannot use.

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "pipeline/fit_request.hpp"
#include "pipeline/plan.hpp"

namespace yarnfit::cli {

// --shell-model thesis|stiffening (`shell fit`, `fit`, `batch`).
void add_shell_model_option(CLI::App& cmd, std::string& model);
// --fab-held-out (pipeline::FitRequest::fab_held_out).
void add_fab_held_out_option(CLI::App& cmd, std::vector<std::string>& tests);

// --export u3m,arcsim,table (`fit`, `batch`): the formats written beside the fit's outputs.
void add_export_option(CLI::App& cmd, std::vector<std::string>& formats);

// The settings options: swarm, local step, samples, seed, compression nodes, ablations, the
// profile (not the shell stage's --mesh, the fabric, the output folder, --threads,
// --start, --quiet or --force, which differ between the commands).
void add_fit_setting_options(CLI::App& cmd, pipeline::FitRequest& request);

// A fit command's arguments: the request its options bind to, and the terminal's.
struct FitArgs {
  pipeline::FitRequest request;
  bool quiet = false;
  bool no_report = false;  // `fit`: no report/ folder
};

// `fit`, `shell fit` and `yarn fit`: the plan of the request with its progress on the
// terminal, then the refusal (every problem, named by option: exit 2), the outputs' text
// unless quiet, and the failure (exit 1).
int run_fit_command(FitArgs a);

}  // namespace yarnfit::cli
