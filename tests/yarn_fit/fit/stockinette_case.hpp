#pragma once
// The stockinette tile of ../shared as the calibration tests use it: the tile, the yarn
// parameter scales (ks2 = 400 N, R_est from the tile) and targets simulated from known
// parameters. Tests call YARNFIT_REQUIRE_SHARED(stockinette_pattern()) first.
#include <stdexcept>
#include <vector>

#include "yarn_fit/fit/synth/synthetic_yarn_fabric.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"
#include "tests/test_support.hpp"
#include "yarn_fit/model/yarn_params.hpp"
#include "yarn_fit/periodic/yarn_tile.hpp"

namespace yarnfit::yarn::testcase {

inline std::filesystem::path stockinette_pattern() {
  return testing::shared_dir() / "data" / "patterns" / "stockinette.pyp";
}

struct Stockinette {
  db::PeriodicTile tile;
  yarn::ParameterScales scales;

  [[nodiscard]] yarn::YarnTile yarn_tile() const { return yarn::make_yarn_tile(tile); }
  // The default parameters with a soft toe phase (ks1 = 0.05 ks2), where the objective's
  // errors depend on ks1.
  [[nodiscard]] yarn::YarnParams soft_toe_params() const {
    yarn::YarnParams p = yarn::default_params(scales);
    p.ks1 = 0.05 * scales.ks2;
    return p;
  }
  // Uniform targets simulated from `truth` over [0, max_stretch] with `points` per direction.
  [[nodiscard]] SyntheticYarnResult synthesise(const yarn::YarnParams& truth, std::vector<db::Direction> directions,
                                               double max_stretch, int points) const {
    SyntheticYarnOptions so;
    so.directions = std::move(directions);
    so.max_stretch = max_stretch;
    so.points = points;
    return simulate_yarn_targets(tile, truth, so);
  }
};

// Throws std::runtime_error with the reader's problems when the tile cannot be read.
inline Stockinette load_stockinette() {
  db::Problems problems;
  const auto tile = db::read_pyp(stockinette_pattern(), problems);
  if (!tile) throw std::runtime_error(problems.to_string());
  return {*tile, {400.0, db::compute_tile_facts(*tile).r_est}};
}

}  // namespace yarnfit::yarn::testcase
