// The pear-loop scene and the bending fit: the model's bending stiffness, the scaling law of
// the loop, mesh convergence, physical trends, exact sensitivities, hard cases, and recovery of
// known k_θ with honest identification.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <iostream>
#include <numbers>

#include "shell_fit/energies/bending_term.hpp"
#include "shell_fit/fit/bending_fit.hpp"
#include "shell_fit/scenes/pear_loop.hpp"
#include "tests/shell_fit/known_materials.hpp"
#include "tests/expect_error.hpp"

namespace yarnfit::shell {
namespace {

using known::k_knit;
// Nearly inextensible: the loop's tension ρ g L ~ 0.2 N/m strains it by ~1e-5.
using known::k_stiff;
constexpr double k_rho = 0.18;  // kg/m² (180 gsm)
constexpr double k_g = 9.81;

// The fit's target distances: 7 evenly over 3…34 mm.
const std::vector<double> k_distances = [] {
  std::vector<double> d;
  for (int i = 0; i < 7; ++i) d.push_back(0.003 + 0.031 * i / 6.0);
  return d;
}();

ShellParams params_for(const InplaneParams& inplane, double ktheta) {
  ShellParams p;
  p.inplane = inplane;
  p.bending.ktheta = {ktheta, ktheta, ktheta};
  return p;
}

// A narrow strip keeps the tests fast; the loop's shape does not depend on the width
// (stiffness and weight are both per unit width).
PearLoopSetup narrow_setup() {
  PearLoopSetup s;
  s.length = 0.10;
  s.width = 0.02;
  s.areal_density = k_rho;
  return s;
}

std::vector<double> aspect_ratios(const PearLoopRun& run) {
  std::vector<double> r;
  for (const auto& s : run.samples) r.push_back(s.aspect_ratio);
  return r;
}

void print(const char* what, const PearLoopRun& run) {
  std::cout << what << ": " << run.newton_iterations << " Newton iterations, " << run.seconds << " s\n";
  for (const auto& s : run.samples) {
    std::cout << "  d " << s.clamp_distance * 1e3 << " mm  r " << s.aspect_ratio << "  h " << s.height * 1e3
              << " mm  p " << s.width * 1e3 << " mm  " << (s.converged ? "" : s.message) << "\n";
  }
}

// The edge model's moment per unit width is 2 k_θ κ on the scene's mesh: bend the whole mesh
// into a cylinder of radius R about the y axis (the loop's state) and compare its bending
// energy with ½ B/R² over the area the bent edges own. Also checks which k_θ each test
// direction measures.
TEST(PearLoop, ModelBendingStiffnessIsTwiceKtheta) {
  const BendingParams k{{1e-6, 2e-6, 4e-6}};
  for (int dir = 0; dir < 3; ++dir) {
    PearLoopSetup s = narrow_setup();
    s.material_angle = -db::pull_angle(static_cast<db::Direction>(dir));
    s.refinements = dir == 1 ? 1 : 0;
    const PearLoopScene scene(s);
    EXPECT_EQ(scene.governing_ktheta(), dir);
    EXPECT_NEAR(scene.effective_ktheta(k), k.ktheta[static_cast<std::size_t>(dir)], 1e-12);
    const ShellMesh& m = scene.mesh();
    const BendingTerm bending(m, k);
    const double R = 0.03;
    Eigen::VectorXd x(3 * m.vertex_count());
    double length = 0.0, column = 1e300;
    for (int v = 0; v < m.vertex_count(); ++v) {
      const double X = m.rest(v, 0);
      x.segment<3>(3 * v) << R * std::sin(X / R), m.rest(v, 1), R * (1.0 - std::cos(X / R));
      length = std::max(length, X);
      if (X > 1e-12) column = std::min(column, X);
    }
    // Interior columns of across-edges own one column spacing each: (length − spacing)·W.
    const double owned = (length - column) * s.width;
    const double B = bending_stiffness_per_width(scene.effective_ktheta(k));
    EXPECT_NEAR(bending.value(x), 0.5 * B / (R * R) * owned, 1e-9 * bending.value(x)) << "direction " << dir;
  }
  EXPECT_DOUBLE_EQ(bending_stiffness_per_width(3e-6), 6e-6);
  EXPECT_NEAR(bending_length(ktheta_for_bending_length(0.012, k_rho), k_rho), 0.012, 1e-15);
}

TEST(PearLoop, EveryRunReportsItsEffects) {
  const PearLoopScene scene(narrow_setup());
  const auto run = scene.run(params_for(k_knit, ktheta_for_bending_length(0.02, k_rho)), {0.01});
  ASSERT_TRUE(run.ok) << run.message;
  EXPECT_EQ(run.effects, (std::vector<std::string>{"membrane", "bending", "gravity"}));
}

// Issue acceptance: for a nearly inextensible strip the loop's shape is fixed by bending
// against gravity, so r depends on the stiffnesses only through ℓ = (B/(ρ g))^(1/3) and on the
// lengths only through d/ℓ and L/ℓ.
TEST(PearLoop, AspectRatioDependsOnlyOnTheBendingLength) {
  const double ell = 0.015;
  const std::vector<double> d{k_distances[0], k_distances[2], k_distances[4], k_distances[6]};
  // (1) Two (k_θ, ρ) pairs with the same ℓ.
  PearLoopSetup a = narrow_setup(), b = narrow_setup();
  b.areal_density = 3.0 * k_rho;
  const auto run_a = PearLoopScene(a).run(params_for(k_stiff, ktheta_for_bending_length(ell, a.areal_density)), d);
  const auto run_b = PearLoopScene(b).run(params_for(k_stiff, ktheta_for_bending_length(ell, b.areal_density)), d);
  ASSERT_TRUE(run_a.ok) << run_a.message;
  ASSERT_TRUE(run_b.ok) << run_b.message;
  print("rho 0.18, l 15 mm", run_a);
  print("rho 0.54, l 15 mm", run_b);
  for (std::size_t i = 0; i < d.size(); ++i)
    EXPECT_NEAR(run_b.samples[i].aspect_ratio, run_a.samples[i].aspect_ratio, 0.01 * run_a.samples[i].aspect_ratio);

  // (2) k_θ × 8 doubles ℓ; with d, L (and W, so the mesh is similar) doubled, r is unchanged.
  PearLoopSetup c = narrow_setup();
  c.length *= 2.0;
  c.width *= 2.0;
  c.target_edge *= 2.0;
  std::vector<double> d2;
  for (double di : d) d2.push_back(2.0 * di);
  const auto run_c = PearLoopScene(c).run(params_for(k_stiff, 8.0 * ktheta_for_bending_length(ell, k_rho)), d2);
  ASSERT_TRUE(run_c.ok) << run_c.message;
  print("k x 8, d, L, W x 2", run_c);
  for (std::size_t i = 0; i < d.size(); ++i)
    EXPECT_NEAR(run_c.samples[i].aspect_ratio, run_a.samples[i].aspect_ratio, 0.01 * run_a.samples[i].aspect_ratio);
}

// The inextensible planar elastica of the half loop, by shooting: tangent angle θ(s) from the
// clamp (θ = −π/2, pointing down) to the bottom (θ = 0, by symmetry), minimising
//   ∫₀^S [½ B θ'² + ρ g (S − s) sin θ + λ cos θ] ds   (gravity by parts, λ: closes x(S) = 0)
// so B θ'' = ρ g (S − s) cos θ − λ sin θ. Unknowns θ'(0) and λ; Newton on θ(S) = 0, x(S) = 0,
// continued in ℓ from a stiff strip. Returns r = h/p.
double elastica_aspect_ratio(double ell, double d, double L) {
  const double S = 0.5 * L;  // units with ρ g = 1, so B = ℓ³
  constexpr int steps = 400;
  struct End {
    double theta, x, zmin, xmin;
  };
  const auto shoot = [&](double omega0, double lambda, double ell_now) {
    const double b = ell_now * ell_now * ell_now;
    const double h = S / steps;
    std::array<double, 4> y{-std::numbers::pi / 2, omega0, -0.5 * d, 0.0};  // θ, θ', x, z
    End e{0, 0, 0, -0.5 * d};
    const auto f = [&](double s, const std::array<double, 4>& v) {
      return std::array<double, 4>{v[1], ((S - s) * std::cos(v[0]) - lambda * std::sin(v[0])) / b, std::cos(v[0]),
                                   std::sin(v[0])};
    };
    for (int i = 0; i < steps; ++i) {
      const double s = i * h;
      std::array<double, 4> k1 = f(s, y), t{}, k2{}, k3{}, k4{};
      for (int j = 0; j < 4; ++j) t[j] = y[j] + 0.5 * h * k1[j];
      k2 = f(s + 0.5 * h, t);
      for (int j = 0; j < 4; ++j) t[j] = y[j] + 0.5 * h * k2[j];
      k3 = f(s + 0.5 * h, t);
      for (int j = 0; j < 4; ++j) t[j] = y[j] + h * k3[j];
      k4 = f(s + h, t);
      for (int j = 0; j < 4; ++j) y[j] += h / 6.0 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
      e.zmin = std::min(e.zmin, y[3]);
      e.xmin = std::min(e.xmin, y[2]);
    }
    e.theta = y[0];
    e.x = y[2];
    return e;
  };
  double omega0 = -1.0 / L, lambda = 0.0;  // a gently curving start at ℓ = 5 cm
  const double ell_start = std::max(0.05, ell);
  const int continuation_steps = static_cast<int>(std::ceil((ell_start - ell) / 5e-4));
  for (int c = 0; c <= continuation_steps; ++c) {
    const double en = continuation_steps == 0 ? ell : ell_start + (ell - ell_start) * c / continuation_steps;
    for (int it = 0; it < 100; ++it) {
      const End e0 = shoot(omega0, lambda, en);
      const double f0 = std::abs(e0.theta) + std::abs(e0.x) / L;
      if (f0 < 1e-12) break;
      const double h0 = 1e-6 * (std::abs(omega0) + 1e-3), h1 = 1e-6 * (std::abs(lambda) + 1e-3);
      const End a = shoot(omega0 + h0, lambda, en), b = shoot(omega0, lambda + h1, en);
      const double j00 = (a.theta - e0.theta) / h0, j01 = (b.theta - e0.theta) / h1;
      const double j10 = (a.x - e0.x) / h0, j11 = (b.x - e0.x) / h1;
      const double det = j00 * j11 - j01 * j10;
      const double d0 = -(j11 * e0.theta - j01 * e0.x) / det, d1 = -(-j10 * e0.theta + j00 * e0.x) / det;
      double t = 1.0;
      for (; t > 1e-4; t *= 0.5) {
        const End trial = shoot(omega0 + t * d0, lambda + t * d1, en);
        if (std::abs(trial.theta) + std::abs(trial.x) / L < f0) break;
      }
      omega0 += t * d0;
      lambda += t * d1;
    }
  }
  const End e = shoot(omega0, lambda, ell);
  return -e.zmin / (-2.0 * e.xmin);
}

// Against the inextensible planar elastica (an independent solution of the same physics): the
// shell's loop has a width and a membrane, so a few percent remain (pear_loop.hpp).
TEST(PearLoop, AgreesWithTheInextensibleElastica) {
  const PearLoopScene scene(narrow_setup());
  for (double ell : {0.012, 0.03}) {
    const std::vector<double> d{0.003, 0.0185, 0.034};
    const auto run = scene.run(params_for(k_knit, ktheta_for_bending_length(ell, k_rho)), d);
    ASSERT_TRUE(run.ok) << run.message;
    for (std::size_t i = 0; i < d.size(); ++i) {
      const double r_e = elastica_aspect_ratio(ell, d[i], 0.10);
      const double r = run.samples[i].aspect_ratio;
      std::cout << "l " << ell * 1e3 << " mm, d " << d[i] * 1e3 << " mm: shell " << r << ", elastica " << r_e << " ("
                << 100.0 * (r - r_e) / r_e << " %)\n";
      EXPECT_NEAR(r, r_e, 0.04 * r_e);
    }
  }
}

// SPEC §3: outputs on a twice-subdivided mesh differ from the default mesh by < 2 %.
TEST(PearLoop, MeshConvergence) {
  for (double ell : {0.012}) {
    const ShellParams p = params_for(k_knit, ktheta_for_bending_length(ell, k_rho));
    const std::vector<double> d{0.003, 0.0185, 0.034};
    PearLoopSetup s = narrow_setup();
    const auto coarse = PearLoopScene(s).run(p, d);
    s.refinements = 2;
    const auto fine = PearLoopScene(s).run(p, d);
    ASSERT_TRUE(coarse.ok) << coarse.message;
    ASSERT_TRUE(fine.ok) << fine.message;
    std::cout << "l " << ell * 1e3 << " mm: default " << coarse.seconds << " s, twice subdivided " << fine.seconds << " s\n";
    for (std::size_t i = 0; i < d.size(); ++i) {
      const double r0 = coarse.samples[i].aspect_ratio, r2 = fine.samples[i].aspect_ratio;
      std::cout << "  d " << d[i] * 1e3 << " mm: r " << r0 << " -> " << r2 << " (" << 100.0 * (r0 - r2) / r2 << " %)\n";
      EXPECT_NEAR(r0, r2, 0.02 * r2) << "l " << ell << " d " << d[i];
    }
  }
}

// The physics: bringing the clamps together narrows the loop while its depth hardly changes
// (it is set by the strip's length), so r falls monotonically as d grows; a softer strip
// (shorter ℓ) sags into a deeper, narrower loop, so r grows as ℓ shrinks.
TEST(PearLoop, AspectRatioFallsAsTheClampsSeparateAndRisesAsTheStripSoftens) {
  const PearLoopScene scene(narrow_setup());
  std::vector<double> previous;
  for (double ell : {0.05, 0.02, 0.01}) {
    const auto run = scene.run(params_for(k_knit, ktheta_for_bending_length(ell, k_rho)), k_distances);
    ASSERT_TRUE(run.ok) << run.message;
    const auto r = aspect_ratios(run);
    for (std::size_t i = 1; i < r.size(); ++i) EXPECT_LT(r[i], r[i - 1]) << "l " << ell << " d " << k_distances[i];
    for (std::size_t i = 0; i < previous.size(); ++i) EXPECT_GT(r[i], previous[i]) << "l " << ell << " d " << k_distances[i];
    previous = r;
  }
}

// dr/dk_θ from the equilibrium Hessian against central differences of whole runs.
TEST(PearLoop, SensitivitiesMatchFiniteDifferences) {
  PearLoopSetup s = narrow_setup();
  s.material_angle = -std::numbers::pi / 4;  // bias: the three k_θ all take part
  s.target_edge = 5e-3;
  const PearLoopScene scene(s);
  ShellParams p = params_for(k_knit, 0.0);
  p.bending.ktheta = {3e-6, 2e-6, 1e-6};
  const std::vector<double> d{0.005, 0.025};
  const auto run = scene.run(p, d, true);
  ASSERT_TRUE(run.ok) << run.message;
  for (std::size_t j = 0; j < 3; ++j) {
    const double h = 1e-3 * p.bending.ktheta[j];
    ShellParams up = p, down = p;
    up.bending.ktheta[j] += h;
    down.bending.ktheta[j] -= h;
    const auto ru = scene.run(up, d), rd = scene.run(down, d);
    ASSERT_TRUE(ru.ok && rd.ok);
    for (std::size_t i = 0; i < d.size(); ++i) {
      const double fd = (ru.samples[i].aspect_ratio - rd.samples[i].aspect_ratio) / (2.0 * h);
      const double ift = run.samples[i].daspect_dktheta[static_cast<Eigen::Index>(j)];
      const double scale = run.samples[i].daspect_dktheta.cwiseAbs().maxCoeff();
      EXPECT_NEAR(ift, fd, 1e-3 * scale) << "k " << j << " d " << d[i];
    }
  }
}

// A near-zero bending stiffness (ℓ = L/1000: a chain) must not produce NaN: either an
// equilibrium or a clear failure.
TEST(PearLoop, NearZeroBendingStiffnessStaysFinite) {
  PearLoopSetup setup = narrow_setup();
  setup.target_edge = 5e-3;
  const PearLoopScene scene(setup);
  for (double ktheta : {ktheta_for_bending_length(1e-4, k_rho), 0.0}) {
    const auto run = scene.run(params_for(k_knit, ktheta), {0.01}, true);
    print(ktheta > 0.0 ? "l = 0.1 mm" : "k_theta = 0", run);
    for (const auto& s : run.samples) {
      EXPECT_TRUE(std::isfinite(s.aspect_ratio) && std::isfinite(s.height) && std::isfinite(s.width));
      EXPECT_TRUE(s.daspect_dktheta.allFinite());
      if (!s.converged) {
        EXPECT_FALSE(s.message.empty());
      }
    }
    if (!run.ok) {
      EXPECT_FALSE(run.message.empty());
    }
  }
}

TEST(PearLoop, BadInputIsRejected) {
  PearLoopSetup s = narrow_setup();
  s.cells_along = 3;
  EXPECT_ERROR(PearLoopScene{s}, yarnfit::ErrorCategory::input);
  s = narrow_setup();
  s.areal_density = -1.0;
  EXPECT_ERROR(PearLoopScene{s}, yarnfit::ErrorCategory::input);
  const PearLoopScene scene(narrow_setup());
  EXPECT_ERROR((void)scene.initial_state(0.09), yarnfit::ErrorCategory::input);  // no loop closes that wide
  const auto run = scene.run(params_for(k_knit, 1e-6), {0.09});
  EXPECT_FALSE(run.ok);
  EXPECT_FALSE(run.samples[0].converged);
  EXPECT_FALSE(run.message.empty());
}

// Timing of one equilibrium on the full 100 × 60 mm swatch at the default mesh (printed).
TEST(PearLoop, OneEquilibriumAtTheDefaultMesh) {
  PearLoopSetup s;
  s.areal_density = k_rho;
  const PearLoopScene scene(s);
  const auto p = params_for(k_knit, ktheta_for_bending_length(0.012, k_rho));
  const auto run = scene.run(p, {0.014});
  ASSERT_TRUE(run.ok) << run.message;
  PearLoopWarmStart warm;
  (void)scene.run(p, {0.014}, false, &warm);
  const auto again = scene.run(params_for(k_knit, 1.05 * ktheta_for_bending_length(0.012, k_rho)), {0.014}, true, &warm);
  std::cout << scene.mesh().vertex_count() << " vertices: one equilibrium from the start loop " << run.seconds << " s ("
            << run.newton_iterations << " Newton iterations); warm-started with sensitivities " << again.seconds << " s ("
            << again.newton_iterations << " iterations)\n";
}

// ---------------------------------------------------------------------------------------------
// The bending fit.

db::BendingTest bending_test(db::Direction dir, const PearLoopRun& run) {
  db::BendingTest t;
  t.direction = dir;
  t.swatch = {0.10, 0.02};
  for (const auto& s : run.samples) {
    t.curve.clamp_distance.push_back(s.clamp_distance);
    t.curve.aspect_ratio.push_back(s.aspect_ratio);
  }
  return t;
}

// A fabric whose bending curves are simulated from `truth` on a once-refined mesh (the fit
// runs on the default one), at the fit's 7 target distances 3…34 mm.
db::Fabric synthetic_bending_fabric(const BendingParams& truth, const std::vector<db::Direction>& dirs,
                                    const InplaneParams& law = k_knit) {
  db::Fabric f;
  f.id = "synthetic_bending";
  f.areal_density = k_rho;
  const std::vector<double> d = k_distances;
  for (db::Direction dir : dirs) {
    db::BendingTest t;
    t.swatch = {0.10, 0.02};
    t.direction = dir;
    PearLoopSetup s = pear_loop_setup(t, k_rho, 2.5e-3, 1);
    ShellParams p;
    p.inplane = law;
    p.bending = truth;
    const auto run = PearLoopScene(s).run(p, d);
    EXPECT_TRUE(run.ok) << run.message;
    f.bending_tests[dir] = bending_test(dir, run);
  }
  return f;
}

void print(const BendingFitResult& r) {
  std::cout << "fit: " << r.message << "\n  bending " << r.bending_pct << " %, " << r.iterations << " iterations, "
            << r.simulations << " simulations, " << r.seconds << " s\n  start";
  for (double k : r.start.ktheta) std::cout << " " << k;
  std::cout << "\n  params";
  for (double k : r.params.ktheta) std::cout << " " << k;
  std::cout << "\n";
  for (const auto& n : r.not_identified) std::cout << "  not identified: " << n << "\n";
}

TEST(BendingFit, RecoversKthetaFromAnotherMesh) {
  const BendingParams truth{{ktheta_for_bending_length(0.012, k_rho), 0.0, 0.0}};
  const auto fabric = synthetic_bending_fabric({{truth.ktheta[0], truth.ktheta[0], truth.ktheta[0]}}, {db::Direction::weft});
  const auto r = fit_bending(fabric, k_knit, BendingFitOptions{});
  print(r);
  EXPECT_TRUE(r.converged) << r.message;
  EXPECT_EQ(r.identified, std::vector<std::string>{"ktheta_weft"});
  EXPECT_NEAR(r.params.ktheta[0], truth.ktheta[0], 0.02 * truth.ktheta[0]);
  EXPECT_LT(r.bending_pct, 1.0);
  ASSERT_EQ(r.directions.size(), 1u);
  EXPECT_EQ(r.directions[0].clamp_distance.size(), 7u);
  EXPECT_NEAR(r.directions[0].clamp_distance.front(), 0.003, 1e-12);
  EXPECT_NEAR(r.directions[0].clamp_distance.back(), 0.034, 1e-12);
  EXPECT_TRUE(r.max_curvature[0].has_value());
  EXPECT_FALSE(r.max_curvature[1].has_value());
  EXPECT_EQ(r.effects, (std::vector<std::string>{"membrane", "bending", "gravity"}));
  // Start values from the data, not constants: within 30 % of the truth.
  EXPECT_NEAR(r.start.ktheta[0], truth.ktheta[0], 0.3 * truth.ktheta[0]);
}

// A knit slack along the warp at rest (kyy → 0, its stiffness all lock-up, as the laws
// homogenised from yarn models by `synth fabric` are): its pear loops are well posed, and the
// search must reach their stiffness. A thin-shell limit read from the small-strain kyy alone
// capped k_theta at 1.5e-7 N*m, ten times below this truth.
TEST(BendingFit, ALawSlackAtRestStillReachesTheLoopsStiffness) {
  InplaneParams slack = k_knit;
  slack.kyy = 0.3;
  slack.lyy = 400.0;
  slack.byy = 2.0;
  const double k = ktheta_for_bending_length(0.012, k_rho);
  const auto fabric = synthetic_bending_fabric({{k, k, k}}, {db::Direction::warp}, slack);
  const auto r = fit_bending(fabric, slack, BendingFitOptions{});
  print(r);
  EXPECT_TRUE(r.converged) << r.message;
  EXPECT_TRUE(r.at_bounds.empty());
  EXPECT_NEAR(r.params.ktheta[2], k, 0.03 * k);
}

TEST(BendingFit, AMissingDirectionIsNotIdentified) {
  const double kw = ktheta_for_bending_length(0.012, k_rho), kp = ktheta_for_bending_length(0.018, k_rho);
  const BendingParams truth{{kw, std::sqrt(kw * kp), kp}};
  const auto fabric = synthetic_bending_fabric(truth, {db::Direction::weft, db::Direction::warp});
  BendingFitOptions o;
  o.threads = 2;
  const auto r = fit_bending(fabric, k_knit, o);
  print(r);
  EXPECT_TRUE(r.converged) << r.message;
  EXPECT_EQ(r.identified, (std::vector<std::string>{"ktheta_weft", "ktheta_warp"}));
  ASSERT_EQ(r.not_identified.size(), 1u);
  EXPECT_EQ(r.not_identified[0].rfind("ktheta_bias: no bias bending test", 0), 0u);
  EXPECT_NEAR(r.params.ktheta[1], std::sqrt(r.params.ktheta[0] * r.params.ktheta[2]), 1e-9 * r.params.ktheta[1]);
  EXPECT_NEAR(r.params.ktheta[0], kw, 0.03 * kw);
  EXPECT_NEAR(r.params.ktheta[2], kp, 0.03 * kp);
}

TEST(BendingFit, WithoutBendingTestsNothingIsFitted) {
  db::Fabric f;
  f.id = "no_bending";
  f.areal_density = k_rho;
  const auto r = fit_bending(f, k_knit, BendingFitOptions{});
  EXPECT_FALSE(r.converged);
  EXPECT_TRUE(r.identified.empty());
  EXPECT_EQ(r.not_identified.size(), 3u);
  EXPECT_FALSE(r.message.empty());
}

TEST(BendingFit, BendingTestsNeedTheArealDensity) {
  db::Fabric f;
  f.id = "no_density";
  db::BendingTest t;
  t.swatch = {0.10, 0.02};
  t.curve.clamp_distance = {0.005, 0.02};
  t.curve.aspect_ratio = {2.0, 1.5};
  f.bending_tests[db::Direction::weft] = t;
  EXPECT_ERROR((void)fit_bending(f, k_knit, BendingFitOptions{}), yarnfit::ErrorCategory::input);
}

TEST(BendingFit, TargetsAreClippedToTheMeasuredRange) {
  db::BendingTest t;
  t.curve.clamp_distance = {0.010, 0.020, 0.040};
  t.curve.aspect_ratio = {2.0, 1.6, 1.2};
  const auto targets = make_bending_targets(t);
  ASSERT_EQ(targets.clamp_distance.size(), 7u);
  EXPECT_DOUBLE_EQ(targets.clamp_distance.front(), 0.010);
  EXPECT_DOUBLE_EQ(targets.clamp_distance.back(), 0.034);
  EXPECT_NEAR(targets.measured_aspect_ratio.front(), 2.0, 1e-12);
  EXPECT_NEAR(targets.measured_aspect_ratio.back(), 1.6 - 0.4 * 14.0 / 20.0, 1e-12);
}

}  // namespace
}  // namespace yarnfit::shell
