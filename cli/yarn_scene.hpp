#pragma once
// Command-line options shared by `yarnfit yarn sim` and `yarnfit yarn curve`: the pattern,
// the yarn parameters and the direction, the rest-shape heuristic (6.5.2) and solver limits
// (pipeline/tools/simulate_yarn.hpp's YarnSceneRequest).

#include <CLI/CLI.hpp>

#include "pipeline/tools/simulate_yarn.hpp"

namespace yarnfit::cli {

// --pattern, --params, --direction, --ks2, --rest-shape/--no-rest-shape, --rest-rounds,
// --max-iterations, --stress-tolerance, --compression-method, --threads.
void add_yarn_scene_options(CLI::App& app, pipeline::YarnSceneRequest& scene);

}  // namespace yarnfit::cli
