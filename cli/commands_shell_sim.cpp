// yarnfit shell sim: one scene of the thin-shell model from given parameters, outputs as JSON
// (pipeline/tools/simulate_shell.hpp runs it).
#include <iostream>
#include <memory>

#include "cli/commands.hpp"
#include "cli/shell_scene_args.hpp"

namespace yarnfit::cli {
namespace {

struct SimArgs {
  pipeline::ShellSimRequest request;
  std::vector<CLI::Option*> parameter_options;
};

int run_shell_sim(SimArgs& a) {
  a.request.given_parameters = given_parameters(a.parameter_options);
  db::Problems problems;
  const auto outcome = pipeline::simulate_shell_scene(a.request, problems);
  if (!problems.empty()) return invalid_input(problems);
  std::cout << outcome.json.dump(2) << "\n";
  if (!outcome.converged) std::cerr << "shell sim: not converged: " << outcome.failure << "\n";
  return outcome.converged ? k_exit_ok : k_exit_internal;
}

}  // namespace

void add_shell_sim_command(CLI::App& shell, int& exit_code) {
  auto args = std::make_shared<SimArgs>();
  auto* sim = shell.add_subcommand(
      "sim", "Simulate one scene from given shell parameters and print its outputs as JSON: the clamped "
             "stretch test (clamp force, line force, compression at each stretch) or the pear loop (aspect "
             "ratio h/p at each clamp distance). Defaults are those of `yarnfit synth shell`. Exit 1 when a "
             "simulation does not converge (the JSON says which).");
  sim->add_option("--scene", args->request.scene, "stretch (clamped stretch test) or pear (pear-loop bending test)")
      ->check(CLI::IsMember({"stretch", "pear"}))
      ->capture_default_str();
  sim->add_option("--direction", args->request.direction, "Test direction: the pull or the strip along weft, bias or warp")
      ->check(CLI::IsMember({"weft", "bias", "warp"}))
      ->capture_default_str();
  sim->add_option("--params", args->request.params_file,
                  "A shell_fit.json (its params) or a JSON object of parameters; options given on the command "
                  "line win")
      ->check(CLI::ExistingFile);
  args->parameter_options = add_shell_parameter_options(*sim, args->request.values);
  sim->add_option("--stretch", args->request.stretch, "Stretch(es) s, increasing, comma-separated (clamped stretch)")
      ->delimiter(',');
  sim->add_option("--distance", args->request.distance_mm, "Clamp distance(s) d [mm], comma-separated (pear loop)")
      ->delimiter(',');
  add_shell_scene_options(*sim, args->request.values);
  sim->callback([args, &exit_code] { exit_code = run_shell_sim(*args); });
}

}  // namespace yarnfit::cli
