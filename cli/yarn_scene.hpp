#pragma once
// Command-line options shared by `yarnfit yarn sim` and `yarnfit yarn curve`: the pattern,
// the yarn parameters and the direction, the rest-shape heuristic (6.5.2) and solver limits,
// turned into the library's scene set-up (yarn_fit/scenes/yarn_scene.hpp).

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

#include "yarn_fit/scenes/yarn_scene.hpp"

namespace yarnfit::cli {

struct YarnSceneArgs {
  std::string pattern;      // pyp tile; its x axis is the weft (fabric.yaml's weft_axis: x)
  std::string params_file;  // YAML or JSON with the keys of yarn_fit.json's params
  std::string direction = "weft";
  double ks2 = 0.0;         // > 0: fills ks2, kc2, R2 the parameter file leaves out (SPEC §3)
  bool rest_shape = true;   // run the rest-shape heuristic before loading
  int rest_rounds = yarn::RestShapeOptions{}.rounds;
  int max_iterations = yarn::EquilibriumOptions{}.max_iterations;
  double stress_tolerance = yarn::EquilibriumOptions{}.stress_tolerance;  // < 0: the system's default
  std::string compression_method = "root";  // root (∂Ψ/∂c = 0) or cobyla
  int threads = 1;
  bool quiet = false;
};

// --pattern, --params, --direction, --ks2, --rest-shape/--no-rest-shape, --rest-rounds,
// --max-iterations, --compression-method, --threads, -q/--quiet.
void add_yarn_scene_options(CLI::App& app, YarnSceneArgs& args);

// The library's set-up for these arguments.
yarn::YarnSceneSetup scene_setup(const YarnSceneArgs& args);

// Reads the pattern and the parameters. Every problem is appended as one line
// `file:line: field: message` (or `--option: value: message`); empty result then.
std::optional<yarn::YarnScene> load_yarn_scene(const YarnSceneArgs& args, std::vector<std::string>& problems);

}  // namespace yarnfit::cli
