#include "cli/yarn_scene.hpp"

namespace yarnfit::cli {

void add_yarn_scene_options(CLI::App& app, pipeline::YarnSceneRequest& a) {
  app.add_option("--pattern", a.setup.pattern, "Periodic yarn tile (HYLC pyp, metres); its x axis is the weft")
      ->required();
  app.add_option("--params", a.setup.params,
                 "Yarn parameters, YAML or JSON, SI units, keys of yarn_fit.json's params: ks1, eps_s, kb, R1, "
                 "kc1, ks2, kc2, R2 (a yarn_fit.json itself is accepted)")
      ->required();
  app.add_option("--direction", a.setup.direction, "Stretch direction: weft (0 deg), bias (45 deg) or warp (90 deg)")
      ->check(CLI::IsMember({"weft", "bias", "warp"}))
      ->capture_default_str();
  app.add_option("--ks2", a.setup.ks2,
                 "Stiffest yarn's stiffness [N]: fills ks2, kc2 = 1e3 ks2/R_est and R2 = 0.25 R_est when the "
                 "parameter file leaves them out (SPEC 3)");
  app.add_flag("--rest-shape,!--no-rest-shape", a.setup.rest_shape,
               "Estimate yarn rest shapes first (thesis 6.5.2: the tile is then nearly stress-free at rest, as in "
               "the yarn fit); --no-rest-shape simulates the rest lengths and curvatures of the file (default: "
               "rest shape on)");
  app.add_option("--rest-rounds", a.setup.rest_rounds, "Rounds of the rest-shape heuristic")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  app.add_option("--max-iterations", a.setup.max_iterations, "Newton iterations per equilibrium solve")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  app.add_option("--stress-tolerance", a.setup.stress_tolerance,
                 "A solve also ends once the coarse stress has settled within this [N/m] although forces of "
                 "slack yarns remain; 0 = off, solve to the force tolerance (default: 1e-6 ks1 / shorter period)");
  app.add_option("--compression-method", a.compression_method,
                 "Zero-orthogonal-stress compression: root (root find on dPsi/dc, default) or cobyla (as in "
                 "the thesis)")
      ->check(CLI::IsMember({"root", "cobyla"}))
      ->capture_default_str();
  app.add_option("--threads", a.threads, "OpenMP threads for the simulation's parallel loops (the yarn solver is serial today)")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
}

}  // namespace yarnfit::cli
