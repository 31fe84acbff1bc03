#pragma once
// Yarn-level calibration (thesis 6.5.3; SPEC §3 "Parameters"): find p = {ks1, ε̄s, kb, R1, kc1}
// whose periodic yarn simulations reproduce the uniform targets, by a particle swarm on the
// objective with few stretch samples (7 per direction) followed by a local step from the
// swarm's best with many (20), every candidate going through the rest-shape heuristic first
// (the alternation of 6.5.3, inside YarnObjective). The local step is implicit filtering
// with Gauss–Newton steps by default, or COBYLA as in the thesis (LocalMethod).
//
// Parameter space (SPEC §3): R1 ∈ [0.5, 1.5] R_est; kb ∈ [1e-3, 10]·ks2 R_est²/4;
// ks1 ∈ [1e-3, 1]·ks2; ε̄s ∈ [1e-4, 0.15]; kc1 ∈ [1e-2, 1e2]·ks2/R_est; ks1, ε̄s, kb, kc1 in log
// space (ε̄s too, unlike SPEC's linear [0, 0.15]: see yarn_parameter_space);
// ks2, kc2, R2 fixed from the fabric (ParameterScales). The ablation `linear_stretch` fixes
// ks1 = ks2 and ε̄s = 0 (thesis Fig. 6.16) and fits {kb, R1, kc1} only.

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "results/yarn_fit_file.hpp"

#include "yarn_fit/fit/alternation.hpp"
#include "yarn_fit/fit/global_search.hpp"
#include "yarn_fit/fit/local_step.hpp"
#include "yarn_fit/fit/parameter_profile.hpp"
#include "yarn_fit/fit/objective/bending_check.hpp"
#include "yarn_fit/fit/objective/yarn_objective.hpp"
#include "fabrics_db/problems.hpp"
#include "numerics/progress.hpp"
#include "swarm/cobyla.hpp"
#include "swarm/implicit_filtering.hpp"
#include "swarm/particle_swarm.hpp"
#include "yarn_fit/model/yarn_params.hpp"

namespace yarnfit::yarn {

struct YarnFitSettings {
  // The global step (global_search.hpp): staged (default) or the thesis's swarm.
  GlobalMethod global_method = GlobalMethod::staged;
  StagedSearchSettings staged;
  // The thesis's swarm (global_method swarm): particles × iterations on swarm_samples.
  int particles = 64;
  int iterations = 10;
  int swarm_samples = 7;   // stretch samples per direction in the swarm
  int local_samples = 12;  // in the local step, the rescore and the final evaluation
  // Where c* is solved, per stage: 0 (default) at every stretch sample, by continuation
  // along s; N ≥ 2 at N evenly spread samples with c linear in between (the objective's
  // compression_nodes; 2 is the thesis's both-ends scheme of 6.5.3). The two-node interpolant
  // is far enough off the true c* that the true parameters and a wrong basin score alike, so
  // a swarm on that objective cannot tell them apart; with c* at every sample it can
  // (figures: docs/calibration.md).
  int swarm_compression_nodes = 0;
  int local_compression_nodes = 0;
  std::uint64_t seed = 1;
  int threads = 0;         // 0: OpenMP default
  bool swarm = true;           // false (--no-swarm): the local step alone, from `start` or the middle of the bounds
  // Where the local step starts without the swarm (--start: refining an earlier fit or a
  // guess); ignored while `swarm` is on. Its optimised parameters must lie inside the bounds
  // (with linear_stretch, ks1 and ε̄s are not used).
  std::optional<yarn::YarnParams> start;
  bool linear_stretch = false; // ks1 = ks2, ε̄s = 0 (--linear-stretch)
  bool rest_shape = true;      // false (--no-rest-shape): the tile's own rest shape
  // A swarm candidate stops simulating once its g reaches its particle's best so far
  // (YarnObjective::evaluate's cutoff). The run is the same as without (swarm bests, the
  // local step, the result); false evaluates every candidate in full (for studies of the
  // objective over the swarm's candidates).
  bool swarm_cutoff = true;
  LocalMethod local_method = LocalMethod::gauss_newton;
  AlternationSettings alternation;  // gauss_newton: rounds, iterations per round, fallback
  // Budget of the local step (objective evaluations). Implicit filtering needs 13 per
  // iteration (a stencil of 10 and up to 3 trials) and usually converges within 150.
  int local_evaluations = 150;
  double local_initial_step = 0.05;  // COBYLA's first step, as a fraction of each range
  double local_initial_scale = 0.02;  // implicit filtering's first stencil half-width (unit cube)
  // Converged once the half-width falls below this: after the stencils of 2, 1 and 0.5 %; the
  // 0.25 % stencil found nothing better in a recovery fit (docs/calibration.md).
  double local_min_scale = 0.003;
  // The fit's checkpoint (fit_checkpoint.hpp; the swarm stages write <checkpoint>.<stage>
  // beside it); empty: none.
  std::filesystem::path checkpoint;
  bool resume = false;               // continue from `checkpoint` (and its stage files)
  // Polled after every swarm iteration and local run: false stops the fit there, to be resumed
  // from the checkpoint (YarnFitResult::stopped). Empty: never stop.
  std::function<bool()> keep_going;
  // Curvatures per direction at which the fitted model is bent for the bending error
  // (bending_check.hpp; only directions with bending targets); 0 skips the check.
  int bending_points = 5;
  // How sharply the targets determine each fitted parameter (parameter_profile.hpp): the
  // local objective with each parameter moved by this relative step both ways around the
  // fit, 2 evaluations per parameter; 0 skips it (--no-profile).
  double profile_step = 0.1;
  ObjectiveOptions objective;        // samples and rest_shape are set from the fields above
  // Progress per swarm iteration (stage "contact", "all" or "swarm", the iterations planned),
  // after the rescore, and per local evaluation (stage "local"): best objective so far,
  // seconds since the start of the fit.
  numerics::ProgressFn progress;

