#pragma once
// Command-line options shared by `yarnfit synth shell` and `yarnfit shell sim`: the shell
// parameters, the swatch, gauge marks, areal density and meshes
// (pipeline/tools/simulate_shell.hpp's ShellSceneRequest). Both commands register them through
// these functions, so their defaults are the same and `shell sim` with default options runs
// exactly the scenes whose curves `synth shell` writes.

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "pipeline/tools/simulate_shell.hpp"

namespace yarnfit::cli {

// --kxx … --kn2, --ktheta-weft/bias/warp and the lock-up --lxx … --bss, --axx, --ayy; returns
// the options, in the order of k_shell_param_names.
std::vector<CLI::Option*> add_shell_parameter_options(CLI::App& app, pipeline::ShellSceneRequest& values);
// --length-mm, --width-mm, --gauge-length-mm, --gauge-width-mm, --areal-density-gsm, --mesh,
// --refine, --bend-mesh, --bend-refine.
void add_shell_scene_options(CLI::App& app, pipeline::ShellSceneRequest& values);
// The parameters given on the command line among `options` (add_shell_parameter_options').
[[nodiscard]] std::vector<std::string> given_parameters(const std::vector<CLI::Option*>& options);

}  // namespace yarnfit::cli
