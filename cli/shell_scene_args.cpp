#include "cli/shell_scene_args.hpp"


namespace yarnfit::cli {

std::vector<CLI::Option*> add_shell_parameter_options(CLI::App& app, pipeline::ShellSceneRequest& a) {
  const auto values = pipeline::parameter_values(a);
  std::vector<CLI::Option*> options;
  for (std::size_t i = 0; i < 6; ++i) {
    options.push_back(app.add_option(std::string("--") + pipeline::k_shell_param_names[i], *values[i],
                                                 "In-plane shell parameter [N/m]")
                                      ->capture_default_str());
  }
  const char* dirs[3] = {"weft", "bias", "warp"};
  for (std::size_t i = 0; i < 3; ++i) {
    options.push_back(
        app.add_option(std::string("--ktheta-") + dirs[i], *values[6 + i],
                       std::string("Bending stiffness k_theta along the ") + dirs[i] + " [N*m]; 0: none")
            ->capture_default_str());
  }
  for (std::size_t i = 9; i < values.size(); ++i) {
    const bool share = i >= 15, rate = !share && (i - 9) % 2 == 1;
    options.push_back(
        app.add_option(std::string("--") + pipeline::k_shell_param_names[i], *values[i],
                       share  ? "Lateral share a of the weft (axx) or warp (ayy) lock-up strain [-]"
                       : rate ? "Lock-up rate b of the stiffening model [-]"
                              : "Lock-up stiffness l of the stiffening model [N/m]; 0: none")
            ->capture_default_str());
  }
  return options;
}

void add_shell_scene_options(CLI::App& app, pipeline::ShellSceneRequest& a) {
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

std::vector<std::string> given_parameters(const std::vector<CLI::Option*>& options) {
  std::vector<std::string> given;
  for (std::size_t i = 0; i < options.size(); ++i)
    if (options[i]->count() > 0) given.emplace_back(pipeline::k_shell_param_names[i]);
  return given;
}

}  // namespace yarnfit::cli
