#pragma once
// Rest-shape heuristic (thesis 6.5.2): alternate equilibrium solves at χ = 0 with resets of
// the rest lengths and rest curvatures to the current configuration, so that the tile's rest
// state is stable (small coarse stress) while the yarns stay close to the input geometry.
// Rest lengths stay within ±max_length_change of the input; every round's solve converges
// (the thesis runs only a few Newton iterations in early rounds: `early_rounds`). The final
// state is a converged equilibrium with the new rest shape, its period moved by a few chord
// steps towards zero normal rest stress (period_chord_steps).

#include <Eigen/Core>

#include "yarn_fit/periodic/yarn_system.hpp"
#include "yarn_fit/solver/equilibrium.hpp"

namespace yarnfit::yarn {

struct RestShapeOptions {
  // The coarse rest stress falls geometrically with the rounds (figures: docs/calibration.md,
  // "Moved from yarn_fit/homogenise/rest_shape.hpp").
  int rounds = 40;
  // Rounds with only `early_iterations` Newton iterations (the thesis's "few steps early").
  // Off by default: a solve cut short after a few iterations ends wherever its line searches
  // and contact-list rebuilds took it, so the rest shape, and every fit objective built on it,
  // jumps when a parameter changes by 1e-6; with every round converged the objective moves
  // smoothly, and the heuristic costs about the same (figures: docs/calibration.md).
  int early_rounds = 0;
  int early_iterations = 4;
  double max_length_change = 0.2;  // |L̄ / L̄_input − 1| ≤ this
  // Reset L̄ ← L̄ + ω (L − L̄) (and likewise κ̄). ω = 1 is the thesis's reset; ω ≈ 1.5 halves
  // the rest stress left after 40 rounds but loosens the tile further (its rest lengths move
  // further from the input's: docs/calibration.md).
  double over_relaxation = 1.0;
  // Final stage, the period chord steps: adjust the tile's period by a small symmetric
  // in-plane stretch (I + E) so that the coarse normal stress at χ = 0 falls to about a tenth
  // (the shear: see period_shear). The resets cannot remove the stress carried by contacts,
  // and each further round loosens the tile while the ratio of the rest stress to the stress
  // at 10 % stretch hardly falls; a nearly stress-free rest state is what the fit compares
  // the targets against (a fabric at rest carries no stress).
  // Chord-Newton steps on P(E) = 0 (numerics/roots/chord_newton.hpp, after 2 solves, 3 with
  // shear, for ∂P/∂E; 0: the stage is off and the period stays). Four steps leave about a
  // tenth of the stress. Solving further (Broyden's method to 1e-3 of it) leaves the tile
  // slack across: c* is then undetermined over a wide band, and the true parameters score far
  // worse on their own targets (figures: docs/calibration.md).
  // Not the rest-period relaxation (rest_period.hpp, `yarnfit fit --relax-period`,
  // ObjectiveOptions::rest_period), which minimises the tile's energy over the period until
  // the normal stress is within a tolerance, after this heuristic and off by default.
  int period_chord_steps = 4;
  double max_period_change = 0.1;  // |E_ij| ≤ this
  // Relax the period's shear E01 as well. Off by default: the tile is soft in shear at rest,
  // so zeroing a small shear stress takes a large E01, and E01 jumped whenever the rounds
  // above settled in a nearby equilibrium instead of another. Without it the true parameters
  // score better on their own targets and a default fit is faster; the shear stress left is
  // small (tests/yarn_fit, RestShapeLeavesLittleCoarseStress...; figures: docs/calibration.md).
  bool period_shear = false;
  EquilibriumOptions solve;  // its stress_tolerance is not used: every solve goes to the force tolerance
};

struct RestShapeResult {
  bool converged = false;             // the last (full) solve converged
  int rounds = 0;
  int newton_iterations = 0;
  Eigen::Matrix2d rest_stress = Eigen::Matrix2d::Zero();  // coarse stress P at χ = 0 [N/m]
  Eigen::Matrix2d stress_before_period = Eigen::Matrix2d::Zero();  // P before the period chord steps
  Eigen::Matrix2d period_stretch = Eigen::Matrix2d::Zero();  // E applied to the period
  double max_length_change = 0.0;     // max |L̄ / L̄_input − 1| after the heuristic
  int clamped_edges = 0;              // edges whose rest length sits on the ±bound
  double seconds = 0.0;
  EquilibriumResult last_solve;
};

// Edits the system's rest lengths and curvatures; `g` is the relaxed state at χ = 0 on return.
RestShapeResult relax_rest_shape(YarnSystem& system, Eigen::VectorXd& g,
                                 const RestShapeOptions& options = {});

// Resets rest lengths (clamped to the bound) and rest curvatures towards the configuration `g`
// at the system's current deformation (fully for omega = 1). Returns the number of clamped edges.
int reset_rest_shape(YarnSystem& system, const Eigen::VectorXd& g, double max_length_change, double omega = 1.0);

}  // namespace yarnfit::yarn
