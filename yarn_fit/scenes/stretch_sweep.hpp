#pragma once
// Uniform uniaxial stretch curve of a periodic tile (SPEC §4 "uniform yarn stretch", thesis
// 6.5.1): the tile is stretched along one direction through increasing stretches s, each at
// its zero-orthogonal-stress compression c*(s) (readouts.hpp), in-plane (κ = 0, no
// co-rotation). Point i is warm-started from point i−1, moved by a first-order predictor: that
// state is the anchor of every compression trial and its c* is the first trial. A point that fails is recorded
// (Sample::ok false with its reason) and the sweep carries on from the last converged point.

#include <Eigen/Core>
#include <cstddef>
#include <functional>
#include <vector>

#include "yarn_fit/homogenise/readouts.hpp"

namespace yarnfit::yarn {

struct StretchSweepOptions {
  // initial_guess is used for the first point only; band_stress 0 reads each point's
  // compression band at the solve's stress tolerance (default_stress_tolerance), < 0 not at all.
  CompressionOptions compression;
  EquilibriumOptions solve;
  // Each point after a converged one starts from the last state moved along the equilibrium's
  // own tangent dg*/ds to the new stretch at the last c* (a first-order predictor;
  // docs/yarn-solve.md has what it saves); a point that fails from there is solved again
  // from the last state. false: from the last state as it is.
  bool predictor = true;
  // Called after each point with its index, its sample and the state it ended in (the
  // point's equilibrium at sample.chi when sample.ok, else the warm start the next point
  // will use). The system's current deformation is not necessarily sample.chi.
  std::function<void(std::size_t, const Sample&, const Eigen::VectorXd&)> on_point;
};

struct StretchSweep {
  std::vector<Sample> points;  // one per stretch, in order; chi.compression = c* when ok
  int failures = 0;            // points with ok == false
  int newton_iterations = 0;   // summed over every solve of every point
  int solves = 0;
  double seconds = 0.0;
  [[nodiscard]] bool ok() const { return failures == 0; }
};

// Moves the equilibrium `g` at `from` to first order towards `to`: g + (dg*/dF) ΔF, with dg*/dF
// the equilibrium's own sensitivity (sensitivity.hpp: one more assembly and factorisation at
// `from`; the system is left at `from`). False, with `g` as it was, where the sensitivity cannot
// be had (a Hessian not definite on the constraints).
bool predict_equilibrium(YarnSystem& system, const CoarseDeformation& from, const CoarseDeformation& to,
                         Eigen::VectorXd& g);

// `points` stretches evenly spaced over [0, max_stretch], both ends included.
// Throws an input Error for points < 2 or a non-finite max_stretch ≤ −1.
std::vector<double> even_stretches(double max_stretch, int points);

// Sweeps `stretches` (in the order given) along the direction `angle` [rad from the weft].
// `g` carries the warm start of the first point in and the last converged state out.
StretchSweep sweep_stretch(YarnSystem& system, double angle, const std::vector<double>& stretches,
                           Eigen::VectorXd& g, const StretchSweepOptions& options = {});

}  // namespace yarnfit::yarn
