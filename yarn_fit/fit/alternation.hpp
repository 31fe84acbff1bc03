#pragma once
// The local step of the yarn fit (issue 33): the thesis's alternating rest-shape heuristic
// (6.5.2–6.5.3) as the outer loop, Gauss–Newton within each round.
//
// The point θ_k has its rest state, relaxed there from the tile as read (rest_state.hpp), and
// its g on it from that state's own samples, which is bitwise YarnObjective::evaluate(θ_k): the
// g that the swarm and the reports use. Round k holds that rest state, and Ceres'
// Levenberg–Marquardt minimises g on it with the exact residual Jacobian
// (YarnObjective::evaluate_at_rest: sensitivities at every sample), each evaluation starting its
// samples where the best evaluation so far left them, so that the run follows one branch of the
// tile's equilibria. Holding the rest state is what lets the Jacobian leave the rest shape's own
// dependence on θ out honestly; relaxing it again at the run's result puts it back: that point
// becomes θ_{k+1} if its own g is lower. The held rest state is a good model of g only near θ_k
// (a run that moved far lowered the held g while the point's own g rose: docs/calibration.md),
// so each run stays inside a box around θ_k that grows after a step the held model predicted
// well and shrinks after one it did not: a trust region on the alternation. The model is the
// held residuals plus B (u − u_k), B the rest state's own contribution to the Jacobian, learnt
// by Broyden updates from short rounds, and measured by forward differences (one relaxation per
// parameter) at the point where a round's model mispredicted; a rejected round that measured it
// does not count towards the fallback. The rounds end when a run from θ_k no longer moves it
// (the alternation's fixed point: Jᵀr = 0 with the rest state held at θ_k itself), when the box
// has shrunk below `move_tolerance`, or when they run out. After `failures_before_fallback`
// rounds in a row without a lower g (or with Ceres failing) the step falls back to implicit
// filtering from the point (swarm/implicit_filtering.hpp) and says so.
//
// The same Jacobian gives the identifiability profile (parameter_profile.hpp) without further
// evaluations: it is kept, in log θ, with the residuals of the best point.

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "yarn_fit/fit/objective/yarn_objective.hpp"
#include "fabrics_db/problems.hpp"
#include "swarm/implicit_filtering.hpp"
#include "swarm/parameter_space.hpp"

namespace yarnfit::yarn {

struct AlternationSettings {
  int max_rounds = 8;               // rest states relaxed (and Gauss–Newton runs) at most
  int iterations_per_round = 6;     // Ceres iterations per round
  double initial_radius = 0.1;      // the first round's box half-width (unit cube)
  // Rounds that moved at most this far (unit cube) update the secant estimate of the rest
  // state's dependence on θ (0: never); longer moves see more than its linear part.
  double secant_move = 0.03;
  // After a round whose trial its model did not predict (rejected, or accepted with less than
  // a quarter of the predicted decrease), the rest state's own derivative is measured at the
  // current point: forward differences of the re-relaxed residuals, this far apart (unit cube;
  // 0: never). It replaces the secant estimate, so the next round's model is right to first
  // order in every direction, not only along the rounds' moves. On tight woven tiles the rest
  // state moves with θ so much that a model without it fails within a few rounds
  // (docs/calibration.md, issue 49).
  double rest_difference_step = 1e-3;
  double move_tolerance = 1e-3;     // converged once a round moves every coordinate by less (unit cube)
  int failures_before_fallback = 2; // failed rounds in a row before implicit filtering takes over
  swarm::ImplicitFilteringSettings fallback;  // its max_evaluations is the fallback's budget

  // Every invalid field, under its name ("fallback.shrink" for the fallback's); empty when
  // valid.
  [[nodiscard]] db::Problems problems() const;
};

struct AlternationRound {
  int round = 0;              // from 1
  double g_start = 0.0;       // g(θ_k) on its own rest state (= YarnObjective::evaluate)
  double g_end = 0.0;         // the round's best on the held rest state
  double g_true = 0.0;        // g at that point on its own rest state (+inf when it failed)
  bool accepted = false;      // g_true < g_start: the point moved there
  double move = 0.0;          // largest change of a coordinate over the round (unit cube)
  int evaluations = 0;
  int iterations = 0;         // Ceres iterations
  std::string termination;    // Ceres' termination, or why the round failed
  bool failed = false;
  // After the round: the rest state's derivative measured at the current point (one relaxation
  // per coordinate, counted in `evaluations`).
  bool rest_derivative_measured = false;
  double seconds = 0.0;
};

struct AlternationSummary {
  bool ok = false;                // a best point with a finite g exists
  std::string message;
  Eigen::VectorXd best_point;     // caller's coordinates
  double best_value = 0.0;        // its g (YarnObjective::evaluate)
  double start_value = 0.0;
  std::vector<AlternationRound> rounds;
  bool converged = false;         // stopped because the parameters stopped moving
  double last_move = 0.0;
  int evaluations = 0;
  int failed_evaluations = 0;
  bool fell_back = false;         // implicit filtering took over
  std::string fallback_reason;
  swarm::ImplicitFilteringSummary fallback;
  // At the best point, on its own rest state: r and dr/d log θ (one column per coordinate), for
  // the identifiability profile. Empty when the best point came from the fallback.
  Eigen::VectorXd residuals;
  Eigen::MatrixXd jacobian_log;
  double seconds = 0.0;

  [[nodiscard]] std::string brief_report() const;
};

// θ for a point of the space (complete parameters: the fixed ones from the fabric).
using PointToParams = std::function<yarn::YarnParams(const Eigen::VectorXd&)>;
// After every evaluation: evaluations so far and the best g seen on a held rest state.
using AlternationProgress = std::function<void(int evaluations, double best)>;

// The space's parameter names must be YarnParams keys (yarn_param_from_string). Throws
// an input Error for invalid settings, a start outside the bounds or an unknown name;
// numerical trouble is reported in the summary.
AlternationSummary run_alternation(const YarnObjective& objective, const swarm::ParameterSpace& space,
                                   const PointToParams& to_params, const Eigen::VectorXd& start,
                                   const AlternationSettings& settings, const AlternationProgress& progress = {});

}  // namespace yarnfit::yarn
