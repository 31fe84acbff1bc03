// `yarnfit synth yarn`: uniform targets and a fabric record simulated from a periodic tile and
// known yarn parameters (issue 5; yarn_fit/fit/synth/synthetic_yarn_fabric.hpp). `yarnfit synth
// fabric`: a whole record whose clamped-stretch and pear-loop tests come from known yarn
// parameters through their homogenised shell law (issue 48; pipeline/synthetic_fabric.hpp).
#include <cmath>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "yarn_fit/fit/synth/synthetic_yarn_fabric.hpp"
#include "pipeline/synthetic_fabric.hpp"
#include "cli/commands.hpp"
#include "fabrics_db/text_util.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"
#include "yarn_fit/scenes/yarn_scene.hpp"

namespace yarnfit::cli {

namespace {

// The tile and the yarn parameters both synth commands simulate from; `ks2` > 0 fills what the
// parameter file leaves out. Problems go to `problems`.
std::optional<std::pair<db::PeriodicTile, yarn::YarnParams>> read_tile_and_params(const std::string& pattern,
                                                                                   const std::string& params_file,
                                                                                   double ks2,
                                                                                   std::vector<std::string>& problems) {
  db::Problems found;
  const auto tile = db::read_pyp(pattern, found);
  std::optional<yarn::ParameterScales> scales;
  if (tile && ks2 > 0.0) scales = yarn::scales_of(*tile, ks2);
  const auto params = yarn::read_yarn_params(params_file, scales, found);
  for (const auto& p : found.items()) problems.push_back(p.to_string());
  if (!tile || !params) return std::nullopt;
  return std::make_pair(*tile, *params);
}

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
  yarn::SyntheticYarnOptions o;
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
  const auto input = read_tile_and_params(a.pattern, a.params_file, a.ks2, problems);
  if (!problems.empty() || !input) {
    for (const auto& p : problems) std::cerr << p << "\n";
    return k_exit_invalid_input;
  }
  return exit_code_of_writing(a.out, [&] {
    const auto r = yarn::write_synthetic_yarn_fabric(input->first, input->second, o, a.out, a.force);
    if (!a.quiet) {
      std::cout << "wrote " << (std::filesystem::path(a.out) / "uniform_targets.csv").string() << " and fabric "
                << a.id << " in " << (std::filesystem::path(a.out) / "fabric").string() << " ("
                << db::format_g(r.seconds, 3) << " s)\n";
    }
  });
}

struct SynthFabricArgs {
  std::string pattern, params_file, out, id = "synthetic_fabric", family = "synthetic", model = "stiffening";
  double max_stretch = 0.3, max_curvature = 150.0, ks2 = 0.0, density_gsm = 180.0;
  std::vector<std::string> directions{"weft", "bias", "warp"}, bending{"weft", "warp"};
  bool force = false, quiet = false;
};

std::vector<db::Direction> directions_of(const std::vector<std::string>& names, const char* option,
                                         std::vector<std::string>& problems) {
  std::vector<db::Direction> out;
  for (const auto& name : names) {
    if (name == "none") continue;
    const auto dir = db::parse_direction(name);
    if (!dir) problems.push_back(std::string(option) + ": " + name + ": not a direction (weft, bias, warp)");
    else out.push_back(*dir);
  }
  return out;
}

int run_synth_fabric(const SynthFabricArgs& a) {
  std::vector<std::string> problems;
  pipeline::SyntheticFabricOptions o;
  o.id = a.id;
  o.family = a.family;
  o.max_stretch = a.max_stretch;
  o.max_curvature = a.max_curvature;
  o.areal_density = a.density_gsm * 1e-3;
  o.stretch_directions = directions_of(a.directions, "--directions", problems);
  o.bending_directions = directions_of(a.bending, "--bending", problems);
  if (const auto model = shell::parse_inplane_model(a.model)) o.model = *model;
  else problems.push_back("--shell-model: " + a.model + ": not a shell model (stiffening or thesis)");
  if (!(std::isfinite(a.ks2) && a.ks2 >= 0.0)) problems.push_back("--ks2: must be a positive stiffness [N]");
  const auto input = read_tile_and_params(a.pattern, a.params_file, a.ks2, problems);
  if (!problems.empty() || !input) {
    for (const auto& p : problems) std::cerr << p << "\n";
    return k_exit_invalid_input;
  }
  return exit_code_of_writing(a.out, [&] {
    const auto r = pipeline::write_synthetic_fabric(input->first, input->second, o, a.out, a.force);
    if (!a.quiet)
      std::cout << "wrote fabric " << a.id << " in " << a.out << " (" << db::format_g(r.seconds, 3)
                << " s); its law reproduces the yarn model's samples to " << db::format_g(r.law.stress_misfit_pct, 2)
                << " % (stress), " << db::format_g(r.law.compression_misfit_pct, 2) << " % (compression), "
                << db::format_g(r.law.bending_misfit_pct, 2) << " % (bending)\n";
  });
}

}  // namespace

void add_synth_fabric_command(CLI::App& synth, int& exit_code) {
  auto args = std::make_shared<SynthFabricArgs>();
  auto* f = synth.add_subcommand(
      "fabric", "Write a whole fabric record whose clamped-stretch and pear-loop tests come from known yarn parameters: "
                "the tile's uniform responses homogenised to a shell law, the tests simulated with it (the yarn "
                "parameters and the law under ground_truth)");
  f->add_option("--pattern", args->pattern, "Periodic yarn tile (.pyp), x axis along the weft")->required();
  f->add_option("--yarn-params", args->params_file, "Yarn parameters (YAML/JSON, keys of yarn_fit.json's params)")
      ->required();
  f->add_option("-o,--out", args->out, "The record's folder")->required();
  f->add_option("--max-stretch", args->max_stretch, "Largest stretch of the samples and the tests")
      ->check(CLI::Range(1e-3, 2.0))
      ->capture_default_str();
  f->add_option("--directions", args->directions, "Stretch tests")->delimiter(',')->capture_default_str();
  f->add_option("--bending", args->bending, "Pear-loop tests (none: no bending tests)")->delimiter(',')->capture_default_str();
  f->add_option("--max-curvature", args->max_curvature, "Largest curvature of the bending samples [1/m]")
      ->check(CLI::Range(1.0, 1e4))
      ->capture_default_str();
  f->add_option("--areal-density-gsm", args->density_gsm, "Areal density [g/m²] (the pear loop hangs under it)")
      ->check(CLI::Range(1.0, 5000.0))
      ->capture_default_str();
  f->add_option("--shell-model", args->model, "The homogenised law: stiffening or thesis")->capture_default_str();
  f->add_option("--ks2", args->ks2, "Fills ks2, kc2 and R2 the parameter file leaves out (SPEC §3)");
  f->add_option("--id", args->id, "Fabric id")->capture_default_str();
  f->add_option("--family", args->family, "Fabric family")->capture_default_str();
  f->add_flag("--force", args->force, "Replace an existing record in the folder");
  f->add_flag("-q,--quiet", args->quiet, "No summary line");
  f->callback([args, &exit_code] { exit_code = run_synth_fabric(*args); });
}

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
