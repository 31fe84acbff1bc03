// `yarnfit synth shell`: a fabric record of clamped-stretch (and pear-loop) tests simulated from
// shell parameters (issue 3). `yarnfit synth yarn`: uniform targets and a fabric record simulated from a periodic tile and
// known yarn parameters (issue 5). `yarnfit synth fabric`: a whole record whose clamped-stretch
// and pear-loop tests come from known yarn parameters through their homogenised shell law
// (issue 48). pipeline/tools/synth_records.hpp makes all three.
#include <iostream>
#include <memory>
#include <string>

#include "cli/commands.hpp"
#include "cli/shell_scene_args.hpp"
#include "pipeline/tools/synth_records.hpp"

namespace yarnfit::cli {

namespace {

struct SynthShellArgs {
  pipeline::SynthShellRequest request;
};

struct SynthYarnArgs {
  pipeline::SynthYarnRequest request;
  bool quiet = false;
};

struct SynthFabricArgs {
  pipeline::SynthFabricRequest request;
  bool quiet = false;
};

// Runs one synth request: its problems exit 2 before anything is written.
template <class Request, class Synth>
int run_synth(const Request& request, bool quiet, Synth&& synth) {
  db::Problems problems;
  std::string wrote;
  const int code = exit_code_of_writing(request.out, [&] { wrote = synth(request, problems); });
  if (!problems.empty()) return invalid_input(problems);
  if (code == k_exit_ok && !quiet) std::cout << wrote;
  return code;
}

}  // namespace

void add_synth_fabric_command(CLI::App& synth, int& exit_code) {
  auto args = std::make_shared<SynthFabricArgs>();
  pipeline::SynthFabricRequest& r = args->request;
  auto* f = synth.add_subcommand(
      "fabric", "Write a whole fabric record whose clamped-stretch and pear-loop tests come from known yarn parameters: "
                "the tile's uniform responses homogenised to a shell law, the tests simulated with it (the yarn "
                "parameters and the law under ground_truth)");
  f->add_option("--pattern", r.model.pattern, "Periodic yarn tile (.pyp), x axis along the weft")->required();
  f->add_option("--yarn-params", r.model.params_file, "Yarn parameters (YAML/JSON, keys of yarn_fit.json's params)")
      ->required();
  f->add_option("-o,--out", r.out, "The record's folder")->required();
  f->add_option("--max-stretch", r.max_stretch, "Largest stretch of the samples and the tests")
      ->check(CLI::Range(1e-3, 2.0))
      ->capture_default_str();
  f->add_option("--directions", r.directions, "Stretch tests")->delimiter(',')->capture_default_str();
  f->add_option("--bending", r.bending, "Pear-loop tests (none: no bending tests)")->delimiter(',')->capture_default_str();
  f->add_option("--max-curvature", r.max_curvature, "Largest curvature of the bending samples [1/m]")
      ->check(CLI::Range(1.0, 1e4))
      ->capture_default_str();
  f->add_option("--areal-density-gsm", r.density_gsm, "Areal density [g/m²] (the pear loop hangs under it)")
      ->check(CLI::Range(1.0, 5000.0))
      ->capture_default_str();
  f->add_option("--shell-model", r.shell_model, "The homogenised law: stiffening or thesis")->capture_default_str();
  f->add_option("--ks2", r.model.ks2, "Fills ks2, kc2 and R2 the parameter file leaves out (SPEC §3)");
  f->add_option("--id", r.id, "Fabric id")->capture_default_str();
  f->add_option("--family", r.family, "Fabric family")->capture_default_str();
  f->add_flag("--force", r.force, "Replace an existing record in the folder");
  f->add_flag("-q,--quiet", args->quiet, "No summary line");
  f->callback([args, &exit_code] { exit_code = run_synth(args->request, args->quiet, pipeline::synth_fabric); });
}

void add_synth_yarn_command(CLI::App& synth, int& exit_code) {
  auto args = std::make_shared<SynthYarnArgs>();
  pipeline::SynthYarnRequest& r = args->request;
  auto* y = synth.add_subcommand(
      "yarn", "Simulate uniform yarn-level stretch targets from a tile and known yarn parameters (after the "
              "rest-shape heuristic) and write DIR/uniform_targets.csv and a fabric record DIR/fabric");
  y->add_option("--pattern", r.model.pattern, "Periodic yarn tile (.pyp), x axis along the weft")->required();
  y->add_option("--params", r.model.params_file, "Yarn parameters (YAML/JSON, keys of yarn_fit.json's params)")
      ->required();
  y->add_option("-o,--out", r.out, "Output folder")->required();
  y->add_option("--max-stretch", r.max_stretch, "Largest stretch per direction")
      ->check(CLI::Range(1e-6, 3.0))
      ->capture_default_str();
  y->add_option("--directions", r.directions, "Directions to simulate")->delimiter(',')->capture_default_str();
  y->add_option("--points", r.points, "Stretch points per direction, evenly from 0")
      ->check(CLI::Range(2, 1000))
      ->capture_default_str();
  y->add_option("--ks2", r.model.ks2, "Fills ks2, kc2 and R2 the parameter file leaves out (SPEC §3)");
  y->add_option("--id", r.id, "Fabric id")->capture_default_str();
  y->add_option("--family", r.family, "Fabric family")->capture_default_str();
  y->add_flag("--force", r.force, "Replace an existing record in the folder");
  y->add_flag("-q,--quiet", args->quiet, "No summary line");
  y->callback([args, &exit_code] { exit_code = run_synth(args->request, args->quiet, pipeline::synth_yarn); });
}

void add_synth_commands(CLI::App& app, int& exit_code) {
  auto* synth = app.add_subcommand("synth", "Synthetic fabric records simulated from known parameters");
  synth->require_subcommand(1);
  auto args = std::make_shared<SynthShellArgs>();
  pipeline::SynthShellRequest& r = args->request;
  auto* sh = synth->add_subcommand(
      "shell", "Simulate clamped stretch tests (and, with k_theta, pear-loop bending tests) from shell "
               "parameters and write a fabric record with them under ground_truth");
  sh->add_option("-o,--out", r.out, "Fabric folder to write")->required();
  sh->add_option("--id", r.id, "Fabric id")->capture_default_str();
  sh->add_option("--family", r.family, "Fabric family")->capture_default_str();
  (void)add_shell_parameter_options(*sh, r.values);
  sh->add_option("--weft", r.weft, "Largest weft stretch (<= 0 omits the test)")->capture_default_str();
  sh->add_option("--bias", r.bias, "Largest bias stretch (<= 0 omits the test)")->capture_default_str();
  sh->add_option("--warp", r.warp, "Largest warp stretch (<= 0 omits the test)")->capture_default_str();
  sh->add_option("--bending", r.bending,
                 "Directions of the pear-loop tests, written when k_theta is given (all three must be positive)")
      ->delimiter(',')
      ->capture_default_str();
  add_shell_scene_options(*sh, r.values);
  sh->add_option("--noise", r.noise, "Relative Gaussian noise on force, compression and aspect ratio")
      ->check(CLI::Range(0.0, 0.5));
  sh->add_option("--seed", r.seed, "Noise seed")->capture_default_str();
  sh->add_option("--points", r.points, "Points per stretch curve")->check(CLI::Range(3, 1000))->capture_default_str();
  sh->add_option("--bend-points", r.bend_points, "Clamp distances per pear-loop curve, evenly over 3-34 mm")
      ->check(CLI::Range(2, 100))
      ->capture_default_str();
  sh->add_flag("--force", r.force, "Replace an existing record in the folder");
  sh->callback([args, &exit_code] { exit_code = run_synth(args->request, false, pipeline::synth_shell); });
}

}  // namespace yarnfit::cli
