#include "cli/shell_scene_args.hpp"

#include <cmath>

#include "fabrics_db/text_util.hpp"

namespace yarnfit::cli {

std::vector<double*> shell_parameter_values(ShellSceneArgs& a) {
  return {&a.kxx, &a.kxy, &a.kyy, &a.kss, &a.kn1, &a.kn2, &a.ktheta_weft, &a.ktheta_bias, &a.ktheta_warp,
          &a.lxx, &a.bxx, &a.lyy, &a.byy, &a.lss, &a.bss, &a.axx, &a.ayy};
}

void add_shell_parameter_options(CLI::App& app, ShellSceneArgs& a) {
  const auto values = shell_parameter_values(a);
  a.parameter_options.clear();
  for (std::size_t i = 0; i < 6; ++i) {
    a.parameter_options.push_back(app.add_option(std::string("--") + k_shell_param_names[i], *values[i],
                                                 "In-plane shell parameter [N/m]")
                                      ->capture_default_str());
  }
  const char* dirs[3] = {"weft", "bias", "warp"};
  for (std::size_t i = 0; i < 3; ++i) {
    a.parameter_options.push_back(
        app.add_option(std::string("--ktheta-") + dirs[i], *values[6 + i],
                       std::string("Bending stiffness k_theta along the ") + dirs[i] + " [N*m]; 0: none")
            ->capture_default_str());
  }
  for (std::size_t i = 9; i < values.size(); ++i) {
    const bool share = i >= 15, rate = !share && (i - 9) % 2 == 1;
    a.parameter_options.push_back(
        app.add_option(std::string("--") + k_shell_param_names[i], *values[i],
                       share  ? "Lateral share a of the weft (axx) or warp (ayy) lock-up strain [-]"
                       : rate ? "Lock-up rate b of the stiffening model [-]"
                              : "Lock-up stiffness l of the stiffening model [N/m]; 0: none")
            ->capture_default_str());
  }
}

void add_shell_scene_options(CLI::App& app, ShellSceneArgs& a) {
  app.add_option("--length-mm", a.length_mm, "Swatch free length between the clamps")->capture_default_str();
  app.add_option("--width-mm", a.width_mm, "Swatch width")->capture_default_str();
  app.add_option("--gauge-length-mm", a.gauge_length_mm, "Gauge mark spacing along the pull (0: clamps)");
  app.add_option("--gauge-width-mm", a.gauge_width_mm, "Gauge mark spacing across (0: free edges)");
  app.add_option("--areal-density-gsm", a.areal_density_gsm, "Areal density for the pear loop's gravity [g/m^2]")
      ->capture_default_str();
  app.add_option("--mesh", a.mesh_mm, "Cell size of the clamped-stretch mesh [mm]")->capture_default_str();
  app.add_option("--refine", a.refine, "Midpoint subdivisions of the clamped-stretch mesh")
      ->check(CLI::Range(0, 3))
      ->capture_default_str();
  app.add_option("--bend-mesh", a.bend_mesh_mm, "Cell size of the pear-loop mesh [mm]")->capture_default_str();
  app.add_option("--bend-refine", a.bend_refine, "Midpoint subdivisions of the pear-loop mesh")
      ->check(CLI::Range(0, 2))
      ->capture_default_str();
}

std::vector<std::string> check_shell_scene_args(const ShellSceneArgs& a, bool need_bending) {
  std::vector<std::string> problems;
  const auto say = [&](const std::string& option, double value, const std::string& what) {
    problems.push_back(option + ": " + db::format_g(value) + ": " + what);
  };
  const auto finite = [](double v) { return std::isfinite(v); };
  for (const auto& [name, v] : {std::pair{"--kxx", a.kxx}, {"--kyy", a.kyy}, {"--kss", a.kss}})
    if (!(finite(v) && v > 0.0)) say(name, v, "must be positive [N/m]");
  for (const auto& [name, v] : {std::pair{"--kn1", a.kn1}, {"--kn2", a.kn2}})
    if (!(finite(v) && v >= 0.0)) say(name, v, "must be zero or positive [N/m]");
  for (const auto& [name, v] : {std::pair{"--lxx", a.lxx}, {"--bxx", a.bxx}, {"--lyy", a.lyy}, {"--byy", a.byy},
                                {"--lss", a.lss}, {"--bss", a.bss}})
    if (!(finite(v) && v >= 0.0)) say(name, v, "must be zero or positive");
  // A lateral share takes either sign (the fits search [-3, 3]: a negative one lets a narrowing
  // across the pull add to the lock-up), as the laws of shell_fit.json and ground_truth hold.
  for (const auto& [name, v] : {std::pair{"--axx", a.axx}, {"--ayy", a.ayy}})
    if (!finite(v)) say(name, v, "must be finite");
  if (!finite(a.kxy)) say("--kxy", a.kxy, "must be finite [N/m]");
  else if (a.kxx > 0.0 && a.kyy > 0.0 && !(a.kxy * a.kxy < a.kxx * a.kyy))
    say("--kxy", a.kxy, "the membrane stiffness is not positive definite (needs kxy^2 < kxx*kyy)");
  for (const auto& [name, v] :
       {std::pair{"--ktheta-weft", a.ktheta_weft}, {"--ktheta-bias", a.ktheta_bias}, {"--ktheta-warp", a.ktheta_warp}}) {
    if (!(finite(v) && v >= 0.0)) say(name, v, "must be zero or positive [N*m]");
    else if (need_bending && !(v > 0.0)) say(name, v, "the pear loop needs a positive bending stiffness [N*m]");
  }
  if (!(finite(a.length_mm) && a.length_mm > 0.0)) say("--length-mm", a.length_mm, "must be positive");
  if (!(finite(a.width_mm) && a.width_mm > 0.0)) say("--width-mm", a.width_mm, "must be positive");
  if (!(finite(a.gauge_length_mm) && a.gauge_length_mm >= 0.0 && a.gauge_length_mm < a.length_mm))
    say("--gauge-length-mm", a.gauge_length_mm, "must lie between 0 and the free length (0: clamps)");
  if (!(finite(a.gauge_width_mm) && a.gauge_width_mm >= 0.0 && a.gauge_width_mm <= a.width_mm))
    say("--gauge-width-mm", a.gauge_width_mm, "must lie between 0 and the width (0: free edges)");
  if (need_bending && !(finite(a.areal_density_gsm) && a.areal_density_gsm > 0.0))
    say("--areal-density-gsm", a.areal_density_gsm, "the pear loop hangs under gravity: must be positive");
  if (!(finite(a.mesh_mm) && a.mesh_mm > 0.0)) say("--mesh", a.mesh_mm, "must be positive [mm]");
  if (!(finite(a.bend_mesh_mm) && a.bend_mesh_mm > 0.0)) say("--bend-mesh", a.bend_mesh_mm, "must be positive [mm]");
  return problems;
}

shell::SyntheticShellOptions synthetic_options(const ShellSceneArgs& a) {
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

}  // namespace yarnfit::cli
