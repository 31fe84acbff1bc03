#pragma once
// The local step of the yarn fit from one start (thesis 6.5.3's refinement of the swarm's best),
// by one of three methods:
//  * gauss_newton (default, issue 33): the alternation of rest state and Gauss–Newton on exact
//    Jacobians (alternation.hpp);
//  * implicit_filtering: Gauss–Newton on stencil differences whose scale shrinks
//    (swarm/implicit_filtering.hpp), the default before issue 33;
//  * cobyla: the thesis's COBYLA (swarm/cobyla.hpp).

#include <Eigen/Core>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "yarn_fit/fit/alternation.hpp"
#include "yarn_fit/fit/objective/yarn_objective.hpp"
#include "swarm/implicit_filtering.hpp"
#include "swarm/parameter_space.hpp"

namespace yarnfit::yarn {

enum class LocalMethod {
  // The thesis's alternation as the outer loop — the rest state relaxed at the round's
  // parameters and held — with Gauss–Newton (Ceres' Levenberg–Marquardt) on the exact residual
  // Jacobian within each round, a trust region across rounds and a secant estimate of the rest
  // state's own dependence (alternation.hpp).
  gauss_newton,
  // Gauss–Newton steps on stencil differences of the residuals, the stencil halving from 2 % of
  // every range until a stencil of 0.5 % finds nothing better than its centre. Before exact
  // Jacobians this was the default: the objective is rough below about 1e-3 of the ranges (the
  // c* searches and the rest shape settle on one of several nearby equilibria) but smooth in its
  // trend. COBYLA's linear models stall there, far from a known truth (docs/calibration.md).
  implicit_filtering,
  cobyla,  // the thesis's local step (6.5.3), NLopt's COBYLA (swarm/cobyla.hpp)
};
[[nodiscard]] const char* to_string(LocalMethod method);  // "gauss-newton", "implicit-filtering", "cobyla"
[[nodiscard]] std::optional<LocalMethod> local_method_from_string(std::string_view name);

struct LocalStepSettings {
  LocalMethod method = LocalMethod::gauss_newton;
  AlternationSettings alternation;  // gauss_newton (its fallback: implicit filtering's budget)
  int evaluations = 150;            // implicit filtering and COBYLA: the budget
  double cobyla_initial_step = 0.05;  // a fraction of each range
  double initial_scale = 0.02;        // implicit filtering's first stencil half-width (unit cube)
  double min_scale = 0.003;           // and where it stops
  int threads = 0;
};

// What the local step did from one start, whichever optimiser ran it.
struct LocalStepSummary {
  LocalMethod method = LocalMethod::gauss_newton;
  bool ran = false;
  std::string status;      // the optimiser's status, in words
  bool converged = false;  // stopped at its own tolerance rather than at a budget
  Eigen::VectorXd start_point, best_point;  // caller's coordinates
  double best_value = std::numeric_limits<double>::infinity();
  double start_value = std::numeric_limits<double>::infinity();
  int evaluations = 0;
  int failed = 0;
  int iterations = 0;        // implicit filtering: stencils; Gauss–Newton: rounds
  double final_scale = 0.0;  // implicit filtering: stencil half-width when it stopped (unit cube)
  std::vector<swarm::ImplicitFilteringIteration> history;  // implicit filtering: per iteration
  std::vector<swarm::FailedEvaluation> failures;
  AlternationSummary alternation;  // Gauss–Newton: rounds, fallback, linearisation at the best
  double seconds = 0.0;
  std::string report;  // one line: the optimiser's own brief report

  [[nodiscard]] bool usable() const { return std::isfinite(best_value); }
};

// Fills a Gauss–Newton summary's fields from its `alternation` (a run read back from a checkpoint).
void take_alternation(LocalStepSummary& out);

// Progress after every evaluation: evaluations so far and the best g.
using LocalProgress = std::function<void(int evaluations, double best)>;

LocalStepSummary run_local_step(const YarnObjective& objective, const swarm::ParameterSpace& space,
                                const PointToParams& to_params, const Eigen::VectorXd& start,
                                const LocalStepSettings& settings, const LocalProgress& progress = {});

}  // namespace yarnfit::yarn
