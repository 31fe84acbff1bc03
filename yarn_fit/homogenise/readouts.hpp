#pragma once
// Homogenised read-outs of the periodic yarn simulation (thesis 6.5.1, 3.23):
//  * energy density Ψ = E / Ā (6.8) at equilibrium;
//  * stretch stress σ_s = dΨ/ds, analytic from the equilibrium state (6.10 / 3.23): at
//    equilibrium the fluctuation's own derivative drops out, so σ_s = ∂Ψ/∂s at fixed g;
//  * bending stress by central differences of the equilibrated Ψ in κ (as in the thesis);
//  * the zero-orthogonal-stress compression c*(s) = argmin_c Ψ(s, c), found either by a
//    bracketed root find on ∂Ψ/∂c = 0 (default, each evaluation warm-started) or by COBYLA
//    on Ψ(c) (NLopt, as in the thesis); both are exposed so they can be compared.
//
// Every read-out carries the equilibrium summaries it relied on; a failed solve makes the
// read-out fail with that status instead of returning a number.

#include <Eigen/Core>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "yarn_fit/periodic/yarn_system.hpp"
#include "yarn_fit/solver/equilibrium.hpp"

namespace yarnfit::yarn {

struct Sample {
  CoarseDeformation chi;
  bool ok = false;                   // every solve behind the numbers converged
  double energy_density = 0.0;       // Ψ [J/m²]
  double stress_s = 0.0;             // σ_s = dΨ/ds [N/m]
  double stress_c = 0.0;             // ∂Ψ/∂c [N/m] (0 at the zero-orthogonal-stress c)
  // solve_free_compression only: the slope ∂²Ψ/∂c² [N/m] of ∂Ψ/∂c between the search's last
  // two converged evaluations (0 when it made fewer or the slope was not positive); the next
  // search of a march starts with it (CompressionOptions::initial_slope).
  double stress_c_slope = 0.0;
  Eigen::Matrix2d coarse_stress = Eigen::Matrix2d::Zero();  // P (κ = 0) [N/m]
  int newton_iterations = 0;         // summed over all solves of the sample
  int solves = 0;
  double seconds = 0.0;
  EquilibriumResult last_solve;
  std::vector<std::string> effects;
  std::string message;               // why ok is false
  // solve_free_compression with CompressionOptions::band_stress > 0: the band of c around the
  // root in which |∂Ψ/∂c| ≤ band_stress (an end the search interval cut is that bound; NaN
  // when not read), and whether Ψ is flat in c there (band wider than ±flat_band): the
  // sample is then the equilibrium at the band's c of smallest |c|, a defined answer where
  // any c of the band is free of orthogonal stress.
  double band_lower = std::numeric_limits<double>::quiet_NaN();
  double band_upper = std::numeric_limits<double>::quiet_NaN();
  bool flat = false;
};

// Equilibrium at χ, warm-started from `g` (updated in place), then the read-outs.
Sample simulate_sample(YarnSystem& system, const CoarseDeformation& chi, Eigen::VectorXd& g,
                       const EquilibriumOptions& options = {});

enum class CompressionMethod { root_find, cobyla };

struct CompressionOptions {
  CompressionMethod method = CompressionMethod::root_find;
  double lower = -0.3;      // search interval for c
  double upper = 0.9;
  double tolerance = 1e-5;  // on c
  // Root find only: accept any evaluated c with |∂Ψ/∂c| ≤ this [N/m] (0: the exact root).
  // Where the fabric is slack across its width (small stretch), ∂Ψ/∂c stays within solver
  // noise of 0 over a wide band of c and the exact root moves by several percent for a tiny
  // change of the parameters; every c in that band is free of orthogonal stress to within
  // the tolerance, and the search keeps the first one it evaluates (a guess already inside
  // the band is kept as it is).
  double stress_tolerance = 0.0;
  double initial_step = 0.05;  // first bracketing step in c (a warm curve point may use less)
  // > 0: a known ∂²Ψ/∂c² [N/m] near the guess (from the previous point of a march): the first
  // step is then the Newton step −∂Ψ/∂c / slope instead of initial_step. 0: unknown.
  double initial_slope = 0.0;
  int max_evaluations = 60;
  double initial_guess = 0.0;
  // Root find only, > 0 [N/m]: read the band where |∂Ψ/∂c| ≤ band_stress (Sample::band_*),
  // from the slope at the root when it shows a band narrower than ±flat_band, else by a
  // search for each end; a band wider than that is flat (Sample::flat).
  double band_stress = 0.0;
  double flat_band = 0.05;
};

// c*(s) with Ψ minimal over c at chi's stretch, direction and curvature (chi.compression is
// ignored; the search starts at compression.initial_guess). The sample returned is the
// equilibrium at c*, with its solve count and summed Newton iterations. `g` carries the warm
// start in and the solution out.
Sample solve_free_compression(YarnSystem& system, CoarseDeformation chi, Eigen::VectorXd& g,
                              const CompressionOptions& compression = {},
                              const EquilibriumOptions& options = {});

// dΨ/dκ by central differences of equilibrated Ψ with step h [1/m] (0: 1e-3 / yarn radius).
// With parameters `wanted`, also dσ_κ/dθ: by the envelope theorem dΨ/dθ at each of the two
// equilibria is the energy's partial derivative at fixed state (the rest shape held), so
// dσ_κ/dθ = (∂Ψ/∂θ(κ + h) − ∂Ψ/∂θ(κ − h)) / 2h, the same difference of exact derivatives.
struct BendingSample {
  Sample centre;
  double stress_kappa = 0.0;  // [N] (J/m² per 1/m)
  Eigen::VectorXd d_stress_kappa;  // dσ_κ/dθ for `wanted` (empty without)
  bool ok = false;
  std::string message;
};
BendingSample simulate_bending(YarnSystem& system, const CoarseDeformation& chi,
                               Eigen::VectorXd& g, double step = 0.0,
                               const EquilibriumOptions& options = {},
                               std::span<const YarnParam> wanted = {});

}  // namespace yarnfit::yarn
