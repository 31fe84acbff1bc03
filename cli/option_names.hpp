#pragma once
// The libraries name the fields of their option structs in their problems
// (shell::ShellFitOptions, yarn::YarnFitSettings, pipeline::PipelineOptions: "mesh",
// "yarn.swarm_samples"); the command line shows the option the user typed instead.

#include <string>

#include "fabrics_db/problems.hpp"

namespace yarnfit::cli {

// "--samples" for "swarm_samples" or "yarn.swarm_samples"; the field itself when no option
// sets it.
[[nodiscard]] std::string option_name(const std::string& field);

// The problems with their fields as options, each line once (two fields set by one option,
// e.g. the swarm's and the local step's compression nodes, say the same thing).
[[nodiscard]] db::Problems as_options(const db::Problems& problems);

}  // namespace yarnfit::cli