  // Every invalid field, each named as above ("particles", "swarm_samples", …); empty when
  // the settings are usable. Checked before any work starts.
  [[nodiscard]] db::Problems problems() const;
};

struct YarnFitResult {
  bool ok = false;
  std::string message;              // why !ok
  bool stopped = false;             // keep_going asked to stop: resume from the checkpoint
  yarn::YarnParams params;          // best found (complete, SI)
  ObjectiveResult final;            // the best re-evaluated with local_samples per direction
  std::vector<std::string> on_bound;  // fitted parameters within 1e-3 of a bound (unit cube)
  BendingCheck bending;             // the fitted model against the bending targets (not fitted)
  ParameterProfile profile;         // how sharply the targets pin each fitted parameter
  std::vector<GlobalStage> global;  // the global step's stages, in order (empty without one)
  swarm::SwarmSummary swarm;        // the last swarm stage (empty history when none ran)
  LocalStepSummary local;           // the local run whose result won
  std::vector<LocalStepSummary> local_runs;  // every local run, in the order of their starts
  int evaluations = 0;              // objective evaluations, both stages
  int swarm_stopped = 0;            // swarm candidates stopped at their particle's best (after a resume: since it)
  double seconds_swarm = 0.0;       // the global step
  double seconds_local = 0.0;
  double seconds_total = 0.0;
  // The optimised parameters and their bounds (the search space of these scales).
  std::vector<swarm::Parameter> bounds;
  // What the simulations included: the yarn energies, and "co-rotation" when the bending
  // check bent the tile (κ ≠ 0, the co-rotated periodic conditions of 3.2.2).
  std::vector<std::string> effects;
};

// The optimised coordinates and their bounds for these scales.
swarm::ParameterSpace yarn_parameter_space(const yarn::ParameterScales& scales, bool linear_stretch);
// A point of that space as complete parameters (fixed ones from the scales).
yarn::YarnParams params_from_point(const Eigen::VectorXd& x, const yarn::ParameterScales& scales,
                                   bool linear_stretch);
Eigen::VectorXd point_from_params(const yarn::YarnParams& p, bool linear_stretch);

// Runs the calibration. Throws an input Error for invalid settings or targets; a
// calibration whose every candidate failed, or whose best parameters fail on re-evaluation,
// returns ok = false with the reason, and then `final` holds no directions (no errors, no
// curves: nothing that belongs to other parameters).
YarnFitResult fit_yarn_params(const yarn::YarnTile& tile, const std::vector<db::DirectionTargets>& targets,
                              const yarn::ParameterScales& scales, const YarnFitSettings& settings);

// What yarn_fit.json holds (SPEC §5; results/yarn_fit_file.hpp writes it): params {ks1, eps_s, kb, R1, kc1, ks2, kc2, R2}, errors
// {stress_comfort_pct, stress_full_pct, compression_pct, bending_pct (null without bending
// targets or when the check was skipped or failed)} (all null, with errors_reason, when the
// fit failed), evaluations, timing_s, effects, plus per-direction errors, the final curves
// (`curves`, in direction order), on_bound, bounds {name: {lower, upper, log}},
// identifiability (the parameter profile), settings (after a --resume the checkpoint's
// particles and iterations) and stage summaries with their one-line reports.
results::YarnFitFile to_file(const YarnFitResult& result, const YarnFitSettings& settings);

}  // namespace yarnfit::yarn
