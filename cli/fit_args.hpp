#pragma once
// The fit options of `yarnfit fit`, `shell fit`, `yarn fit` and `batch`, bound straight to the
// fields of one pipeline::FitRequest (pipeline/fit_request.hpp), so that a batch fits every
// fabric exactly as `fit` would; the library names every value it cannot use.

#include <CLI/CLI.hpp>

#include "cli/request_options.hpp"
#include "pipeline/fit_request.hpp"
#include "pipeline/plan.hpp"

namespace yarnfit::cli {

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
