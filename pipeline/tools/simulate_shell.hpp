#pragma once
// `shell sim` as one library call, and the shell scene both it and `synth shell` describe: the
// shell parameters, the swatch, gauge marks, areal density and meshes, in the user's units.
// Both commands fill the same ShellSceneRequest, so `shell sim` with its defaults runs exactly
// the scenes whose curves `synth shell` writes (shell_fit/fit/synthetic_fabric.hpp).

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "fabrics_db/problems.hpp"
#include "shell_fit/fit/shell_fit.hpp"
#include "shell_fit/fit/synthetic_fabric.hpp"

namespace yarnfit::pipeline {

struct ShellSceneRequest {
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
};

// The parameter names of shell_fit.json's `params`, in the order of parameter_values.
using shell::k_shell_param_names;
// Pointers to the request's parameters, in the order of k_shell_param_names.
[[nodiscard]] std::vector<double*> parameter_values(ShellSceneRequest& request);

// Every value that makes no scene, named by its field ("kxx", "length_mm", "mesh"…).
// `need_bending`: the pear loop needs positive k_θ and density.
[[nodiscard]] db::Problems scene_problems(const ShellSceneRequest& request, bool need_bending);
// The library's options for the request (parameters, swatch, gauge, density, meshes).
[[nodiscard]] shell::SyntheticShellOptions synthetic_options(const ShellSceneRequest& request);

struct ShellSimRequest {
  std::string scene = "stretch";  // stretch (clamped stretch test) or pear (pear-loop test)
  std::string direction = "weft";
  std::string params_file;  // a shell_fit.json or a JSON of parameters; empty: none
  // The parameters named here keep the request's values; the file fills the others.
  std::vector<std::string> given_parameters;
  std::vector<double> stretch;      // clamped stretch: s where the test reads it, increasing
  std::vector<double> distance_mm;  // pear loop: clamp distances
  ShellSceneRequest values;
};

struct ShellSimOutcome {
  nlohmann::json json;  // direction, params, swatch and the scene's read-outs
  bool converged = false;
  std::string failure;  // why not
};

// Checks the request (problems name its fields or the parameter file) and simulates nothing
// when there is a problem; otherwise runs the scene.
[[nodiscard]] ShellSimOutcome simulate_shell_scene(const ShellSimRequest& request, db::Problems& problems);

}  // namespace yarnfit::pipeline
