#pragma once
// The synth commands as one library call each: fabric records made from known models, for the
// fits to recover.
//   synth shell:  clamped-stretch (and pear-loop) tests simulated from shell parameters
//                 (shell_fit/fit/synthetic_fabric.hpp);
//   synth yarn:   uniform yarn-level targets and a record of their stretch curves
//                 (yarn_fit/fit/synth/synthetic_yarn_fabric.hpp);
//   synth fabric: a whole record whose clamped-stretch and pear-loop tests come from the yarn
//                 model through its homogenised shell law (pipeline/synthetic_fabric.hpp).

#include <string>
#include <vector>

#include "fabrics_db/problems.hpp"
#include "pipeline/tools/simulate_shell.hpp"

namespace yarnfit::pipeline {

struct SynthShellRequest {
  ShellSceneRequest values;  // the parameters and the scenes
  std::string out;           // the record's folder
  std::string id = "synthetic_shell";
  std::string family = "synthetic";
  double weft = 0.8, bias = 0.6, warp = 0.4;  // largest stretch of each test; ≤ 0 omits it
  std::vector<std::string> bending{"weft", "bias", "warp"};  // pear-loop tests, when a k_θ is given
  double noise = 0.0;  // relative Gaussian noise on force, compression and aspect ratio
  unsigned seed = 1;
  int points = 13;     // per stretch curve
  int bend_points = shell::SyntheticShellOptions{}.bending_points;
  bool force = false;
};

// The known yarn model: a pyp tile and a parameter file (YAML/JSON, keys of yarn_fit.json's
// params); `ks2` > 0 fills ks2, kc2 and R2 the file leaves out (SPEC §3).
struct KnownYarnModel {
  std::string pattern;
  std::string params_file;
  double ks2 = 0.0;
};

struct SynthYarnRequest {
  KnownYarnModel model;
  std::string out;  // the folder: OUT/uniform_targets.csv and the record OUT/fabric
  std::string id = "synthetic_yarn";
  std::string family = "synthetic";
  double max_stretch = 0.3;
  std::vector<std::string> directions{"weft", "bias", "warp"};
  int points = 13;     // per direction, evenly from 0
  bool force = false;  // replace an existing record
};

struct SynthFabricRequest {
  KnownYarnModel model;
  std::string out;  // the record's folder
  std::string id = "synthetic_fabric";
  std::string family = "synthetic";
  std::string shell_model = "stiffening";
  double max_stretch = 0.3;
  double max_curvature = 150.0;  // of the bending samples [1/m]
  double density_gsm = 180.0;    // the pear loops hang under it
  std::vector<std::string> directions{"weft", "bias", "warp"};  // stretch tests
  std::vector<std::string> bending{"weft", "warp"};            // pear-loop tests; "none": none
  bool force = false;
};

// Each checks its request (problems name its fields, or the file read) and writes nothing when
// there is one; otherwise writes the record and returns a line saying what it wrote. Throws
// an input Error for settings the simulation refuses, an Error when a
// simulation fails or the record exists without `force`.
[[nodiscard]] std::string synth_shell(const SynthShellRequest& request, db::Problems& problems);
[[nodiscard]] std::string synth_yarn(const SynthYarnRequest& request, db::Problems& problems);
[[nodiscard]] std::string synth_fabric(const SynthFabricRequest& request, db::Problems& problems);

}  // namespace yarnfit::pipeline
