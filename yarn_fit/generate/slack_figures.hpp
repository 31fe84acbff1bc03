#pragma once
// Issue 37's figures for one tile: the 0–22 % free-compression sweeps (23 points) in weft,
// bias and warp from its rest state; the points converged, the Newton iterations per point
// (every solve of the point's compression search) and the energy–stress consistency
// |ΔΨ − ½(σ_i + σ_{i−1}) Δs| / |ΔΨ| over the intervals with s ≥ 5 % (at the free compression
// dΨ/ds = σ_s, so the trapezoid of σ_s must give the energy's change). bench_yarn_fit's
// `slack` table prints them; the slack tests hold every reproducer to the goals.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "yarn_fit/periodic/yarn_system.hpp"
#include "yarn_fit/scenes/stretch_sweep.hpp"

namespace yarnfit::yarn {

struct SlackGoals {
  int median_iterations = 30;
  int max_iterations = 200;
  double consistency_median = 0.01;
  double consistency_90th = 0.05;
};

struct SlackDirection {
  std::string direction;  // weft, bias, warp
  StretchSweep sweep;
};

struct SlackFigures {
  std::vector<SlackDirection> directions;
  int points = 0;
  int converged = 0;
  std::vector<double> iterations;   // per point, all directions
  std::vector<double> consistency;  // per interval with s ≥ 5 %, all directions
  double seconds = 0.0;

  [[nodiscard]] double median_iterations() const;
  [[nodiscard]] double max_iterations() const;
  [[nodiscard]] double consistency_median() const;
  [[nodiscard]] double consistency_90th() const;
  // Every point converged and every figure within the goals.
  [[nodiscard]] bool meets(const SlackGoals& goals = {}) const;
};

// The q-quantile of `values` (nearest rank; 0 for none).
[[nodiscard]] double quantile(std::vector<double> values, double q);

// Sweeps `tile` (already at its rest shape, `rest` its relaxed state at χ = 0) in the three
// directions, each from the rest state.
SlackFigures sweep_slack_tile(const YarnTile& tile, const YarnParams& params, const Eigen::VectorXd& rest);

}  // namespace yarnfit::yarn
