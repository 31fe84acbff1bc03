// The membrane term (shell_fit/energies/membrane_term.hpp) through the one derivative check:
// planar and surface forms in every material frame, rest and rigid-motion invariance, the
// material frame turning with the mesh, inversion, per-parameter derivatives, the PSD
// projection and the parallel assembly.

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
#include "shell_fit/energies/membrane_term.hpp"
#include "tests/shell_fit/energies/shell_fixtures.hpp"

namespace yarnfit::shell {
namespace {

using namespace fixtures;
using Matrix32 = Eigen::Matrix<double, 3, 2>;

TEST(MembraneTermTest, DerivativesMatchFiniteDifferences) {
  double worst_g = 0.0, worst_h = 0.0;
  unsigned seed = 1;
  for (const InplaneParams& params : {sample_inplane(), sample_stiffening()}) {
  for (const int dim : {2, 3}) {
    for (const double angle : test_angles()) {
      const ShellMesh mesh = jittered_mesh(angle, seed);
      const MembraneTerm term(mesh, params, dim);
      for (int trial = 0; trial < 2; ++trial) {
        const Eigen::VectorXd x = random_deformation(mesh, dim, ++seed);
        DerivativeCheckOptions o;
        o.length_scale = mesh_size(mesh);
        SCOPED_TRACE(::testing::Message()
                     << "dim " << dim << ", angle " << angle << ", seed " << seed);
        const auto r = expect_derivatives_match(term, x, o);
        worst_g = std::max(worst_g, r.gradient_error);
        worst_h = std::max(worst_h, r.hessian_error);
      }
    }
  }
  }
  std::printf("MembraneTerm FD: worst best-step rel. error gradient %.2e, Hessian %.2e\n", worst_g,
              worst_h);
}

TEST(MembraneTermTest, ZeroAtRestAndInvariantUnderRigidMotion) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const double angle : test_angles()) {
    const ShellMesh mesh = jittered_mesh(angle, 5);
    for (const int dim : {2, 3}) {
      const MembraneTerm term(mesh, sample_inplane(), dim);
      const Eigen::VectorXd rest = embed(mesh, dim);
      // Zero up to the rounding of D_m⁻¹ on the jittered mesh: the energy scale here is
      // k · area ≈ 1e-2 J and the force scale k · size ≈ 1 N.
      EXPECT_NEAR(term.value(rest), 0.0, 1e-24);
      EXPECT_LE(gradient_of(term, rest).lpNorm<Eigen::Infinity>(), 1e-12);

      const Eigen::VectorXd x = random_deformation(mesh, dim, 21);
      Eigen::VectorXd moved(x.size());
      if (dim == 2) {
        const Eigen::Rotation2Dd Q(3.0 * u(rng));
        const Eigen::Vector2d t(u(rng), u(rng));
        for (int v = 0; v < mesh.vertex_count(); ++v)
          moved.segment<2>(2 * v) = Q * x.segment<2>(2 * v) + t;
      } else {
        const Eigen::Matrix3d Q = rotation3(3 * u(rng), 3 * u(rng), 3 * u(rng));
        const Eigen::Vector3d t(u(rng), u(rng), u(rng));
        for (int v = 0; v < mesh.vertex_count(); ++v)
          moved.segment<3>(3 * v) = Q * x.segment<3>(3 * v) + t;
      }
      EXPECT_NEAR(term.value(moved), term.value(x), 1e-12 * term.value(x)) << "dim " << dim;
      // Rest moved rigidly is still at rest.
      Eigen::VectorXd rest_moved(rest.size());
      if (dim == 2) {
        const Eigen::Rotation2Dd Q(1.234);
        for (int v = 0; v < mesh.vertex_count(); ++v)
          rest_moved.segment<2>(2 * v) = Q * rest.segment<2>(2 * v);
      } else {
        const Eigen::Matrix3d Q = rotation3(0.3, 1.1, -0.7);
        for (int v = 0; v < mesh.vertex_count(); ++v)
          rest_moved.segment<3>(3 * v) = Q * rest.segment<3>(3 * v);
      }
      EXPECT_NEAR(term.value(rest_moved), 0.0, 1e-18);
    }
  }
}

