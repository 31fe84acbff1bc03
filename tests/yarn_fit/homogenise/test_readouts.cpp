// Homogenised read-outs (yarn_fit/homogenise/readouts.hpp) on the real stockinette tile:
// analytic against finite-difference stress, the two zero-orthogonal-stress methods, the
// stress-tolerance band, and the κ → 0 limit of the curved map.

#include <gtest/gtest.h>

#include <Eigen/SparseCore>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "tests/yarn_fit/yarn_fixtures.hpp"

namespace yarnfit::yarn {
namespace {

using namespace fixtures;

TEST_F(StockinetteSystem, AnalyticStretchStressMatchesCentralDifferencesOfPsi) {
  for (const double angle : {weft_angle(), warp_angle()}) {
    const double s = 0.2, h = 2e-3;
    const Sample mid = relaxed(tile, params, {s, 0.0, 0.0, angle});
    const Sample up = relaxed(tile, params, {s + h, 0.0, 0.0, angle});
    const Sample down = relaxed(tile, params, {s - h, 0.0, 0.0, angle});
    ASSERT_TRUE(mid.ok && up.ok && down.ok);
    const double fd = (up.energy_density - down.energy_density) / (2 * h);
    EXPECT_LT(rel(mid.stress_s, fd), 0.01) << "angle " << angle << ": analytic " << mid.stress_s
                                           << " N/m, central differences " << fd << " N/m";
  }
}

TEST_F(StockinetteSystem, RootFindAndCobylaAgreeOnTheZeroOrthogonalStressCompression) {
  YarnSystem sys(make_yarn_tile(tile), params);
  Eigen::VectorXd g1 = Eigen::VectorXd::Zero(sys.dof_count());
  Eigen::VectorXd g2 = g1;
  const CoarseDeformation chi{0.2, 0.0, 0.0, weft_angle()};
  CompressionOptions root;
  const Sample a = solve_free_compression(sys, chi, g1, root);
  CompressionOptions cobyla;
  cobyla.method = CompressionMethod::cobyla;
  cobyla.tolerance = 1e-5;
  const Sample b = solve_free_compression(sys, chi, g2, cobyla);
  ASSERT_TRUE(a.ok && b.ok) << a.message << b.message;
  EXPECT_NEAR(a.chi.compression, b.chi.compression, 1e-3);
  EXPECT_LT(std::abs(a.stress_c), 1e-3 * std::abs(a.stress_s));
  std::printf("c* root find %.6f (%d solves), COBYLA %.6f (%d solves)\n", a.chi.compression,
              a.solves, b.chi.compression, b.solves);
}

// With a stress tolerance the root find stops at the first c it evaluates inside the band
// |∂Ψ/∂c| ≤ tolerance; a guess already inside is kept.

TEST_F(StockinetteSystem, CompressionStressToleranceStopsInsideTheBandNearTheGuess) {
  YarnSystem sys(make_yarn_tile(tile), params);
  const Eigen::VectorXd g0 = Eigen::VectorXd::Zero(sys.dof_count());
  const CoarseDeformation chi{0.2, 0.0, 0.0, weft_angle()};
  Eigen::VectorXd g = g0;
  const Sample exact = solve_free_compression(sys, chi, g, {});
  ASSERT_TRUE(exact.ok) << exact.message;
  const Eigen::VectorXd g_exact = g;

  CompressionOptions band;
  band.stress_tolerance = 0.02 * exact.stress_s;
  band.initial_guess = exact.chi.compression + 0.03;
  g = g_exact;
  const Sample near = solve_free_compression(sys, chi, g, band);
  ASSERT_TRUE(near.ok) << near.message;
  EXPECT_LE(std::abs(near.stress_c), band.stress_tolerance);
  // The bracketing aims just past the secant root, so the first c in the band may lie on
  // either side of c*; it is never further than the guess, and found with fewer solves.
  EXPECT_LT(std::abs(near.chi.compression - exact.chi.compression), 0.03);
  EXPECT_LE(near.solves, exact.solves);

  band.initial_guess = exact.chi.compression;
  g = g_exact;
  const Sample kept = solve_free_compression(sys, chi, g, band);
  ASSERT_TRUE(kept.ok) << kept.message;
  EXPECT_EQ(kept.solves, 1);
  EXPECT_EQ(kept.chi.compression, exact.chi.compression);
  std::printf("exact c* %.5f (%d solves); band ±%.3g N/m from c* + 0.03: %.5f (%d solves)\n",
              exact.chi.compression, exact.solves, band.stress_tolerance, near.chi.compression, near.solves);
}

// Item 3: the co-rotated map tends to the affine one, and the equilibrated Ψ(κ) is smooth
// through κ = 0 on the rest-shaped tile (the state every fit starts from). Stockinette curls,
// so dΨ/dκ ≠ 0 at κ = 0; smoothness shows as second differences that agree between the
// steps h and 2h (they would not across a kink or a jump between equilibria).

TEST_F(StockinetteSystem, CurvedMapTendsToTheAffineOneAndPsiIsSmoothThroughZero) {
  YarnSystem sys(make_yarn_tile(tile), params);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(sys.dof_count());
  sys.set_deformation({0.1, 0.05, 0.0, bias_angle()});
  sys.rebuild_contacts(g);
  const double flat = sys.energy(g);
  for (const double k : {1e-3, 1e-5}) {
    sys.set_deformation({0.1, 0.05, k, bias_angle()});
    sys.rebuild_contacts(g);
    EXPECT_LT(rel(sys.energy(g), flat), 10 * k) << "κ = " << k;
  }
  Eigen::VectorXd rest = Eigen::VectorXd::Zero(sys.dof_count());
  sys.set_deformation({});
  ASSERT_TRUE(relax_rest_shape(sys, rest).converged);
  EquilibriumOptions o;
  o.force_tolerance = 1e-12 * params.ks2;
  for (const double angle : {weft_angle(), warp_angle()}) {
    std::vector<double> psi;
    const double h = 2.0;  // 1/m (κ R = 0.002)
    for (int i = -2; i <= 2; ++i) {
      Eigen::VectorXd gi = rest;
      const Sample s = simulate_sample(sys, {0.0, 0.0, i * h, angle}, gi, o);
      ASSERT_TRUE(s.ok) << s.message;
      psi.push_back(s.energy_density);
    }
    const double d2_small = (psi[3] - 2 * psi[2] + psi[1]) / (h * h);
    const double d2_large = (psi[4] - 2 * psi[2] + psi[0]) / (4 * h * h);
    EXPECT_GT(d2_small, 0.0) << "angle " << angle;
    EXPECT_LT(rel(d2_small, d2_large), 0.01)
        << "angle " << angle << ": second differences " << d2_small << " and " << d2_large;
    std::printf("angle %.3f: dPsi/dkappa(0) %.4g N, d2Psi/dkappa2 %.5g (h) %.5g (2h) J\n", angle,
                (psi[3] - psi[1]) / (2 * h), d2_small, d2_large);
  }
}

// Item 4: after the rest-shape heuristic the coarse stress left at χ = 0, read along each
// load direction u (uᵀ P u, the offset it would put on that direction's σ_s curve), is below
// 5 % of σ_s at 10 % stretch in that direction, and rest lengths moved by at most 20 %.

}  // namespace
}  // namespace yarnfit::yarn

