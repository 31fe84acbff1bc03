#pragma once
// The shared stockinette fixture of the yarn tests that run on the real tiles in ../shared
// (skipped without them, failed under CI=true).

#include <gtest/gtest.h>

#include <Eigen/SparseCore>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "fabrics_db/tile/periodic_tile.hpp"
#include "tests/test_support.hpp"
#include "yarn_fit/homogenise/readouts.hpp"
#include "yarn_fit/homogenise/rest_shape.hpp"
#include "yarn_fit/periodic/yarn_system.hpp"

namespace yarnfit::yarn::fixtures {

inline const std::string kPatterns = std::string(YARNFIT_SHARED_DIR) + "/data/patterns/";

inline db::PeriodicTile load_tile(const std::string& name) {
  db::Problems problems;
  auto tile = db::read_pyp(kPatterns + name, problems);
  if (!tile) throw std::runtime_error(problems.to_string());
  return *tile;
}

inline YarnParams params_for(const db::PeriodicTile& tile) {
  const auto facts = db::compute_tile_facts(tile);
  return default_params({400.0, facts.r_est});
}

inline double rel(double a, double b) { return std::abs(a - b) / std::max(std::abs(b), 1e-300); }

// Directional central differences of the assembled energy and gradient, best over a step
// sweep, against the analytic gradient and Hessian.
inline void expect_system_derivatives(YarnSystem& sys, const Eigen::VectorXd& g, const std::string& label) {
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  Eigen::VectorXd grad;
  sys.energy_gradient(g, grad);
  YarnSystem::Triplets t;
  sys.hessian(g, t, false);
  Eigen::SparseMatrix<double> h(sys.dof_count(), sys.dof_count());
  h.setFromTriplets(t.begin(), t.end());
  for (int trial = 0; trial < 3; ++trial) {
    Eigen::VectorXd d(sys.dof_count());
    for (int i = 0; i < d.size(); ++i) d[i] = normal(rng);
    d *= sys.tile().radius / d.norm();
    const double slope = grad.dot(d);
    const Eigen::VectorXd hd = h * d;
    double best_g = 1e300, best_h = 1e300;
    for (double step : {1e-2, 1e-3, 1e-4, 1e-5, 1e-6}) {
      const double fd = (sys.energy(g + step * d) - sys.energy(g - step * d)) / (2 * step);
      best_g = std::min(best_g, std::abs(fd - slope) / std::max(std::abs(slope), 1e-300));
      Eigen::VectorXd gp, gm;
      sys.energy_gradient(g + step * d, gp);
      sys.energy_gradient(g - step * d, gm);
      const Eigen::VectorXd fdh = (gp - gm) / (2 * step);
      best_h = std::min(best_h, (fdh - hd).lpNorm<Eigen::Infinity>() / hd.lpNorm<Eigen::Infinity>());
    }
    EXPECT_LT(best_g, 1e-6) << label << " gradient, direction " << trial;
    EXPECT_LT(best_h, 1e-6) << label << " Hessian, direction " << trial;
  }
}

class StockinetteSystem : public ::testing::Test {
 protected:
  void SetUp() override {
    YARNFIT_REQUIRE_SHARED(kPatterns + "stockinette.pyp");
    tile = load_tile("stockinette.pyp");
    params = params_for(tile);
  }
  db::PeriodicTile tile;
  YarnParams params;
};

// The equilibrium of a fresh tile (rotated in-plane by `rotation`) at χ, from the affine state.
inline Sample relaxed(const db::PeriodicTile& t, const YarnParams& p, const CoarseDeformation& chi,
               double rotation = 0.0) {
  YarnSystem sys(rotated_tile(make_yarn_tile(t), rotation), p);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(sys.dof_count());
  EquilibriumOptions o;
  o.force_tolerance = 1e-11 * p.ks2;
  return simulate_sample(sys, chi, g, o);
}

}  // namespace yarnfit::yarn::fixtures
