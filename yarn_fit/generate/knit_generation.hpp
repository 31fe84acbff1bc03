#pragma once
// A relaxed periodic yarn tile of a real knit from its chart, stitch length and yarn radius
// (issue 20; `yarnfit tile make`, records with `pattern: {knit: …}`):
//   1. the initial loops (fabrics_db/tile/knit_tile.hpp), every stitch L long;
//   2. the yarns relaxed at rest, contacts resolved, with straight rest shapes (zero rest
//      curvature) and the rest lengths of step 1, so the yarn length per stitch stays L;
//   3. the period relaxed until the coarse normal stress at rest is at most
//      `rest_stress_fraction` of the tile's σ_s at 10 % stretch, in weft and in warp
//      (rest_period.hpp); σ_s(10 %) is measured on the relaxed tile and the relaxation
//      repeated while that changes the tolerance it was run with.
// The spacings of courses and wales come out of the mechanics of step 3 — unless the geometry
// holds a period (a knitting gauge, issue 48): then step 3 is the rest-shape heuristic at that
// period (thesis 6.5.2: the rest lengths, within ±20 %, and the rest curvatures absorb the
// rest stress), and the rest stress left is reported (rest_stress_ratio), not driven to the
// tolerance.
//
// Yarn parameters: given, or default_params with R_est = R (SPEC §3: R1 = R, R2 = R/4, …)
// and ks2 = 400 N. Every default stiffness is proportional to ks2, so the relaxed geometry
// does not depend on that choice; the stresses reported do, the ratio does not.

#include <Eigen/Core>
#include <optional>
#include <string>
#include <nlohmann/json_fwd.hpp>

#include "fabrics_db/tile/knit_tile.hpp"
#include "results/tile_file.hpp"
#include "yarn_fit/homogenise/rest_period.hpp"
#include "yarn_fit/homogenise/rest_shape.hpp"
#include "yarn_fit/model/yarn_params.hpp"
#include "yarn_fit/periodic/yarn_system.hpp"

namespace yarnfit::yarn {

struct TileGenerationOptions {
  db::KnitTileOptions geometry;
  std::optional<YarnParams> params;   // default: see above
  double default_ks2 = 400.0;         // [N]
  double rest_stress_fraction = 0.01;
  int rounds = 3;                     // relaxations, each with the latest σ_s(10 %)
  int max_period_steps = 40;
  // Hold the period the initial loops were built at (their course_ratio and stitch length
  // decide it) instead of relaxing it by the mechanics; a gauge (geometry's spacings) holds
  // its period whatever this says.
  bool hold_period = false;
  EquilibriumOptions solve;
};

struct GeneratedTile {
  db::KnitTile initial;                 // the loops before relaxation
  db::PeriodicTile tile;                // relaxed: positions at rest, period, rest lengths
  YarnParams params;
  bool converged = false;               // every solve converged and the rest stress is within tolerance
  std::string message;                  // why not
  RestPeriodResult relaxation;          // the last round
  int rounds = 0;
  Eigen::Vector2d stress_at_10 = Eigen::Vector2d::Zero();  // σ_s at 10 % stretch, weft and warp [N/m]
  double rest_stress_ratio = 0.0;       // max over weft, warp of |P_ii| / σ_s,i(10 %)
  double min_distance = 0.0;            // smallest centreline distance at rest [m]
  double stitch_length = 0.0;           // rest length per stitch [m]
  double seconds = 0.0;
  bool held_period = false;             // built at a given period and held there

  [[nodiscard]] double wale_spacing() const { return tile.period_x / initial.chart.wales(); }
  [[nodiscard]] double course_spacing() const { return tile.period_y / initial.chart.courses(); }
};

// Throws an input Error for bad geometry options (make_knit_tile) or parameters;
// numerical trouble is reported in `converged` and `message`.
GeneratedTile generate_knit_tile(const db::KnitChart& chart, const TileGenerationOptions& options);

// The pyp tile of the system's state g at χ = 0 on `source`'s vertices and edges: positions,
// period (the lattice must be diagonal), rest lengths and rest curvatures (κ, 0) from the
// system; twists and reference twists from `source`, reference directors recomputed.
db::PeriodicTile tile_at_rest(const db::PeriodicTile& source, const YarnSystem& system, const Eigen::VectorXd& g);

// The tile's record (SPEC §5 `tile make --json`; results/tile_file.hpp writes it).
results::TileFile to_file(const GeneratedTile& generated);

}  // namespace yarnfit::yarn
