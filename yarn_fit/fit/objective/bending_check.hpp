#pragma once
// How well fitted yarn parameters reproduce the bending targets (SPEC §3 "Error metrics":
// the yarn errors include bending stiffness, thesis Fig. 6.15 and Table 6.1). The objective
// (6.11) fits stretch and compression only; bending is checked afterwards, on the same
// rest-shaped tile.
//
// Per direction with bending targets: the tile is bent along the direction at zero stretch
// and compression, at `points` of the target curvatures (both ends included), marching κ
// upwards with warm starts, and σ_κ = dΨ/dκ is read by central differences (readouts.hpp).
// A knitted tile curls at rest (stockinette: dΨ/dκ(0) ≈ ±5e-4 N, as large as the targets), a
// shell does not: the comparison is of Δσ_κ(κ) = σ_κ(κ) − σ_κ(0), the bending stiffness
// response, against the shell's 2 k_θ κ. Error (results::yarn_error_pct_normalised_after):
// mean |Δσ_κ − target| over the points divided by the largest |target|, in percent.

#include <limits>
#include <string>
#include <vector>

#include "yarn_fit/fit/objective/yarn_objective.hpp"

namespace yarnfit::yarn {

struct BendingDirectionError {
  db::Direction direction = db::Direction::weft;
  std::vector<double> curvature;       // κ [1/m]
  std::vector<double> stress_sim;      // Δσ_κ = σ_κ(κ) − σ_κ(0) [N]
  std::vector<double> stress_target;   // 2 k_θ κ [N]
  double curl_stress = 0.0;            // σ_κ(0) of the yarn tile [N]
  double error_pct = 0.0;               // NaN when every target is 0
};

struct BendingCheck {
  bool ok = false;
  std::string message;  // why !ok (a bending solve failed); empty with no bending targets
  std::vector<BendingDirectionError> directions;  // directions with bending targets
  double bending_pct = std::numeric_limits<double>::quiet_NaN();  // mean over directions (NaN when none)
  int solves = 0;
  std::vector<std::string> effects;  // what the bending scenes assembled (co-rotation when bent)
  double seconds = 0.0;
};

// `points` ≥ 2 curvatures per direction. Never throws for numerical trouble.
BendingCheck check_bending(const yarn::YarnTile& tile, const std::vector<db::DirectionTargets>& targets,
                           const yarn::YarnParams& params, const ObjectiveOptions& options, int points = 5);

}  // namespace yarnfit::yarn