namespace yarnfit::yarn {
namespace {

using namespace fixtures;

// Two straight weft yarns 2 mm apart (R 0.25 mm), nothing crossing them: at rest Ψ does not
// depend on the compression across them until they touch, so ∂Ψ/∂c = 0 over a band from the
// search's lower bound to near contact (c ≈ 0.75), and "the root" is any c of it.
db::PeriodicTile parallel_weft_yarns() {
  db::PeriodicTile t;
  t.period_x = t.period_y = 4e-3;
  t.radius = 2.5e-4;
  constexpr int per_yarn = 8;
  for (const double y : {1e-3, 3e-3}) {
    const int first = t.vertex_count();
    for (int i = 0; i < per_yarn; ++i) t.positions.push_back({i * t.period_x / per_yarn, y, 0.0});
    for (int i = 0; i < per_yarn; ++i) t.edges.push_back({first + i, first + (i + 1) % per_yarn, i + 1 == per_yarn ? 1 : 0, 0});
  }
  db::fill_tile_defaults(t);
  return t;
}

TEST(FlatCompressionBand, AtRestTheReadOutIsTheBandsSmallestCompressionWhateverTheGuess) {
  const db::PeriodicTile tile = parallel_weft_yarns();
  YarnSystem sys(make_yarn_tile(tile), default_params({400.0, tile.radius}));
  CompressionOptions co;
  co.band_stress = default_stress_tolerance(sys);
  for (const double guess : {0.1, -0.05, 0.3}) {
    SCOPED_TRACE(guess);
    co.initial_guess = guess;
    Eigen::VectorXd g = Eigen::VectorXd::Zero(sys.dof_count());
    const Sample s = solve_free_compression(sys, {0.0, 0.0, 0.0, weft_angle()}, g, co);
    ASSERT_TRUE(s.ok) << s.message;
    EXPECT_TRUE(s.flat);
    EXPECT_EQ(s.band_lower, co.lower) << "flat down to the search's bound";
    EXPECT_GT(s.band_upper, 0.5);
    EXPECT_LT(s.band_upper, 0.8) << "the band ends where the yarns meet";
    EXPECT_EQ(s.chi.compression, 0.0);
    EXPECT_LE(std::abs(s.stress_c), co.band_stress);
  }
  // Without the band the root search keeps whatever c it evaluates first: not defined.
  CompressionOptions plain;
  plain.initial_guess = 0.1;
  Eigen::VectorXd g = Eigen::VectorXd::Zero(sys.dof_count());
  const Sample s = solve_free_compression(sys, {0.0, 0.0, 0.0, weft_angle()}, g, plain);
  ASSERT_TRUE(s.ok) << s.message;
  EXPECT_EQ(s.chi.compression, 0.1);
  EXPECT_FALSE(s.flat);
  EXPECT_TRUE(std::isnan(s.band_lower));
}

TEST_F(StockinetteSystem, AStretchedKnitHasANarrowBandAroundItsRoot) {
  YarnSystem sys(make_yarn_tile(tile), params);
  CompressionOptions co;
  co.band_stress = 1e-2;  // N/m
  Eigen::VectorXd g = Eigen::VectorXd::Zero(sys.dof_count());
  const Sample s = solve_free_compression(sys, {0.1, 0.0, 0.0, weft_angle()}, g, co);
  ASSERT_TRUE(s.ok) << s.message;
  EXPECT_FALSE(s.flat);
  EXPECT_LT(s.band_lower, s.chi.compression);
  EXPECT_GT(s.band_upper, s.chi.compression);
  EXPECT_LT(s.band_upper - s.band_lower, 1e-3);
  // The band's ends carry ∂Ψ/∂c = ∓ band_stress, to first order.
  for (const double end : {s.band_lower, s.band_upper}) {
    Eigen::VectorXd ge = g;
    const Sample at = simulate_sample(sys, {0.1, end, 0.0, weft_angle()}, ge);
    ASSERT_TRUE(at.ok) << at.message;
    EXPECT_NEAR(std::abs(at.stress_c), co.band_stress, 0.1 * co.band_stress) << "c " << end;
  }
}

}  // namespace
}  // namespace yarnfit::yarn
