#pragma once
// Synthetic yarn fabrics (issue 5, `yarnfit synth yarn`): uniform targets simulated from a
// periodic tile and known yarn parameters, so that a yarn fit on them is a recovery test.
//
// The tile first goes through the rest-shape heuristic (6.5.2) with the true parameters, the
// same step the calibration applies to every candidate; then per direction a free-compression
// stretch sweep (yarn_fit/scenes/stretch_sweep.hpp, c*(s) solved at every point) over
// `points` stretches evenly in [0, max_stretch]. The targets are written with fabrics_db's
// writer (uniform_targets.csv). The fabric record holds the tile, one yarn whose stiffness_N is
// ks2, the parameters under ground_truth, and per direction a stretch test on the default
// 10 × 6 cm swatch whose clamp force is the uniform line stress times the width (σ_s · 0.06 m)
// and whose compression is c*: the uniform response, not a clamped-swatch simulation.

#include <filesystem>
#include <string>
#include <vector>

#include "fabrics_db/records/fabric.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"
#include "fabrics_db/targets/uniform_targets.hpp"
#include "yarn_fit/homogenise/rest_shape.hpp"
#include "yarn_fit/model/yarn_params.hpp"

namespace yarnfit::yarn {

struct SyntheticYarnOptions {
  std::string id = "synthetic_yarn";
  std::string family = "synthetic";
  std::vector<db::Direction> directions{db::Direction::weft, db::Direction::bias, db::Direction::warp};
  double max_stretch = 0.3;
  int points = 13;            // per direction, evenly over [0, max_stretch], both ends included
  double swatch_length = 0.10;  // [m]
  double swatch_width = 0.06;   // [m]
  yarn::RestShapeOptions rest;
};

struct SyntheticYarnResult {
  std::vector<db::DirectionTargets> targets;
  yarn::RestShapeResult rest;
  double seconds = 0.0;
};

// Simulates the targets. Throws an input Error for invalid options or parameters and
// an Error naming the direction and stretch when a simulation fails.
SyntheticYarnResult simulate_yarn_targets(const db::PeriodicTile& tile, const yarn::YarnParams& params,
                                          const SyntheticYarnOptions& options);

// Writes OUT/uniform_targets.csv and OUT/fabric/{fabric.yaml, tile.pyp, stretch_<dir>.csv}.
// Refuses to replace an existing fabric.yaml unless `overwrite`.
SyntheticYarnResult write_synthetic_yarn_fabric(const db::PeriodicTile& tile, const yarn::YarnParams& params,
                                                const SyntheticYarnOptions& options,
                                                const std::filesystem::path& out, bool overwrite = false);

}  // namespace yarnfit::yarn
