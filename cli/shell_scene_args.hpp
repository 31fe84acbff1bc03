#pragma once
// Command-line options shared by `yarnfit synth shell` and `yarnfit shell sim`: the shell
// parameters, the swatch, gauge marks, areal density and meshes. Both commands register them
// through these functions, so their defaults are the same and `shell sim` with default
// options runs exactly the scenes whose curves `synth shell` writes.

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "shell_fit/fit/shell_fit.hpp"
#include "shell_fit/fit/synthetic_fabric.hpp"

namespace yarnfit::cli {

struct ShellSceneArgs {
  // In-plane parameters [N/m]: a knit-like default (weft compliant, warp stiff).
  double kxx = 120, kxy = 35, kyy = 400, kss = 30, kn1 = 5, kn2 = 8;
  // k_θ weft, bias, warp [N·m]; 0: not given.
  double ktheta_weft = 0, ktheta_bias = 0, ktheta_warp = 0;
  // Lock-up of the stiffening model (l [N/m], b [-]) along weft, warp, shear; 0: eq. 6.1.
  double lxx = 0, bxx = 0, lyy = 0, byy = 0, lss = 0, bss = 0, axx = 0, ayy = 0;
  double length_mm = shell::SyntheticShellOptions{}.length * 1e3;
  double width_mm = shell::SyntheticShellOptions{}.width * 1e3;
  double gauge_length_mm = 0, gauge_width_mm = 0;  // 0: read at the clamps / free edges
  double areal_density_gsm = shell::SyntheticShellOptions{}.areal_density * 1e3;
  double mesh_mm = shell::SyntheticShellOptions{}.target_edge * 1e3;
  int refine = shell::SyntheticShellOptions{}.refinements;
  double bend_mesh_mm = shell::SyntheticShellOptions{}.bending_target_edge * 1e3;
  int bend_refine = shell::SyntheticShellOptions{}.bending_refinements;
  // The parameter options, in the order of k_shell_param_names, to tell which were given on
  // the command line.
  std::vector<CLI::Option*> parameter_options;
};

// The parameter names of shell_fit.json's `params`, in the order of parameter_options.
using shell::k_shell_param_names;

// --kxx … --kn2, --ktheta-weft/bias/warp and the lock-up --lxx … --bss, --axx, --ayy.
void add_shell_parameter_options(CLI::App& app, ShellSceneArgs& args);
// --length-mm, --width-mm, --gauge-length-mm, --gauge-width-mm, --areal-density-gsm, --mesh,
// --refine, --bend-mesh, --bend-refine.
void add_shell_scene_options(CLI::App& app, ShellSceneArgs& args);

// Pointers to the parameter values, in the order of k_shell_param_names.
std::vector<double*> shell_parameter_values(ShellSceneArgs& args);

// The problems with the values (one line each, naming the option); empty when all are usable.
// `need_bending`: the pear loop needs positive k_θ and density.
std::vector<std::string> check_shell_scene_args(const ShellSceneArgs& args, bool need_bending);

// The library's options for these arguments (parameters, swatch, gauge, density, meshes).
shell::SyntheticShellOptions synthetic_options(const ShellSceneArgs& args);

}  // namespace yarnfit::cli
