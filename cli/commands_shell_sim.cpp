// yarnfit shell sim: one scene of the thin-shell model from given parameters, outputs as JSON.
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/shell_scene_args.hpp"
#include "fabrics_db/records/fabric.hpp"
#include "fabrics_db/text_util.hpp"
#include "shell_fit/fit/shell_fit.hpp"
#include "shell_fit/fit/synthetic_fabric.hpp"
#include "shell_fit/scenes/scene_json.hpp"

namespace yarnfit::cli {
namespace {

using nlohmann::json;

struct SimArgs {
  std::string scene = "stretch";
  std::string direction = "weft";
  std::string params_file;
  std::vector<double> stretch;      // clamped stretch: s where the test reads it
  std::vector<double> distance_mm;  // pear loop: clamp distances
  ShellSceneArgs values;
};

json null_or(const std::optional<double>& v) { return v ? json(*v) : json(nullptr); }

// The parameters of a shell_fit.json into the values not given on the command line.
void read_params_file(SimArgs& a, std::vector<std::string>& problems) {
  db::Problems found;
  const auto values = shell::read_shell_params(a.params_file, found);
  for (const auto& p : found.items()) problems.push_back(p.to_string());
  const auto targets = shell_parameter_values(a.values);
  for (std::size_t i = 0; i < values.size(); ++i)
    if (values[i] && a.values.parameter_options[i]->count() == 0) *targets[i] = *values[i];
}

int run_stretch(const SimArgs& a, const shell::SyntheticShellOptions& o, db::Direction dir, json& out) {
  const shell::ClampedStretchSetup setup = shell::synthetic_stretch_setup(o, dir);
  std::unique_ptr<shell::ClampedStretchScene> scene;
  try {
    scene = std::make_unique<shell::ClampedStretchScene>(setup);
  } catch (const std::invalid_argument& e) {
    std::cerr << "shell sim: " << e.what() << "\n";
    return k_exit_invalid_input;
  }
  const auto run = scene->run(o.params.inplane, a.stretch);
  out.update(shell::stretch_run_json(setup, *scene, a.stretch, run));
  return run.ok ? k_exit_ok : k_exit_internal;
}

int run_pear(const SimArgs& a, const shell::SyntheticShellOptions& o, db::Direction dir, json& out) {
  const shell::PearLoopSetup setup = shell::synthetic_bending_setup(o, dir);
  std::unique_ptr<shell::PearLoopScene> scene;
  try {
    scene = std::make_unique<shell::PearLoopScene>(setup);
  } catch (const std::invalid_argument& e) {
    std::cerr << "shell sim: " << e.what() << "\n";
    return k_exit_invalid_input;
  }
  std::vector<double> distances;
  bool bad = false;
  for (double d_mm : a.distance_mm) {
    distances.push_back(d_mm * 1e-3);
    try {
      (void)scene->initial_state(distances.back());
    } catch (const std::invalid_argument& e) {
      std::cerr << "--distance: " << db::format_g(d_mm) << " mm: " << e.what() << "\n";
      bad = true;
    }
  }
  if (bad) return k_exit_invalid_input;
  const auto run = scene->run(o.params, distances);
  out.update(shell::pear_run_json(setup, *scene, o.params.bending, run));
  return run.ok ? k_exit_ok : k_exit_internal;
}

int run_shell_sim(SimArgs& a) {
  std::vector<std::string> problems;
  const bool pear = a.scene == "pear";
  if (!a.params_file.empty()) read_params_file(a, problems);
  if (pear) {
    if (a.distance_mm.empty()) problems.push_back("--distance: the pear loop needs one or more clamp distances [mm]");
    if (!a.stretch.empty()) problems.push_back("--stretch: applies to --scene stretch, not to the pear loop");
    for (double d : a.distance_mm)
      if (!(std::isfinite(d) && d >= 0.0)) problems.push_back("--distance: " + db::format_g(d) + ": must be zero or positive [mm]");
  } else {
    if (a.stretch.empty()) problems.push_back("--stretch: the clamped stretch needs one or more stretches");
    if (!a.distance_mm.empty()) problems.push_back("--distance: applies to --scene pear, not to the clamped stretch");
    for (std::size_t i = 0; i < a.stretch.size(); ++i) {
      const double s = a.stretch[i];
      if (!(std::isfinite(s) && s > -1.0)) problems.push_back("--stretch: " + db::format_g(s) + ": must be greater than -1");
      else if (i > 0 && !(s > a.stretch[i - 1]))
        problems.push_back("--stretch: " + db::format_g(s) + ": stretches must increase (they are a loading path)");
    }
  }
  for (const auto& p : check_shell_scene_args(a.values, pear)) problems.push_back(p);
  if (!problems.empty()) {
    for (const auto& p : problems) std::cerr << p << "\n";
    return k_exit_invalid_input;
  }
  const db::Direction dir = *db::parse_direction(a.direction);
  const shell::SyntheticShellOptions o = synthetic_options(a.values);
  json out;
  out["direction"] = a.direction;
  out["params"] = shell::params_json(o.params);
  out["swatch"] = {{"length_m", o.length}, {"width_m", o.width}};
  if (!pear) {
    out["swatch"]["gauge_length_m"] = null_or(o.gauge_length);
    out["swatch"]["gauge_width_m"] = null_or(o.gauge_width);
  }
  const int code = pear ? run_pear(a, o, dir, out) : run_stretch(a, o, dir, out);
  if (code == k_exit_invalid_input) return code;
  std::cout << out.dump(2) << "\n";
  if (code != k_exit_ok) std::cerr << "shell sim: not converged: " << out["message"].get<std::string>() << "\n";
  return code;
}

}  // namespace

void add_shell_sim_command(CLI::App& shell, int& exit_code) {
  auto args = std::make_shared<SimArgs>();
  auto* sim = shell.add_subcommand(
      "sim", "Simulate one scene from given shell parameters and print its outputs as JSON: the clamped "
             "stretch test (clamp force, line force, compression at each stretch) or the pear loop (aspect "
             "ratio h/p at each clamp distance). Defaults are those of `yarnfit synth shell`. Exit 1 when a "
             "simulation does not converge (the JSON says which).");
  sim->add_option("--scene", args->scene, "stretch (clamped stretch test) or pear (pear-loop bending test)")
      ->check(CLI::IsMember({"stretch", "pear"}))
      ->capture_default_str();
  sim->add_option("--direction", args->direction, "Test direction: the pull or the strip along weft, bias or warp")
      ->check(CLI::IsMember({"weft", "bias", "warp"}))
      ->capture_default_str();
  sim->add_option("--params", args->params_file,
                  "A shell_fit.json (its params) or a JSON object of parameters; options given on the command "
                  "line win")
      ->check(CLI::ExistingFile);
  add_shell_parameter_options(*sim, args->values);
  sim->add_option("--stretch", args->stretch, "Stretch(es) s, increasing, comma-separated (clamped stretch)")
      ->delimiter(',');
  sim->add_option("--distance", args->distance_mm, "Clamp distance(s) d [mm], comma-separated (pear loop)")
      ->delimiter(',');
  add_shell_scene_options(*sim, args->values);
  sim->callback([args, &exit_code] { exit_code = run_shell_sim(*args); });
}

}  // namespace yarnfit::cli
