#pragma once
// The tile's shape fitted where the record gives no gauge (issue 48, item 2): for a tile
// generated from a knit chart and stitch length, the course/wale aspect a = p/w of its loops
// becomes a parameter of the yarn fit, reported under `shape` in yarn_fit.json.
//
// The tile is built at a held period (knit_generation.hpp: the rest lengths and curvatures
// absorb the rest stress) with the loop density of the prior kept, L²/(w p) = K_s, so that a
// moves the loops' proportions, not their size:  w = L / √(K_s a),  p = L √(a / K_s).
//
// Prior (loop_shape_prior): a knit whose every loop shows one face (stockinette and its
// reverse) takes the loop-shape constants of the two plain-knit tiles registered from real
// fabrics that HYLC publishes (../shared/data/patterns: stockinette.pyp K_c = L/p = 6.62,
// K_w = L/w = 3.49; stocktiny.pyp 6.07, 3.71): K_c = 6.35, K_w = 3.60, a = 0.567. (Munden's
// dry-relaxed plain-knit constants, 5.0 and 3.8, a = 0.76, describe wool fabrics off the
// machine and put both registered tiles' courses 20–30 % further apart.) Other charts
// (rib, garter, seed, …) take the period the mechanics relax a generated tile to.
//
// Search (a one-dimensional outer search with warm starts): first the full yarn fit on the tile
// as generated (its period the mechanics', moved by the fit's period steps: the fit without a
// shape of its own, so that the search never ends above its g); then local-only fits from the
// best parameters so far (at the held tile's radius, or at their own R1 where that fails; and
// from the caller's start, when it gave one) on tiles held at the prior aspect and at aspects
// stepped away from it while the held trials' g falls, both ways, within [lower, upper] × the
// prior; then one step to the vertex of the parabola through the best held trial and its
// neighbours. The best trial is the result.
// Its range: where that parabola stays within twice the best g. A held tile's period is the
// shape's, not a relaxation's at one contact radius: every candidate's rest state resolves the
// contacts at its own R1 (docs/calibration.md: why the held tiles alone did worse on the rib
// and the seed).

#include <optional>
#include <string>
#include <vector>

#include "yarn_fit/fit/problem/yarn_fit_problem.hpp"
#include "fabrics_db/records/fabric.hpp"

namespace yarnfit::yarn {

struct ShapeSearchSettings {
  bool enabled = true;
  double lower = 0.8;   // bounds of a, relative to the prior
  double upper = 1.25;
  double step = 0.08;   // first relative step from the prior
  int max_trials = 5;   // local fits after the prior's full fit
};

struct LoopShapePrior {
  double courses_constant = 0.0;  // K_c = L / p
  double wales_constant = 0.0;    // K_w = L / w
  std::string source;
  [[nodiscard]] double aspect() const { return wales_constant / courses_constant; }
};

// The registered plain-knit constants for a chart whose loops all show one face; none else.
std::optional<LoopShapePrior> loop_shape_prior(const db::KnitChart& chart);

struct ShapeTrial {
  double aspect = 0.0;
  bool held = true;        // the period held at the aspect (false: the generated tile's own)
  double objective = 0.0;  // g of the fit on that tile (+inf: failed)
  double r1 = 0.0;         // the radius the tile's crossings were built with [m]
  bool full_fit = false;   // the first trial's fit ran the global search
  double seconds = 0.0;
  std::string message;     // why it failed
};

struct ShapeFit {
  double aspect = 0.0, prior = 0.0, lower = 0.0, upper = 0.0;
  bool held = false;  // the winner is a held tile (false: the generated tile as the mechanics relaxed it)
  std::string prior_source;
  // Where g stays within twice the best's (the parabola through the best trial and its
  // neighbours); NaN on a side the trials leave open.
  double range_lower = 0.0, range_upper = 0.0;
  double wale_spacing = 0.0, course_spacing = 0.0;  // of the fitted tile [m]
  std::vector<ShapeTrial> trials;
  db::PeriodicTile tile;  // the fitted tile
  double seconds = 0.0;
};

// True when the problem's tile is generated from a knit with no gauge and the settings let its
// shape be fitted (not the thesis's method).
bool shape_is_fitted(const db::Fabric& fabric, const YarnFitSettings& yarn, const ShapeSearchSettings& shape);

// The yarn fit with the tile's shape fitted (the problem's tile is replaced by each trial's, and
// by the winner's at the end); `generated` is the knit's tile as generated. Throws
// an input Error as fit_yarn does; a trial whose tile cannot be made is a failed trial.
YarnFitResult fit_yarn_with_shape(YarnFitProblem& problem, const db::KnitSpec& knit, const db::PeriodicTile& generated,
                                  const YarnFitSettings& settings, const ShapeSearchSettings& shape, ShapeFit& fitted);

}  // namespace yarnfit::yarn