TEST(MembraneTermTest, MaterialFrameRotatesWithTheMesh) {
  const double s = 0.15;
  const InplaneParams p = sample_inplane();
  const ShellMesh weft_mesh = grid_mesh(4, 4, 0.02, 0.02, 0.0);
  const ShellMesh warp_mesh = grid_mesh(4, 4, 0.02, 0.02, pi / 2);
  const MembraneTerm weft(weft_mesh, p, 2);
  const MembraneTerm warp(warp_mesh, p, 2);
  const Eigen::Matrix2d along_x = Eigen::Vector2d(1 + s, 1.0).asDiagonal();
  const Eigen::Matrix2d along_y = Eigen::Vector2d(1.0, 1 + s).asDiagonal();
  // Both stretch the weft axis: same energy, and equal to A Ψ of the analytic density.
  const double e = 0.5 * ((1 + s) * (1 + s) - 1.0);
  const double density =
      0.5 * p.kxx * e * e + p.kn1 * s * s + p.kn2 * std::log(1 + s) * std::log(1 + s);
  EXPECT_NEAR(weft.value(affine(weft_mesh, along_x)), 4e-4 * density, 1e-12 * density);
  EXPECT_NEAR(warp.value(affine(warp_mesh, along_y)), 4e-4 * density, 1e-12 * density);
  // Both stretch the warp axis.
  EXPECT_NEAR(weft.value(affine(weft_mesh, along_y)), warp.value(affine(warp_mesh, along_x)),
              1e-15);
  // kxx ≠ kyy, so weft and warp stretches differ (the frame is not ignored).
  EXPECT_GT(weft.value(affine(weft_mesh, along_x)), 1.5 * weft.value(affine(weft_mesh, along_y)));
  // Reaction force on the right edge: Σ g_x = A P00 / length · … reduces to width · P00.
  const Eigen::VectorXd g = gradient_of(weft, affine(weft_mesh, along_x));
  double right = 0.0;
  for (int v = 0; v < weft_mesh.vertex_count(); ++v) {
    if (weft_mesh.rest(v, 0) > 0.02 - 1e-12) right += g(2 * v);
  }
  EXPECT_NEAR(right, 0.02 * InplaneMaterial(p, 0.0).pk1(along_x)(0, 0), 1e-12);
}

TEST(MembraneTermTest, InvertedTriangleIsInvalidNeverNaN) {
  const ShellMesh mesh = grid_mesh(2, 2, 0.02, 0.02, 0.4);
  const MembraneTerm term(mesh, sample_inplane(), 2);
  Eigen::VectorXd x = embed(mesh, 2);
  // Push the centre vertex (index 4) past the opposite corner: its triangles invert.
  x(2 * 4) = 0.025;
  x(2 * 4 + 1) = 0.024;
  EXPECT_EQ(term.value(x), std::numeric_limits<double>::infinity());
  EXPECT_FALSE(term.is_valid(x));
  EXPECT_TRUE(gradient_of(term, x).allFinite());
  EXPECT_TRUE(testing::dense_hessian(term, x, false).allFinite());
  EXPECT_TRUE(testing::dense_hessian(term, x, true).allFinite());
  EXPECT_TRUE(term.is_valid(embed(mesh, 2)));
}

TEST(MembraneTermTest, PerParameterDerivativesMatchFiniteDifferences) {
  // The stiffening law: all fourteen parameters are live (the thesis law is its l = 0 case).
  const InplaneParams p = sample_stiffening();
  constexpr int np = MembraneTerm::parameter_count;
  for (const int dim : {2, 3}) {
    const ShellMesh mesh = jittered_mesh(0.6, 9);
    const Eigen::VectorXd x = random_deformation(mesh, dim, 33);
    const MembraneTerm term(mesh, p, dim);
    const MembraneTerm::ParameterVector v = term.value_per_parameter(x);
    Eigen::MatrixXd G = Eigen::MatrixXd::Zero(x.size(), np);
    term.add_gradient_per_parameter(x, G);
    const auto base = to_array(p);
    // E is linear in every parameter but the rates and shares: E = Σ_{k linear} p_k ∂E/∂p_k.
    double sum = 0.0;
    for (int k = 0; k < np; ++k)
      if (enters_linearly(k)) sum += base[static_cast<std::size_t>(k)] * v(k);
    EXPECT_NEAR(sum, term.value(x), 1e-12 * term.value(x));
    for (int k = 0; k < np; ++k) {
      const double h = 1e-4 * std::max(std::abs(base[static_cast<std::size_t>(k)]), 1.0);
      auto up = base, down = base;
      up[static_cast<std::size_t>(k)] += h;
      down[static_cast<std::size_t>(k)] -= h;
      const MembraneTerm tu(mesh, inplane_from_array(up), dim);
      const MembraneTerm td(mesh, inplane_from_array(down), dim);
      const double fd_value = (tu.value(x) - td.value(x)) / (2 * h);
      const Eigen::VectorXd fd_grad = (gradient_of(tu, x) - gradient_of(td, x)) / (2 * h);
      EXPECT_NEAR(fd_value, v(k), 1e-7 * std::abs(v(k)) + 1e-14) << k_inplane_param_names[k] << ", dim " << dim;
      EXPECT_LE((fd_grad - G.col(k)).lpNorm<Eigen::Infinity>(), 1e-7 * G.col(k).lpNorm<Eigen::Infinity>() + 1e-14)
          << k_inplane_param_names[k] << ", dim " << dim;
    }
  }
}

