// `yarnfit synth yarn`: uniform targets and a fabric record simulated from a periodic tile and
// known yarn parameters (issue 5; calibration/synth/synthetic_yarn_fabric.hpp).
#include <cmath>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "calibration/synth/synthetic_yarn_fabric.hpp"
#include "cli/commands.hpp"
#include "fabrics_db/text_util.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"
#include "yarn_fit/scenes/yarn_scene.hpp"

namespace yarnfit::cli {

namespace {

struct SynthYarnArgs {
  std::string pattern, params_file, out, id = "synthetic_yarn", family = "synthetic";
  double max_stretch = 0.3;
  double ks2 = 0.0;
  std::vector<std::string> directions{"weft", "bias", "warp"};
  int points = 13;
  bool force = false;
  bool quiet = false;
};

int run_synth_yarn(const SynthYarnArgs& a) {
  std::vector<std::string> problems;
  calibration::SyntheticYarnOptions o;
  o.id = a.id;
  o.family = a.family;
  o.max_stretch = a.max_stretch;
  o.points = a.points;
  o.directions.clear();
  for (const auto& name : a.directions) {
    const auto dir = db::parse_direction(name);
    if (!dir) problems.push_back("--directions: " + name + ": not a direction (weft, bias, warp)");
    else o.directions.push_back(*dir);
  }
  if (!(std::isfinite(a.ks2) && a.ks2 >= 0.0)) problems.push_back("--ks2: must be a positive stiffness [N]");
  db::Problems found;
  const auto tile = db::read_pyp(a.pattern, found);
  std::optional<yarn::ParameterScales> scales;
  if (tile && a.ks2 > 0.0) scales = yarn::scales_of(*tile, a.ks2);
  const auto params = yarn::read_yarn_params(a.params_file, scales, found);
  for (const auto& p : found.items()) problems.push_back(p.to_string());
  if (!problems.empty() || !tile || !params) {
    for (const auto& p : problems) std::cerr << p << "\n";
    return k_exit_invalid_input;
  }
  return exit_code_of_writing(a.out, [&] {
    const auto r = calibration::write_synthetic_yarn_fabric(*tile, *params, o, a.out, a.force);
    if (!a.quiet) {
      std::cout << "wrote " << (std::filesystem::path(a.out) / "uniform_targets.csv").string() << " and fabric "
                << a.id << " in " << (std::filesystem::path(a.out) / "fabric").string() << " ("
                << db::format_g(r.seconds, 3) << " s)\n";
    }
  });
}

}  // namespace

void add_synth_yarn_command(CLI::App& synth, int& exit_code) {
  auto args = std::make_shared<SynthYarnArgs>();
  auto* y = synth.add_subcommand(
      "yarn", "Simulate uniform yarn-level stretch targets from a tile and known yarn parameters (after the "
              "rest-shape heuristic) and write DIR/uniform_targets.csv and a fabric record DIR/fabric");
  y->add_option("--pattern", args->pattern, "Periodic yarn tile (.pyp), x axis along the weft")->required();
  y->add_option("--params", args->params_file, "Yarn parameters (YAML/JSON, keys of yarn_fit.json's params)")
      ->required();
  y->add_option("-o,--out", args->out, "Output folder")->required();
  y->add_option("--max-stretch", args->max_stretch, "Largest stretch per direction")
      ->check(CLI::Range(1e-6, 3.0))
      ->capture_default_str();
  y->add_option("--directions", args->directions, "Directions to simulate")->delimiter(',')->capture_default_str();
  y->add_option("--points", args->points, "Stretch points per direction, evenly from 0")
      ->check(CLI::Range(2, 1000))
      ->capture_default_str();
  y->add_option("--ks2", args->ks2, "Fills ks2, kc2 and R2 the parameter file leaves out (SPEC §3)");
  y->add_option("--id", args->id, "Fabric id")->capture_default_str();
  y->add_option("--family", args->family, "Fabric family")->capture_default_str();
  y->add_flag("--force", args->force, "Replace an existing record in the folder");
  y->add_flag("-q,--quiet", args->quiet, "No summary line");
  y->callback([args, &exit_code] { exit_code = run_synth_yarn(*args); });
}

}  // namespace yarnfit::cli
