#pragma once
// A whole fabric record from a known yarn model (issue 48, `yarnfit synth fabric`): what the
// pipeline must recover. The same path a fitted yarn model is checked by
// (pipeline/measured_check.hpp), run forwards:
//   1. the tile's uniform responses with the yarn parameters (after the rest-shape heuristic):
//      σ_s and c* along weft, bias and warp up to max_stretch, and Δσ_κ(κ) bent about each
//      direction with pear-loop tests;
//   2. homogenised: the shell law fitted to them (shell::fit_law_to_samples);
//   3. the record's tests simulated with that law: clamped stretch on the 10 × 6 cm swatch and
//      pear loops at 7 distances from 3 to 34 mm (shell_fit/fit/synthetic_fabric.hpp's scenes,
//      on meshes finer than the fit's).
// The record holds the tile (tile.pyp), one yarn whose stiffness_N is ks2, and under
// ground_truth the yarn parameters and the homogenised law's.

#include <filesystem>
#include <string>
#include <vector>

#include "fabrics_db/records/fabric.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"
#include "shell_fit/fit/uniform_law_fit.hpp"
#include "yarn_fit/model/yarn_params.hpp"

namespace yarnfit::pipeline {

struct SyntheticFabricOptions {
  std::string id = "synthetic_fabric";
  std::string family = "synthetic";
  std::string description;  // empty: a sentence saying how the record was made
  std::vector<db::Direction> stretch_directions{db::Direction::weft, db::Direction::bias, db::Direction::warp};
  double max_stretch = 0.3;     // of the uniform samples and the stretch tests
  int uniform_points = 13;      // uniform samples per direction, evenly from 0
  int test_points = 13;         // points of each stretch test
  std::vector<db::Direction> bending_directions{db::Direction::weft, db::Direction::warp};
  double max_curvature = 150.0;  // of the bending samples [1/m]
  int curvature_points = 5;
  double areal_density = 0.18;   // [kg/m²], for the pear loops
  shell::InplaneModel model = shell::InplaneModel::stiffening;
  // How fabric.yaml describes the record (the bundled examples name their yarn and read some
  // tests at gauge marks).
  std::string header;  // comment lines opening fabric.yaml, each starting "# "; empty: the writer's own
  std::string yarn_material = "synthetic";
  int denier = 100;
  int filaments = 0;  // 0: not stated
  std::vector<db::Direction> gauged_directions;  // stretch tests read at gauge marks 80 mm along, 40 mm across
  int digits = 12;  // significant digits of the curves and of ground_truth
};

struct SyntheticFabricResult {
  shell::UniformLawFit law;
  std::vector<db::DirectionTargets> samples;  // the yarn model's uniform responses
  double seconds = 0.0;
};

// Writes FOLDER/fabric.yaml, tile.pyp, stretch_<dir>.csv and bend_<dir>.csv. Throws
// an input Error for invalid options or parameters, an Error when a simulation
// fails, the law cannot be fitted, or fabric.yaml exists and `overwrite` is false.
SyntheticFabricResult write_synthetic_fabric(const db::PeriodicTile& tile, const yarn::YarnParams& params,
                                             const SyntheticFabricOptions& options, const std::filesystem::path& folder,
                                             bool overwrite = false);

}  // namespace yarnfit::pipeline
