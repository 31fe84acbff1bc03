// The dihedral bending term (shell_fit/energies/bending_term.hpp) through the one derivative
// check: rolled and crumpled states, flat sheets, cylinder curvature and its convergence, the
// stiffness axis, per-parameter derivatives and the parallel assembly.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "shell_fit/core/shell_mesh.hpp"
#include "shell_fit/core/shell_params.hpp"
#include "shell_fit/energies/bending_term.hpp"
#include "tests/shell_fit/energies/shell_fixtures.hpp"

namespace yarnfit::shell {
namespace {

using namespace fixtures;
using Matrix32 = Eigen::Matrix<double, 3, 2>;

TEST(BendingTermTest, DerivativesMatchFiniteDifferences) {
  double worst_g = 0.0, worst_h = 0.0, largest_angle = 0.0;
  unsigned seed = 100;
  for (const double angle : test_angles()) {
    for (const bool jitter : {false, true}) {
      const ShellMesh mesh =
          jitter ? jittered_mesh(angle, seed) : grid_mesh(3, 3, 0.03, 0.03, angle);
      const BendingTerm term(mesh, sample_bending());
      const double size = mesh_size(mesh);
      // A strip rolled onto a cylinder plus noise, and a crumpled random sheet with large
      // dihedral angles.
      seed += 3;
      const std::vector<Eigen::VectorXd> states{
          add_noise(rolled(mesh, 0.02), 0.02 * size, seed),
          add_noise(random_deformation(mesh, 3, seed + 1), 0.15 * size, seed + 2)};
      for (const auto& x : states) {
        for (int e = 0; e < static_cast<int>(term.edges().size()); ++e) {
          largest_angle = std::max(largest_angle, std::abs(term.dihedral_angle(x, e)));
        }
        DerivativeCheckOptions o;
        o.length_scale = size;
        SCOPED_TRACE(::testing::Message()
                     << "angle " << angle << ", jitter " << jitter << ", seed " << seed);
        const auto r = expect_derivatives_match(term, x, o);
        worst_g = std::max(worst_g, r.gradient_error);
        worst_h = std::max(worst_h, r.hessian_error);
      }
    }
  }
  EXPECT_GT(largest_angle, 0.5);  // the states do exercise large folds
  std::printf(
      "BendingTerm FD: worst best-step rel. error gradient %.2e, Hessian %.2e "
      "(largest |theta| %.2f rad)\n",
      worst_g, worst_h, largest_angle);
}

TEST(BendingTermTest, FlatSheetHasZeroEnergyAnywhere) {
  const ShellMesh mesh = jittered_mesh(0.3, 2);
  const BendingTerm term(mesh, sample_bending());
  // Flat but stretched in-plane, then moved rigidly in 3-D: no bending.
  const Eigen::VectorXd planar = random_deformation(mesh, 2, 5);
  const Eigen::Matrix3d Q = rotation3(0.4, -1.2, 2.2);
  Eigen::VectorXd x(3 * mesh.vertex_count());
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    x.segment<3>(3 * v) = Q * Eigen::Vector3d(planar(2 * v), planar(2 * v + 1), 0.0) +
                          Eigen::Vector3d(0.1, -0.2, 0.3);
  }
  EXPECT_NEAR(term.value(x), 0.0, 1e-25);
  EXPECT_LE(gradient_of(term, x).lpNorm<Eigen::Infinity>(), 1e-15);  // forces ~ k/L ≈ 1e-3 N
  for (int e = 0; e < static_cast<int>(term.edges().size()); ++e) {
    EXPECT_NEAR(term.dihedral_angle(x, e), 0.0, 1e-12);
  }
  // A bent state keeps its energy under a rigid motion.
  const Eigen::VectorXd bent = add_noise(rolled(mesh, 0.015), 5e-4, 3);
  Eigen::VectorXd moved(bent.size());
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    moved.segment<3>(3 * v) = Q * bent.segment<3>(3 * v) + Eigen::Vector3d(1.0, 2.0, -3.0);
  }
  EXPECT_GT(term.value(bent), 0.0);
  EXPECT_NEAR(term.value(moved), term.value(bent), 1e-10 * term.value(bent));
}

