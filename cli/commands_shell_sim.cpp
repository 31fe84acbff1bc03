// yarnfit shell sim: one scene of the thin-shell model from given parameters, outputs as JSON.
#include <cmath>
#include <fstream>
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
#include "shell_fit/fit/bending_fit.hpp"
#include "shell_fit/fit/synthetic_fabric.hpp"

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

// Reads the parameters of a shell_fit.json (its `params`, or the top level when there is no
// `params`) into the values not given on the command line.
void read_params_file(SimArgs& a, std::vector<std::string>& problems) {
  std::ifstream in(a.params_file);
  if (!in) {
    problems.push_back(a.params_file + ": file: cannot be read");
    return;
  }
  const json doc = json::parse(in, nullptr, false);
  if (doc.is_discarded() || !doc.is_object()) {
    problems.push_back(a.params_file + ": file: not a JSON object (expected shell_fit.json)");
    return;
  }
  const json& p = doc.contains("params") ? doc["params"] : doc;
  if (!p.is_object()) {
    problems.push_back(a.params_file + ": params: expected an object of parameter values");
    return;
  }
  const auto values = shell_parameter_values(a.values);
  bool any = false;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const char* name = k_shell_param_names[i];
    if (!p.contains(name) || p[name].is_null()) continue;  // null: not fitted
    any = true;
    if (!p[name].is_number()) {
      problems.push_back(a.params_file + ": params." + name + ": expected a number");
      continue;
    }
    if (a.values.parameter_options[i]->count() == 0) *values[i] = p[name].get<double>();
  }
  if (!any) problems.push_back(a.params_file + ": params: none of kxx, kxy, kyy, kss, kn1, kn2, ktheta_* found");
}

json params_json(const ShellSceneArgs& v) {
  return {{"kxx", v.kxx}, {"kxy", v.kxy}, {"kyy", v.kyy}, {"kss", v.kss}, {"kn1", v.kn1}, {"kn2", v.kn2},
          {"ktheta_weft", v.ktheta_weft}, {"ktheta_bias", v.ktheta_bias}, {"ktheta_warp", v.ktheta_warp}};
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
  out["scene"] = "stretch";
  out["effects"] = run.effects;
  out["mesh"] = {{"cell_m", setup.target_edge}, {"refinements", setup.refinements},
                 {"vertices", scene->vertex_count()}, {"triangles", scene->mesh().triangle_count()}};
  out["converged"] = run.ok;
  out["message"] = run.message;
  int iterations = 0;
  double seconds = 0.0;
  json samples = json::array();
  for (std::size_t i = 0; i < a.stretch.size(); ++i) {
    if (i < run.samples.size()) {
      const auto& s = run.samples[i];
      iterations += s.newton_iterations;
      seconds += s.seconds;
      samples.push_back({{"stretch", s.measured_stretch},
                         {"clamp_stretch", s.clamp_stretch},
                         {"force_N", s.force},
                         {"line_force_N_per_m", s.force / setup.width},
                         {"compression", s.compression},
                         {"converged", true},
                         {"newton_iterations", s.newton_iterations},
                         {"residual_N", s.residual},
                         {"seconds", s.seconds}});
    } else {
      samples.push_back({{"stretch", a.stretch[i]},
                         {"converged", false},
                         {"message", i == run.samples.size() ? run.message
                                                              : std::string("not simulated: an earlier stretch failed")}});
    }
  }
  out["samples"] = samples;
  out["newton_iterations"] = iterations;
  out["seconds"] = run.ok ? run.seconds : seconds;
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
  out["scene"] = "pear";
  out["effects"] = run.effects;
  out["areal_density_kg_per_m2"] = setup.areal_density;
  out["mesh"] = {{"cell_m", setup.target_edge}, {"refinements", setup.refinements},
                 {"vertices", scene->mesh().vertex_count()}, {"triangles", scene->mesh().triangle_count()}};
  out["governing_ktheta"] = shell::k_bending_names[scene->governing_ktheta()];
  out["effective_ktheta"] = scene->effective_ktheta(o.params.bending);
  out["bending_length_m"] = shell::bending_length(scene->effective_ktheta(o.params.bending), setup.areal_density,
                                                  setup.gravity);
  out["converged"] = run.ok;
  out["message"] = run.message;
  json samples = json::array();
  for (const auto& s : run.samples) {
    json j = {{"clamp_distance_m", s.clamp_distance},
              {"aspect_ratio", s.aspect_ratio},
              {"height_m", s.height},
              {"width_m", s.width},
              {"converged", s.converged},
              {"newton_iterations", s.newton_iterations},
              {"residual_N", s.residual},
              {"seconds", s.seconds},
              {"max_curvature_per_m", s.max_curvature}};
    if (!s.message.empty()) j["message"] = s.message;
    samples.push_back(j);
  }
  out["samples"] = samples;
  out["newton_iterations"] = run.newton_iterations;
  out["seconds"] = run.seconds;
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
  out["params"] = params_json(a.values);
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
