#pragma once
// A shell model against a FAB record's own tests (issue 51; docs/fab.md): the stretch tests
// predicted by the in-plane law through the clamped-strip scene at their short, wide gauges,
// and the loop-method bends fitted for k_θ through the loop scene. Every loading branch of
// every cycle is compared; the relaxation branches are hysteresis no elastic model follows.
//
// Stretch: the force against (reading − the test's zero offset) at the samples past the taut
// length, the model run at a few stretches over that range and interpolated.
// Bends: a bend's zero is not known from its data (docs/fab.md), so each test gets its own
// offset, the mean of (reading − model): the fit pins k_θ by the curves' shapes and slopes,
// not by their level. k_θ is found by a scan over log k_θ then Brent's method, one per
// direction.

#include <string>
#include <vector>

#include "fabrics_db/records/fabric.hpp"
#include "shell_fit/core/shell_params.hpp"

namespace yarnfit::shell {

// One FAB test against a model.
struct FabTestError {
  std::string test;  // S1, S2, U1, D1, D2
  int samples = 0;   // loading-branch samples compared
  // Σ|model − measured| / Σ|measured| over those samples [%], measured with its zero (or,
  // for a bend, its fitted offset) removed.
  double force_pct = 0.0;
  double mean_abs_error = 0.0;  // [N]
  double offset = 0.0;          // the offset taken off the readings [N]
  // A stretch test's force_pct over the loading samples within the stretch its first two
  // cycles reach (the FAB cycles progressively: later ones reach further); NaN for a bend.
  double first_cycles_force_pct = 0.0;
  double max_curvature = 0.0;   // a bend's: the largest |κ| in the model's loops [1/m]
  bool converged = false;       // every simulated point converged
  std::string message;
};

struct FabStretchOptions {
  double target_edge = 5e-3;  // cell size of the strip's mesh [m]
  int points = 8;             // stretches simulated over the loading branches' range
};

// The stretch test `test` of direction `dir` predicted by `params` (every loading branch).
FabTestError predict_fab_stretch(const db::FabTest& test, db::Direction dir, const InplaneParams& params,
                                 const FabStretchOptions& options = {});

struct FabBendOptions {
  int points = 6;                 // clamp distances simulated over each test's loading range
  double ktheta_lower = 1e-9;     // search range of k_θ [N·m]
  double ktheta_upper = 1e-3;
  double tolerance = 2e-3;        // of log k_θ: the relative precision of the fitted k_θ
  int scan_points = 7;            // over log k_θ before Brent's method: one a decade by default
  int max_evaluations = 40;       // of the misfit (scan included), each a loop solve at every distance of every test
  // The loop bends cylindrically, so it is simulated on a strip this fraction of its length
  // wide and its force scaled to the strip's width.
  double width_over_length = 0.1;
};

struct FabBendFit {
  db::Direction direction = db::Direction::weft;
  double ktheta = 0.0;  // [N·m]
  // The k_θ the misfit may lie in before it doubles, bounded by the scan's points beyond
  // (a wide range: the bends pin k_θ weakly).
  double ktheta_low = 0.0, ktheta_high = 0.0;
  bool converged = false;
  bool on_bound = false;
  std::vector<FabTestError> tests;  // U1, D1, D2 as the record has them
  double force_pct = 0.0;           // over every bend sample of the direction
  double mean_abs_error = 0.0;      // [N]
  int evaluations = 0;
  double seconds = 0.0;
  std::string message;
  std::vector<std::string> effects;  // what the loop scene simulated
};

// k_θ of direction `dir` from its loop bends (the tests of kind up_bend / down_bend among
// `tests`), the in-plane law held.
FabBendFit fit_fab_bends(const std::vector<const db::FabTest*>& tests, db::Direction dir, const InplaneParams& inplane,
                         double areal_density, const FabBendOptions& options = {});

// The bend test `test` of direction `dir` predicted by `params` (its k_θ of that direction),
// its offset the best one (a held-out bend: its shape and slope predicted, not its level).
FabTestError predict_fab_bend(const db::FabTest& test, db::Direction dir, const ShellParams& params,
                              double areal_density, const FabBendOptions& options = {});

}  // namespace yarnfit::shell