// κ = θ/H on a cylinder of radius R meshed with right triangles whose legs run along the axis
// (lab x) and around it (lab y): axis-parallel edges carry exactly 1/R, all others are flat,
// and the energy is k_θ/R² per unit area of the interior strips — the continuum density the
// uniform bending targets σ_κ = 2 k_θ κ assume.
TEST(BendingTermTest, CylinderCurvatureAndItsConvergence) {
  const double R = 0.02, lx = 0.02, ly = 0.04;  // ly/R = 2 rad of arc
  std::printf("cylinder R = %.3g m: n | kappa*R axis edges | max |kappa*R| other edges | "
              "sum theta L / (area/R) | E R^2/(k area)\n", R);
  for (const int n : {4, 8, 16, 32, 64}) {
    // Cells 2:1 (dx = lx/n, dy = ly/n), so no aspect-ratio coincidence hides the boundary.
    const ShellMesh mesh = grid_mesh(n, n, lx, ly, 0.0);
    BendingParams uniform;
    uniform.ktheta = {1e-5, 1e-5, 1e-5};
    const BendingTerm term(mesh, uniform);
    const Eigen::VectorXd x = rolled(mesh, R);
    double axis_min = std::numeric_limits<double>::infinity();
    double axis_max = -axis_min, other = 0.0, steiner = 0.0;
    for (int e = 0; e < static_cast<int>(term.edges().size()); ++e) {
      const auto& edge = term.edges()[static_cast<std::size_t>(e)];
      const double kappa = term.curvature(x, e);
      const bool along_axis = mesh.rest(edge.v[0], 1) == mesh.rest(edge.v[1], 1);
      if (along_axis) {
        axis_min = std::min(axis_min, kappa * R);
        axis_max = std::max(axis_max, kappa * R);
      } else {
        other = std::max(other, std::abs(kappa * R));
      }
      const double L = (mesh.rest.row(edge.v[1]) - mesh.rest.row(edge.v[0])).norm();
      steiner += term.dihedral_angle(x, e) * L;
    }
    const double area = lx * ly;
    const double density = term.value(x) * R * R / (1e-5 * area);
    std::printf("  %3d | %.12f .. %.12f | %.1e | %.6f | %.6f\n", n, axis_min, axis_max, other,
                steiner / (area / R), density);
    EXPECT_NEAR(axis_min, 1.0, 1e-9);
    EXPECT_NEAR(axis_max, 1.0, 1e-9);
    EXPECT_LT(other, 1e-9);
    // Σ θ L over the interior edges → area/R (Steiner's total mean curvature); the deficit is
    // the boundary strip: exactly (n−1)/n here. The energy density is k/R² on the n−1
    // interior strips' edges: k/R² · (n−1)/n over the sheet, → k/R².
    EXPECT_NEAR(steiner / (area / R), (n - 1.0) / n, 1e-9);
    EXPECT_NEAR(density, (n - 1.0) / n, 1e-8);
  }
}

TEST(BendingTermTest, EnergyScalesWithStiffnessAlongTheRightAxis) {
  const double R = 0.02;
  const BendingParams p = sample_bending();
  for (const auto& [angle, which] :
       std::vector<std::pair<double, int>>{{0.0, 2}, {pi / 2, 0}, {pi / 4, 1}}) {
    // Cylinder axis along lab x: the curvature runs along lab y, at π/2 − angle from the weft,
    // so the folding edges (along x) carry the stiffness of that direction: warp for angle 0.
    const ShellMesh mesh = grid_mesh(4, 8, 0.02, 0.04, angle);
    const Eigen::VectorXd x = rolled(mesh, R);
    const BendingTerm term(mesh, p);
    BendingParams single;
    single.ktheta = {1e-6, 1e-6, 1e-6};
    const BendingTerm unit(mesh, single);
    const double expected = p.ktheta[static_cast<std::size_t>(which)] / 1e-6 * unit.value(x);
    EXPECT_NEAR(term.value(x), expected, 1e-12 * expected) << "material angle " << angle;
    BendingParams doubled = p;
    for (double& k : doubled.ktheta) k *= 2.0;
    EXPECT_NEAR(BendingTerm(mesh, doubled).value(x), 2.0 * term.value(x), 1e-12 * term.value(x));
  }
}

TEST(BendingTermTest, PerParameterDerivativesMatchFiniteDifferences) {
  const ShellMesh mesh = jittered_mesh(0.4, 17);
  const Eigen::VectorXd x = add_noise(rolled(mesh, 0.02), 1e-3, 4);
  const BendingParams p = sample_bending();
  const BendingTerm term(mesh, p);
  const Eigen::Vector3d v = term.value_per_parameter(x);
  EXPECT_NEAR(p.ktheta[0] * v(0) + p.ktheta[1] * v(1) + p.ktheta[2] * v(2), term.value(x),
              1e-12 * term.value(x));
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(x.size(), 3);
  term.add_gradient_per_parameter(x, G);
  for (std::size_t j = 0; j < 3; ++j) {
    const double h = 1e-3 * p.ktheta[j];
    BendingParams up = p, down = p;
    up.ktheta[j] += h;
    down.ktheta[j] -= h;
    const BendingTerm tu(mesh, up), td(mesh, down);
    const auto k = static_cast<Eigen::Index>(j);
    EXPECT_NEAR((tu.value(x) - td.value(x)) / (2 * h), v(k), 1e-8 * std::abs(v(k)));
    const Eigen::VectorXd fd = (gradient_of(tu, x) - gradient_of(td, x)) / (2 * h);
    EXPECT_LE((fd - G.col(k)).lpNorm<Eigen::Infinity>(), 1e-8 * G.col(k).lpNorm<Eigen::Infinity>());
  }
}

// Meshes above the parallel threshold (512 elements) run the OpenMP path of the assembler:
// checked by directional differences, Hessian-vector products and run-to-run reproducibility.
TEST(BendingTermTest, LargeMeshesMatchDirectionalDifferences) {
  const ShellMesh mesh = grid_mesh(17, 17, 0.06, 0.06, 0.5);  // 578 triangles, 833 edges
  ASSERT_GT(static_cast<int>(mesh.interior_edges.size()), 512);
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const BendingTerm bending(mesh, sample_bending());
  const Eigen::VectorXd x = add_noise(rolled(mesh, 0.03), 3e-4, 51);
  const Eigen::VectorXd d = Eigen::VectorXd::NullaryExpr(x.size(), [&] { return u(rng); });
  expect_directional_derivatives(bending, x, d, 0.06);
}

}  // namespace
}  // namespace yarnfit::shell
