#pragma once
// Fitting the bending stiffnesses k_θ (weft, bias, warp) to a fabric's pear-loop tests by
// simulation in the loop (thesis 6.3.2; SPEC §3):
//
//   k_bending = argmin Σ_i (r(k_bending, d_i) − r_i)²
//
// Ceres least squares on log k_θ, 7 targets per measured direction evenly spread over
// d ∈ [3, 34] mm clipped to the measured range, r_i the measured aspect ratio interpolated
// linearly there. The in-plane parameters are given (from the in-plane fit) and held.
// Jacobians are exact: the pear-loop scene returns dr/dk_θ from its equilibrium Hessian.
//
// Which k_θ a test measures: the one its bent edges carry (PearLoopScene::governing_ktheta,
// weft for the weft test with BendingTerm's convention). A k_θ that no test measures is not
// identified: it is tied to the geometric mean of the fitted ones throughout the fit (so the
// small share it has in the other tests' diagonals is consistent), and listed in
// not_identified with its value. Without any bending test nothing is fitted.
//
// Start values come from the data: for each test, a log-space bracket search on the bending
// length ℓ (k_θ = ρ g ℓ³/2) matches the simulated r to the measured one at the middle target
// on a coarser mesh; r falls monotonically as ℓ grows (a stiffer strip is rounder), from the
// hanging hairpin (ℓ ≪ L) to the gravity-free elastica (ℓ ≫ L). Search bounds ℓ ∈ [L/100, 10 L],
// the top capped where the strip stops being thin against its membrane (B ≤ 1e-4 E L²,
// E = min(kxx, kyy)). A measured r below the elastica's (no k_θ can reach it: about 2.0 at
// d = 3 mm and 1.15 at 34 mm for L = 10 cm) ends on the upper bound, reported in at_bounds.
// When a trial of that search does not reach equilibrium before the bracket closes, the start
// is not the data's: the test starts from the last bending length tried (or the search bound
// it was heading for), and fallback_starts says so.

#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "fabrics_db/records/fabric.hpp"
#include "shell_fit/core/shell_params.hpp"
#include "numerics/progress.hpp"
#include "shell_fit/scenes/pear_loop.hpp"

namespace yarnfit::shell {

inline constexpr int k_bending_targets_per_direction = 7;
inline constexpr double k_bending_min_distance = 3e-3;   // [m]
inline constexpr double k_bending_max_distance = 34e-3;  // [m]
inline const char* const k_bending_names[3] = {"ktheta_weft", "ktheta_bias", "ktheta_warp"};

struct BendingFitOptions {
  double target_edge = 2.5e-3;  // mesh cell size of the scenes [m] (PearLoopSetup)
  int refinements = 0;
  int max_iterations = 40;
  int threads = 1;              // directions simulated in parallel
  double gravity = 9.81;        // [m/s²]
  // Called after every iteration and every trial of the start search.
  numerics::ProgressFn progress;
};

struct BendingDirectionFit {
  db::Direction direction = db::Direction::weft;
  int parameter = 0;                          // index of the k_θ this test measures
  std::vector<double> clamp_distance;         // targets d_i [m]
  std::vector<double> measured_aspect_ratio;  // r_i interpolated at d_i
  std::vector<double> simulated_aspect_ratio;  // at the fitted k_θ; empty when the final evaluation failed
  double max_curvature = 0.0;                 // largest |κ| in the final loops [1/m]
};

struct BendingFitResult {
  bool converged = false;
  std::string message;   // Ceres' termination, or why the fit failed / was not run
  BendingParams start;   // data-based starting values
  BendingParams params;
  std::vector<std::string> identified;
  std::vector<std::string> not_identified;  // "ktheta_bias: no bias bending test (…)"
  std::vector<BendingDirectionFit> directions;
  // The shell metric (reports/metrics/error_metrics.hpp) of the aspect ratio over all
  // targets [%]; NaN when the final evaluation failed or nothing was fitted (errors_reason).
  double bending_pct = std::numeric_limits<double>::quiet_NaN();
  std::string errors_reason;  // why there is no bending_pct (empty when there is)
  // Tests whose start did not come from the data because a trial of the start search failed:
  // "weft test (ktheta_weft): ..." with the bending length it started from instead.
  std::vector<std::string> fallback_starts;
  int iterations = 0;
  int simulations = 0;       // pear-loop runs (each over one test's distances)
  double seconds = 0.0;
  std::vector<std::string> at_bounds;  // parameters that ended on a search bound
  // The search range of every fitted k_θ, {lower, upper} [N·m] (searched in log space).
  std::map<std::string, std::pair<double, double>> bounds;
  // Largest curvature per k_θ slot (weft, bias, warp) in the final loops; absent for slots no
  // test measures. Feeds TargetRanges::max_curvature of the uniform targets.
  std::optional<double> max_curvature[3];
  // What the pear-loop scenes simulated (the names their runs report).
  std::vector<std::string> effects = PearLoopRun{}.effects;
};

// The 7 targets of one test: d evenly over [3, 34] mm ∩ the measured range (the whole
// measured range if they do not overlap), r interpolated linearly.
BendingDirectionFit make_bending_targets(const db::BendingTest& test);

// The scene of one test: its swatch, the material frame of its direction, the fabric's
// density. Throws an input Error for a non-positive density.
PearLoopSetup pear_loop_setup(const db::BendingTest& test, double areal_density, double target_edge,
                              int refinements, double gravity = 9.81);

// Data-based k_θ per slot (weft, bias, warp) and the slots measured; see above.
BendingParams initial_bending_guess(const db::Fabric& fabric, const InplaneParams& inplane,
                                    const BendingFitOptions& options);

// Throws an input Error when the fabric has bending tests but no areal density (the
// pear loop hangs under gravity). A fabric without bending tests returns converged = false,
// all three k_θ in not_identified and params all zero: there is nothing to fit.
BendingFitResult fit_bending(const db::Fabric& fabric, const InplaneParams& inplane,
                             const BendingFitOptions& options);

}  // namespace yarnfit::shell
