// The periodic yarn system and its solver on the real tiles in ../shared (issue 4 items 2, 3,
// 6): derivatives of the assembled system, invariances (translation, period shift, in-plane
// rotation with the load direction, a doubled tile), analytic versus finite-difference
// stress, the two zero-orthogonal-stress methods, the κ → 0 limit, and hard cases.

#include <gtest/gtest.h>

#include <Eigen/SparseCore>
#include <cmath>
#include <random>

#include "fabrics_db/tile/periodic_tile.hpp"
#include "tests/test_support.hpp"
#include "yarn_fit/homogenise/readouts.hpp"
#include "yarn_fit/homogenise/rest_shape.hpp"

namespace yarnfit::yarn {
namespace {

const std::string kPatterns = std::string(YARNFIT_SHARED_DIR) + "/data/patterns/";

db::PeriodicTile load_tile(const std::string& name) {
  db::Problems problems;
  auto tile = db::read_pyp(kPatterns + name, problems);
  if (!tile) throw std::runtime_error(problems.to_string());
  return *tile;
}

YarnParams params_for(const db::PeriodicTile& tile) {
  const auto facts = db::compute_tile_facts(tile);
  return default_params({400.0, facts.r_est});
}

double rel(double a, double b) { return std::abs(a - b) / std::max(std::abs(b), 1e-300); }

// Directional central differences of the assembled energy and gradient, best over a step
// sweep, against the analytic gradient and Hessian.
void expect_system_derivatives(YarnSystem& sys, const Eigen::VectorXd& g, const std::string& label) {
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

TEST_F(StockinetteSystem, AssembledGradientAndHessianMatchFiniteDifferences) {
  YarnSystem sys(make_yarn_tile(tile), params);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> small(-0.05, 0.05);
  Eigen::VectorXd g(sys.dof_count());
  for (int i = 0; i < g.size(); ++i) g[i] = small(rng) * sys.tile().radius;
  for (const auto& [label, chi] :
       {std::pair{"weft 20 %", CoarseDeformation{0.2, 0.05, 0.0, weft_angle()}},
        std::pair{"bias 10 %, rotated frame", CoarseDeformation{0.1, 0.0, 0.0, bias_angle() + 0.3}},
        std::pair{"bent κ = 40/m", CoarseDeformation{0.05, 0.0, 40.0, warp_angle()}}}) {
    sys.set_deformation(chi);
    sys.rebuild_contacts(g);
    expect_system_derivatives(sys, g, label);
  }
}

Sample relaxed(const db::PeriodicTile& t, const YarnParams& p, const CoarseDeformation& chi,
               double rotation = 0.0) {
  YarnSystem sys(rotated_tile(make_yarn_tile(t), rotation), p);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(sys.dof_count());
  EquilibriumOptions o;
  o.force_tolerance = 1e-11 * p.ks2;
  return simulate_sample(sys, chi, g, o);
}

TEST_F(StockinetteSystem, TranslationAndPeriodShiftLeaveTheResponseUnchanged) {
  const CoarseDeformation chi{0.2, 0.0, 0.0, weft_angle()};
  const Sample base = relaxed(tile, params, chi);
  ASSERT_TRUE(base.ok) << base.message;
  db::PeriodicTile moved = tile;
  for (auto& p : moved.positions) {
    p[0] += 0.37e-3;
    p[1] -= 1.3e-3;
    p[2] += 0.2e-3;
  }
  // Vertex 5 moved by a whole period in x: its edges' offsets change accordingly.
  moved.positions[5][0] += moved.period_x;
  for (auto& e : moved.edges) {
    if (e.v0 == 5) e.dx += 1;
    if (e.v1 == 5) e.dx -= 1;
  }
  const Sample shifted = relaxed(moved, params, chi);
  ASSERT_TRUE(shifted.ok) << shifted.message;
  EXPECT_LT(rel(shifted.energy_density, base.energy_density), 1e-8);
  EXPECT_LT(rel(shifted.stress_s, base.stress_s), 1e-8);
}

TEST_F(StockinetteSystem, InPlaneRotationWithTheLoadDirectionLeavesTheResponseUnchanged) {
  const double turn = 0.6;
  for (const double angle : {weft_angle(), bias_angle()}) {
    const Sample base = relaxed(tile, params, {0.2, 0.0, 0.0, angle});
    const Sample turned = relaxed(tile, params, {0.2, 0.0, 0.0, angle + turn}, turn);
    ASSERT_TRUE(base.ok && turned.ok) << base.message << turned.message;
    EXPECT_LT(rel(turned.energy_density, base.energy_density), 1e-8) << "angle " << angle;
    EXPECT_LT(rel(turned.stress_s, base.stress_s), 1e-8) << "angle " << angle;
  }
}

// The doubled tile pins every copy of the original pins (repeat_yarn_tile), so the original's
// periodic states are among its own; both are solved cold from the affine state.
TEST_F(StockinetteSystem, DoubledTileGivesTheSameDensityAndStress) {
  const CoarseDeformation chi{0.2, 0.0, 0.0, weft_angle()};
  const Sample base = relaxed(tile, params, chi);
  ASSERT_TRUE(base.ok) << base.message;
  for (const auto& [nx, ny] : {std::pair{2, 1}, std::pair{1, 2}}) {
    YarnSystem sys(repeat_yarn_tile(tile, nx, ny), params);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(sys.dof_count());
    EquilibriumOptions o;
    o.force_tolerance = 1e-11 * params.ks2;
    const Sample doubled = simulate_sample(sys, chi, g, o);
    ASSERT_TRUE(doubled.ok) << doubled.message;
    EXPECT_LT(rel(doubled.energy_density, base.energy_density), 1e-3) << nx << "x" << ny;
    EXPECT_LT(rel(doubled.stress_s, base.stress_s), 1e-3) << nx << "x" << ny;
  }
}

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
TEST_F(StockinetteSystem, RestShapeLeavesLittleCoarseStressAndKeepsRestLengthsInBounds) {
  YarnSystem sys(make_yarn_tile(tile), params);
  Eigen::VectorXd rest = Eigen::VectorXd::Zero(sys.dof_count());
  const RestShapeResult r = relax_rest_shape(sys, rest);
  ASSERT_TRUE(r.converged) << r.last_solve.message;
  EXPECT_LE(r.max_length_change, 0.2 + 1e-12);
  for (std::size_t e = 0; e < sys.tile().edges.size(); ++e) {
    const double ratio = sys.tile().edges[e].rest_length / sys.tile().input_rest_lengths[e];
    ASSERT_LE(std::abs(ratio - 1.0), 0.2 + 1e-12) << "edge " << e;
  }
  std::printf("rest shape: %d rounds, %d Newton iterations, %.2f s, rest lengths moved up to %.1f %%;\n"
              "  period stretch E = (%.2f %%, %.2f %%, %.2f %%) took P = (%.3g, %.3g) to (%.3g, %.3g) N/m\n",
              r.rounds, r.newton_iterations, r.seconds, 100 * r.max_length_change,
              100 * r.period_stretch(0, 0), 100 * r.period_stretch(1, 1), 100 * r.period_stretch(0, 1),
              r.stress_before_period(0, 0), r.stress_before_period(1, 1), r.rest_stress(0, 0), r.rest_stress(1, 1));
  for (const double angle : {weft_angle(), bias_angle(), warp_angle()}) {
    Eigen::VectorXd g = rest;
    const Sample at10 = simulate_sample(sys, {0.1, 0.0, 0.0, angle}, g);
    ASSERT_TRUE(at10.ok) << at10.message;
    const Eigen::Vector2d u = CoarseDeformation{0.0, 0.0, 0.0, angle}.u();
    const double left = u.dot(r.rest_stress * u);
    EXPECT_LT(std::abs(left), 0.05 * at10.stress_s) << "angle " << angle;
    std::printf("  angle %.3f: rest stress %.4g N/m, sigma_s(10 %%) %.4g N/m (%.1f %%)\n", angle, left,
                at10.stress_s, 100 * std::abs(left) / at10.stress_s);
  }
}

// The period stage relaxes the normal rest stress by stretching the period, and leaves its
// shear alone unless asked (RestShapeOptions::period_shear): the tile is soft in shear at
// rest, and the E01 that zeroes that small stress followed every small change of it.
TEST_F(StockinetteSystem, PeriodStageRelaxesNormalStressAndTouchesShearOnlyWhenAsked) {
  for (const bool shear : {false, true}) {
    YarnSystem sys(make_yarn_tile(tile), params);
    Eigen::VectorXd rest;
    RestShapeOptions options;
    options.period_shear = shear;
    const RestShapeResult r = relax_rest_shape(sys, rest, options);
    ASSERT_TRUE(r.converged) << r.last_solve.message;
    std::printf("period shear %s: E = (%.3f %%, %.3f %%, %.3f %%), P from (%.3g, %.3g, %.3g) to (%.3g, %.3g, %.3g) N/m\n",
                shear ? "on " : "off", 100 * r.period_stretch(0, 0), 100 * r.period_stretch(1, 1),
                100 * r.period_stretch(0, 1), r.stress_before_period(0, 0), r.stress_before_period(1, 1),
                r.stress_before_period(0, 1), r.rest_stress(0, 0), r.rest_stress(1, 1), r.rest_stress(0, 1));
    EXPECT_DOUBLE_EQ(r.period_stretch(0, 1), r.period_stretch(1, 0));
    for (int k = 0; k < 2; ++k) {
      EXPECT_NE(r.period_stretch(k, k), 0.0) << "E" << k << k;
      EXPECT_LT(std::abs(r.rest_stress(k, k)), 0.25 * std::abs(r.stress_before_period(k, k))) << "P" << k << k;
    }
    if (shear) {
      EXPECT_NE(r.period_stretch(0, 1), 0.0);
      EXPECT_LT(std::abs(r.rest_stress(0, 1)), std::abs(r.stress_before_period(0, 1)));
    } else {
      EXPECT_EQ(r.period_stretch(0, 1), 0.0);
    }
    // The tile is what the stage says: its period is the input's times (I + E).
    const Eigen::Matrix2d expected = (Eigen::Matrix2d::Identity() + r.period_stretch) * make_yarn_tile(tile).lattice;
    EXPECT_LT((sys.tile().lattice - expected).norm(), 1e-12 * expected.norm());
  }
}

// Hard cases (issue 4 item 6): finite results and a converged or clearly failed solve.
void expect_stable(const Sample& s, const std::string& label) {
  EXPECT_TRUE(std::isfinite(s.energy_density)) << label;
  EXPECT_TRUE(std::isfinite(s.stress_s)) << label;
  if (s.ok) {
    EXPECT_TRUE(std::isfinite(s.last_solve.min_contact_distance)) << label;
    EXPECT_GT(s.last_solve.min_contact_distance, 0.0) << label << ": barrier crossed";
  } else {
    EXPECT_FALSE(s.message.empty()) << label << ": failure without a reason";
  }
  std::printf("%-28s ok %d  iterations %3d  Ψ %.4g J/m²  σ_s %.4g N/m  closest %.3g R  %s\n",
              label.c_str(), s.ok ? 1 : 0, s.newton_iterations, s.energy_density, s.stress_s,
              s.last_solve.min_contact_distance / 1e-3, s.message.c_str());
}

TEST_F(StockinetteSystem, HardCasesStayFiniteAndReportTheirStatus) {
  const YarnTile base = make_yarn_tile(tile);
  EquilibriumOptions o;
  o.max_iterations = 200;
  // Tile scaled by 0.9: heavy initial overlap.
  {
    db::PeriodicTile scaled = tile;
    for (auto& p : scaled.positions)
      for (double& c : p) c *= 0.9;
    scaled.period_x *= 0.9;
    scaled.period_y *= 0.9;
    for (double& l : scaled.rest_lengths) l *= 0.9;
    YarnSystem sys(make_yarn_tile(scaled), params);
    Eigen::VectorXd g;
    expect_stable(simulate_sample(sys, {0.0, 0.0, 0.0, 0.0}, g, o), "tile scaled by 0.9");
  }
  const auto run = [&](const YarnParams& p, const CoarseDeformation& chi, const std::string& label) {
    YarnSystem sys(base, p);
    Eigen::VectorXd g;
    expect_stable(simulate_sample(sys, chi, g, o), label);
  };
  run(params, {0.0, 0.3, 0.0, weft_angle()}, "compression c = 0.3");
  run(params, {1.6, 0.0, 0.0, weft_angle()}, "stretch s = 1.6");
  YarnParams onset = params;
  onset.eps_s = 1e-12;
  run(onset, {0.3, 0.0, 0.0, warp_angle()}, "eps_s -> 0");
  run(params, {0.0, 0.0, 1.0 / (5.0 * base.radius), weft_angle()}, "curvature 1/(5 R)");
  const auto facts = db::compute_tile_facts(tile);
  const ParameterScales sc{400.0, facts.r_est};
  YarnParams low = params, high = params;
  low.ks1 = 1e-3 * sc.ks2;
  low.kb = 1e-3 * sc.kb_base();
  low.r1 = 0.5 * sc.r_est;
  low.kc1 = 1e-2 * sc.kc_base();
  low.eps_s = 0.0;
  high.ks1 = sc.ks2;
  high.kb = 10 * sc.kb_base();
  high.r1 = 1.5 * sc.r_est;
  high.kc1 = 1e2 * sc.kc_base();
  high.eps_s = 0.15;
  run(low, {0.3, 0.0, 0.0, bias_angle()}, "parameters at lower bounds");
  run(high, {0.3, 0.0, 0.0, bias_angle()}, "parameters at upper bounds");
}

}  // namespace
}  // namespace yarnfit::yarn
