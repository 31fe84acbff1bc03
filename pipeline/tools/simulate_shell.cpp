#include "pipeline/tools/simulate_shell.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

#include "fabrics_db/records/fabric.hpp"
#include "fabrics_db/text_util.hpp"
#include "numerics/util/error.hpp"
#include "shell_fit/scenes/scene_json.hpp"

namespace yarnfit::pipeline {
namespace {

using db::format_g;
using nlohmann::json;

json null_or(const std::optional<double>& v) { return v ? json(*v) : json(nullptr); }

// The parameters of the file into the values not given.
ShellSceneRequest with_params_file(const ShellSimRequest& r, db::Problems& problems) {
  ShellSceneRequest values = r.values;
  if (r.params_file.empty()) return values;
  const auto read = shell::read_shell_params(r.params_file, problems);
  const auto targets = parameter_values(values);
  for (std::size_t i = 0; i < read.size(); ++i) {
    const bool given = std::find(r.given_parameters.begin(), r.given_parameters.end(), k_shell_param_names[i]) !=
                       r.given_parameters.end();
    if (read[i] && !given) *targets[i] = *read[i];
  }
  return values;
}

void check_loading(const ShellSimRequest& r, db::Problems& problems) {
  if (r.scene == "pear") {
    if (r.distance_mm.empty()) problems.add_field("distance", "the pear loop needs one or more clamp distances [mm]");
    if (!r.stretch.empty()) problems.add_field("stretch", "applies to --scene stretch, not to the pear loop");
    for (double d : r.distance_mm)
      if (!(std::isfinite(d) && d >= 0.0)) problems.add_field("distance", format_g(d) + ": must be zero or positive [mm]");
    return;
  }
  if (r.stretch.empty()) problems.add_field("stretch", "the clamped stretch needs one or more stretches");
  if (!r.distance_mm.empty()) problems.add_field("distance", "applies to --scene pear, not to the clamped stretch");
  for (std::size_t i = 0; i < r.stretch.size(); ++i) {
    const double s = r.stretch[i];
    if (!(std::isfinite(s) && s > -1.0)) problems.add_field("stretch", format_g(s) + ": must be greater than -1");
    else if (i > 0 && !(s > r.stretch[i - 1]))
      problems.add_field("stretch", format_g(s) + ": stretches must increase (they are a loading path)");
  }
}

// The scene of a set-up, or the reason it cannot be made (a mesh too coarse for the swatch…).
template <class Scene, class Setup>
std::unique_ptr<Scene> make_scene(const Setup& setup, db::Problems& problems) {
  try {
    return std::make_unique<Scene>(setup);
  } catch (const Error& e) {
    problems.add_field("scene", e.what());
    return nullptr;
  }
}

void run_stretch(const ShellSimRequest& r, const shell::SyntheticShellOptions& o, db::Direction dir, ShellSimOutcome& out,
                 db::Problems& problems) {
  const shell::ClampedStretchSetup setup = shell::synthetic_stretch_setup(o, dir);
  const auto scene = make_scene<shell::ClampedStretchScene>(setup, problems);
  if (!scene) return;
  const auto run = scene->run(o.params.inplane, r.stretch);
  out.json.update(shell::stretch_run_json(setup, *scene, r.stretch, run));
  out.converged = run.ok;
}

void run_pear(const ShellSimRequest& r, const shell::SyntheticShellOptions& o, db::Direction dir, ShellSimOutcome& out,
              db::Problems& problems) {
  const shell::PearLoopSetup setup = shell::synthetic_bending_setup(o, dir);
  const auto scene = make_scene<shell::PearLoopScene>(setup, problems);
  if (!scene) return;
  std::vector<double> distances;
  for (double d_mm : r.distance_mm) {
    distances.push_back(d_mm * 1e-3);
    try {
      (void)scene->initial_state(distances.back());
    } catch (const Error& e) {
      problems.add_field("distance", format_g(d_mm) + " mm: " + e.what());
    }
  }
  if (!problems.empty()) return;
  const auto run = scene->run(o.params, distances);
  out.json.update(shell::pear_run_json(setup, *scene, o.params.bending, run));
  out.converged = run.ok;
}

}  // namespace

std::vector<double*> parameter_values(ShellSceneRequest& a) {
  return {&a.kxx, &a.kxy, &a.kyy, &a.kss, &a.kn1, &a.kn2, &a.ktheta_weft, &a.ktheta_bias, &a.ktheta_warp,
          &a.lxx, &a.bxx, &a.lyy, &a.byy, &a.lss, &a.bss, &a.axx, &a.ayy};
}

db::Problems scene_problems(const ShellSceneRequest& a, bool need_bending) {
  db::Problems problems;
  const auto say = [&](const std::string& field, double value, const std::string& what) {
    problems.add_field(field, format_g(value) + ": " + what);
  };
  const auto finite = [](double v) { return std::isfinite(v); };
  for (const auto& [name, v] : {std::pair{"kxx", a.kxx}, {"kyy", a.kyy}, {"kss", a.kss}})
    if (!(finite(v) && v > 0.0)) say(name, v, "must be positive [N/m]");
  for (const auto& [name, v] : {std::pair{"kn1", a.kn1}, {"kn2", a.kn2}})
    if (!(finite(v) && v >= 0.0)) say(name, v, "must be zero or positive [N/m]");
  for (const auto& [name, v] :
       {std::pair{"lxx", a.lxx}, {"bxx", a.bxx}, {"lyy", a.lyy}, {"byy", a.byy}, {"lss", a.lss}, {"bss", a.bss}})
    if (!(finite(v) && v >= 0.0)) say(name, v, "must be zero or positive");
  // A lateral share takes either sign (the fits search [-3, 3]: a negative one lets a narrowing
  // across the pull add to the lock-up), as the laws of shell_fit.json and ground_truth hold.
  for (const auto& [name, v] : {std::pair{"axx", a.axx}, {"ayy", a.ayy}})
    if (!finite(v)) say(name, v, "must be finite");
  if (!finite(a.kxy)) say("kxy", a.kxy, "must be finite [N/m]");
  else if (a.kxx > 0.0 && a.kyy > 0.0 && !(a.kxy * a.kxy < a.kxx * a.kyy))
    say("kxy", a.kxy, "the membrane stiffness is not positive definite (needs kxy^2 < kxx*kyy)");
  for (const auto& [name, v] :
       {std::pair{"ktheta_weft", a.ktheta_weft}, {"ktheta_bias", a.ktheta_bias}, {"ktheta_warp", a.ktheta_warp}}) {
    if (!(finite(v) && v >= 0.0)) say(name, v, "must be zero or positive [N*m]");
    else if (need_bending && !(v > 0.0)) say(name, v, "the pear loop needs a positive bending stiffness [N*m]");
  }
  if (!(finite(a.length_mm) && a.length_mm > 0.0)) say("length_mm", a.length_mm, "must be positive");
  if (!(finite(a.width_mm) && a.width_mm > 0.0)) say("width_mm", a.width_mm, "must be positive");
  if (!(finite(a.gauge_length_mm) && a.gauge_length_mm >= 0.0 && a.gauge_length_mm < a.length_mm))
    say("gauge_length_mm", a.gauge_length_mm, "must lie between 0 and the free length (0: clamps)");
  if (!(finite(a.gauge_width_mm) && a.gauge_width_mm >= 0.0 && a.gauge_width_mm <= a.width_mm))
    say("gauge_width_mm", a.gauge_width_mm, "must lie between 0 and the width (0: free edges)");
  if (need_bending && !(finite(a.areal_density_gsm) && a.areal_density_gsm > 0.0))
    say("areal_density_gsm", a.areal_density_gsm, "the pear loop hangs under gravity: must be positive");
  if (!(finite(a.mesh_mm) && a.mesh_mm > 0.0)) say("mesh", a.mesh_mm, "must be positive [mm]");
  if (!(finite(a.bend_mesh_mm) && a.bend_mesh_mm > 0.0)) say("bend_mesh", a.bend_mesh_mm, "must be positive [mm]");
  return problems;
}

shell::SyntheticShellOptions synthetic_options(const ShellSceneRequest& a) {
  shell::SyntheticShellOptions o;
  o.params.inplane = {a.kxx, a.kxy, a.kyy, a.kss, a.kn1, a.kn2, a.lxx, a.bxx, a.lyy, a.byy, a.lss, a.bss, a.axx, a.ayy};
  o.params.bending.ktheta = {a.ktheta_weft, a.ktheta_bias, a.ktheta_warp};
  o.length = a.length_mm * 1e-3;
  o.width = a.width_mm * 1e-3;
  if (a.gauge_length_mm > 0) o.gauge_length = a.gauge_length_mm * 1e-3;
  if (a.gauge_width_mm > 0) o.gauge_width = a.gauge_width_mm * 1e-3;
  o.areal_density = a.areal_density_gsm * 1e-3;
  o.target_edge = a.mesh_mm * 1e-3;
  o.refinements = a.refine;
  o.bending_target_edge = a.bend_mesh_mm * 1e-3;
  o.bending_refinements = a.bend_refine;
  return o;
}

ShellSimOutcome simulate_shell_scene(const ShellSimRequest& r, db::Problems& problems) {
  const bool pear = r.scene == "pear";
  const auto direction = db::parse_direction(r.direction);
  if (!direction) problems.add_field("direction", r.direction + ": not a direction (weft, bias, warp)");
  if (!pear && r.scene != "stretch") problems.add_field("scene", r.scene + ": not a scene (stretch or pear)");
  const ShellSceneRequest values = with_params_file(r, problems);
  check_loading(r, problems);
  problems.append(scene_problems(values, pear));
  if (!problems.empty()) return {};

  const shell::SyntheticShellOptions o = synthetic_options(values);
  ShellSimOutcome out;
  out.json["direction"] = r.direction;
  out.json["params"] = shell::params_json(o.params);
  out.json["swatch"] = {{"length_m", o.length}, {"width_m", o.width}};
  if (!pear) {
    out.json["swatch"]["gauge_length_m"] = null_or(o.gauge_length);
    out.json["swatch"]["gauge_width_m"] = null_or(o.gauge_width);
  }
  if (pear) run_pear(r, o, *direction, out, problems);
  else run_stretch(r, o, *direction, out, problems);
  if (!problems.empty()) return {};
  if (!out.converged) out.failure = out.json.value("message", std::string("a simulation did not converge"));
  return out;
}

}  // namespace yarnfit::pipeline
