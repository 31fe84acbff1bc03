#pragma once
// How sharply the targets determine each fitted yarn parameter, measured around the fit.
//
// Stretch curves of a knit pin the parameters very unequally: a 10 % change of R1 raises g
// by orders of magnitude more than one of ks1 or ε̄s (docs/calibration.md), because the
// yarns' stretch is in series with the softer bending and contact of the loops. A user needs to
// know which fitted values the data stand behind, so every fit reports, per optimised
// parameter p_i (from 2 evaluations each of the local step's objective, in parallel):
//  * the one-at-a-time profile: g with p_i × 1/(1 + step) and × (1 + step), the others at
//    the fit (how much a change of p_i alone costs);
//  * the range over which p_i can move, the others re-fitted, before g rises by the fit's
//    own g: p_i / f … p_i · f with log f = sqrt(g_fit · [(JᵀJ)⁻¹]_ii), where J is the
//    Jacobian of the residual vector r (g = |r|²) in log p from the same evaluations (the
//    mean Gram matrix of the forward and backward differences: robust to kinks at the fit)
//    and the Gauss–Newton model of g. A parameter that trades off with others
//    (ks1 with ε̄s and kb, kb with kc1) has a range much wider than with the others held.
// Both are local estimates: the rest-shape heuristic switches between nearby equilibria, so
// g is not smooth at the percent level, and a difference over ±step can straddle a switch.

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "yarn_fit/fit/objective/yarn_objective.hpp"
#include "results/yarn_fit_file.hpp"
#include "swarm/parameter_space.hpp"

namespace yarnfit::yarn {

struct ParameterProfileEntry {
  std::string name;
  double value = 0.0;    // at the fit
  double g_lower = 0.0;  // g with this parameter / (1 + step), the others at the fit (+inf: failed)
  double g_upper = 0.0;  // and × (1 + step)
  // f ≥ 1: this parameter can move to value / f or value · f, the others re-fitted, before g
  // rises by g_fit (Gauss–Newton model); +inf when the residuals do not depend on it (or on
  // it independently of the others), NaN when a side failed.
  double range_factor = 0.0;
  double range_alone_factor = 0.0;  // the same with the others held at the fit
};

struct ParameterProfile {
  bool computed = false;
  // The ranges from the local step's exact Jacobian at the fit and the one-at-a-time g values
  // predicted by its Gauss–Newton model (profile_from_jacobian: no evaluations), rather than
  // from evaluations at ±step (profile_parameters).
  bool from_jacobian = false;
  std::string message;  // why some entries are incomplete (a side failed), or why none were computed
  double step = 0.0;
  double g_fit = 0.0;
  std::vector<ParameterProfileEntry> entries;
  int evaluations = 0;
  double seconds = 0.0;
};

// The range factors of the Gauss–Newton model of g = |r|² around a minimum where g = `g`,
// given JᵀJ with J = dr/d(log p): per parameter, f with log f = sqrt(g · [(JᵀJ)⁻¹]_ii) (the
// others re-fitted; +inf where JᵀJ is singular along it) and sqrt(g / (JᵀJ)_ii) (the others
// held).
struct GaussNewtonRange {
  double refitted = 0.0;
  double alone = 0.0;
};
std::vector<GaussNewtonRange> gauss_newton_ranges(const Eigen::MatrixXd& jtj, double g);

// Profiles each coordinate of `x_fit` (physical units, as ParameterSpace::from_unit gives;
// `to_params` maps a point to parameters) on `objective`, whose evaluation at the fit is
// `at_fit`. `step` > 0 (0.1: 10 %); threads 0: OpenMP's default.
ParameterProfile profile_parameters(const YarnObjective& objective, const swarm::ParameterSpace& space,
                                    const Eigen::VectorXd& x_fit, const ObjectiveResult& at_fit,
                                    const std::function<yarn::YarnParams(const Eigen::VectorXd&)>& to_params,
                                    double step, int threads);

// The same from the residuals r at the fit and their Jacobian J in log θ (one column per
// coordinate of the space), e.g. the Gauss–Newton local step's own: JᵀJ gives the ranges, and
// |r + J δ|² with δ = ∓log(1 + step) in one column the one-at-a-time g values (a model, not
// evaluations: exact for residuals linear in log θ).
ParameterProfile profile_from_jacobian(const swarm::ParameterSpace& space, const Eigen::VectorXd& x_fit,
                                       const Eigen::VectorXd& residuals, const Eigen::MatrixXd& jacobian_log,
                                       double step);

// As yarn_fit.json's `identifiability` holds it.
results::Identifiability to_record(const ParameterProfile& profile);

}  // namespace yarnfit::yarn