TEST(MembraneTermTest, SurfaceMatchesPlanarOnFlatStates) {
  const ShellMesh mesh = jittered_mesh(0.9, 6);
  const MembraneTerm planar(mesh, sample_inplane(), 2);
  const MembraneTerm surface(mesh, sample_inplane(), 3);
  const Eigen::VectorXd x2 = random_deformation(mesh, 2, 44);
  Eigen::VectorXd x3 = Eigen::VectorXd::Zero(3 * mesh.vertex_count());
  for (int v = 0; v < mesh.vertex_count(); ++v) x3.segment<2>(3 * v) = x2.segment<2>(2 * v);
  EXPECT_NEAR(surface.value(x3), planar.value(x2), 1e-13 * planar.value(x2));
  const Eigen::VectorXd g2 = gradient_of(planar, x2), g3 = gradient_of(surface, x3);
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    EXPECT_NEAR(g3(3 * v), g2(2 * v), 1e-12 * g2.lpNorm<Eigen::Infinity>());
    EXPECT_NEAR(g3(3 * v + 1), g2(2 * v + 1), 1e-12 * g2.lpNorm<Eigen::Infinity>());
    EXPECT_EQ(g3(3 * v + 2), 0.0);
  }
}

// Compression makes StVK (and bending far from flat) indefinite; the per-element projection
// must remove every negative eigenvalue of the assembled matrix and change nothing at rest.
TEST(MembraneTermTest, ProjectionRemovesNegativeCurvatureOnly) {
  const ShellMesh mesh = jittered_mesh(0.2, 8);
  for (const int dim : {2, 3}) {
    const MembraneTerm term(mesh, sample_inplane(), dim);
    Eigen::VectorXd x = 0.7 * embed(mesh, dim);  // 30 % compression in both directions
    if (dim == 3) x = add_noise(x, 1e-4, 2);
    const Eigen::MatrixXd raw = testing::dense_hessian(term, x, false);
    const Eigen::MatrixXd projected = testing::dense_hessian(term, x, true);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig_raw(raw), eig_projected(projected);
    EXPECT_LT(eig_raw.eigenvalues().minCoeff(), -1e-3 * eig_raw.eigenvalues().maxCoeff()) << dim;
    EXPECT_GE(eig_projected.eigenvalues().minCoeff(), -1e-12 * eig_raw.eigenvalues().maxCoeff())
        << dim;
    const Eigen::VectorXd rest = embed(mesh, dim);
    EXPECT_LE((testing::dense_hessian(term, rest, true) - testing::dense_hessian(term, rest, false))
                  .norm(),
              1e-10 * testing::dense_hessian(term, rest, false).norm())
        << dim;
  }
}

// Meshes above the parallel threshold (512 elements) run the OpenMP path of the assembler:
// checked by directional differences, Hessian-vector products and run-to-run reproducibility.
TEST(MembraneTermTest, LargeMeshesMatchDirectionalDifferences) {
  const ShellMesh mesh = grid_mesh(17, 17, 0.06, 0.06, 0.5);  // 578 triangles, 833 edges
  ASSERT_GT(mesh.triangle_count(), 512);
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const int dim : {2, 3}) {
    const MembraneTerm term(mesh, sample_inplane(), dim);
    const Eigen::VectorXd x = random_deformation(mesh, dim, 50);
    const Eigen::VectorXd d = Eigen::VectorXd::NullaryExpr(x.size(), [&] { return u(rng); });
    expect_directional_derivatives(term, x, d, 0.06);
  }
}

}  // namespace
}  // namespace yarnfit::shell
