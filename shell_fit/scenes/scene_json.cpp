#include "shell_fit/scenes/scene_json.hpp"

#include <string>

#include "shell_fit/fit/bending_fit.hpp"

namespace yarnfit::shell {

using nlohmann::json;

json params_json(const ShellParams& p) {
  const auto& i = p.inplane;
  const auto& k = p.bending.ktheta;
  json j = {{"kxx", i.kxx}, {"kxy", i.kxy}, {"kyy", i.kyy}, {"kss", i.kss}, {"kn1", i.kn1}, {"kn2", i.kn2},
            {"ktheta_weft", k[0]}, {"ktheta_bias", k[1]}, {"ktheta_warp", k[2]}};
  // The lock-up terms only when the law has them (eq. 6.1 otherwise, as before).
  const auto v = to_array(i);
  bool lockup = false;
  for (int n = k_first_lockup_param; n < k_inplane_param_count; ++n) lockup |= v[static_cast<std::size_t>(n)] != 0.0;
  if (lockup)
    for (int n = k_first_lockup_param; n < k_inplane_param_count; ++n) j[k_inplane_param_names[n]] = v[static_cast<std::size_t>(n)];
  return j;
}

json stretch_run_json(const ClampedStretchSetup& setup, const ClampedStretchScene& scene,
                      const std::vector<double>& stretches, const ClampedStretchRun& run) {
  json out;
  out["scene"] = "stretch";
  out["effects"] = run.effects;
  out["mesh"] = {{"cell_m", setup.target_edge}, {"refinements", setup.refinements},
                 {"vertices", scene.vertex_count()}, {"triangles", scene.mesh().triangle_count()}};
  out["converged"] = run.ok;
  out["message"] = run.message;
  int iterations = 0;
  double seconds = 0.0;
  json samples = json::array();
  for (std::size_t i = 0; i < stretches.size(); ++i) {
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
      samples.push_back({{"stretch", stretches[i]},
                         {"converged", false},
                         {"message", i == run.samples.size() ? run.message
                                                              : std::string("not simulated: an earlier stretch failed")}});
    }
  }
  out["samples"] = samples;
  out["newton_iterations"] = iterations;
  out["seconds"] = run.ok ? run.seconds : seconds;
  return out;
}

json pear_run_json(const PearLoopSetup& setup, const PearLoopScene& scene, const BendingParams& bending,
                   const PearLoopRun& run) {
  json out;
  out["scene"] = "pear";
  out["effects"] = run.effects;
  out["areal_density_kg_per_m2"] = setup.areal_density;
  out["mesh"] = {{"cell_m", setup.target_edge}, {"refinements", setup.refinements},
                 {"vertices", scene.mesh().vertex_count()}, {"triangles", scene.mesh().triangle_count()}};
  out["governing_ktheta"] = k_bending_names[scene.governing_ktheta()];
  out["effective_ktheta"] = scene.effective_ktheta(bending);
  out["bending_length_m"] = bending_length(scene.effective_ktheta(bending), setup.areal_density, setup.gravity);
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
  return out;
}

}  // namespace yarnfit::shell
