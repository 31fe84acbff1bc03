// Energy terms of the thin shell (thesis 6.3, SPEC §3 "Shell"): finite-difference checks of
// every term's derivatives (through the one routine in derivative_check.hpp) and physics
// checks that would catch a wrong formula with right derivatives.

#include <gtest/gtest-spi.h>
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
#include "shell_fit/energies/gravity_term.hpp"
#include "shell_fit/energies/inplane_material.hpp"
#include "shell_fit/energies/membrane_term.hpp"
#include "tests/shell_fit/derivative_check.hpp"

namespace yarnfit::shell {
namespace {

using testing::DerivativeCheckOptions;
using testing::expect_derivatives_match;
using testing::gradient_of;
constexpr double pi = std::numbers::pi;
using Matrix32 = Eigen::Matrix<double, 3, 2>;

// ---- fixtures built by hand (no dependency on mesh/) ------------------------------------

// (nx × ny) cells on [0, lx] × [0, ly], each split along the same diagonal into two
// counter-clockwise right triangles; interior edges built.
ShellMesh grid_mesh(int nx, int ny, double lx, double ly, double material_angle) {
  ShellMesh mesh;
  mesh.material_angle = material_angle;
  mesh.rest.resize((nx + 1) * (ny + 1), 2);
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      mesh.rest.row(j * (nx + 1) + i) << lx * i / nx, ly * j / ny;
    }
  }
  mesh.triangles.resize(2 * nx * ny, 3);
  int t = 0;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int v00 = j * (nx + 1) + i, v10 = v00 + 1, v01 = v00 + nx + 1, v11 = v01 + 1;
      mesh.triangles.row(t++) << v00, v10, v11;
      mesh.triangles.row(t++) << v00, v11, v01;
    }
  }
  build_interior_edges(mesh);
  return mesh;
}

// A small irregular mesh: the grid with its interior vertices jittered in the rest plane, so
// elements are not all alike.
ShellMesh jittered_mesh(double material_angle, unsigned seed) {
  ShellMesh mesh = grid_mesh(3, 2, 0.03, 0.02, material_angle);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.002, 0.002);
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    const double x = mesh.rest(v, 0), y = mesh.rest(v, 1);
    if (x > 0 && x < 0.03 && y > 0 && y < 0.02)
      mesh.rest.row(v) += Eigen::RowVector2d(u(rng), u(rng));
  }
  return mesh;
}

Eigen::VectorXd embed(const ShellMesh& mesh, int dim) {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(dim * mesh.vertex_count());
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    x(dim * v) = mesh.rest(v, 0);
    x(dim * v + 1) = mesh.rest(v, 1);
  }
  return x;
}

// x = A X + noise: a random affine map near the identity (stretch, shear, in 3-D also a tilt)
// plus per-vertex noise, all far from inversion.
Eigen::VectorXd random_deformation(const ShellMesh& mesh, int dim, unsigned seed,
                                   double strain = 0.15, double noise = 0.05) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(dim, 2);
  A(0, 0) = A(1, 1) = 1.0;
  for (int r = 0; r < dim; ++r) {
    for (int c = 0; c < 2; ++c) A(r, c) += strain * u(rng);
  }
  const double size = (mesh.rest.colwise().maxCoeff() - mesh.rest.colwise().minCoeff()).norm();
  Eigen::VectorXd x(dim * mesh.vertex_count());
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    const Eigen::VectorXd p = A * mesh.rest.row(v).transpose();
    for (int k = 0; k < dim; ++k) x(dim * v + k) = p(k) + noise * size * 0.1 * u(rng);
  }
  return x;
}

Eigen::VectorXd add_noise(Eigen::VectorXd x, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  for (Eigen::Index i = 0; i < x.size(); ++i) x(i) += u(rng);
  return x;
}

double mesh_size(const ShellMesh& mesh) {
  return (mesh.rest.colwise().maxCoeff() - mesh.rest.colwise().minCoeff()).norm();
}

double total_area(const ShellMesh& mesh) {
  double a = 0.0;
  for (int t = 0; t < mesh.triangle_count(); ++t) a += mesh.rest_area(t);
  return a;
}

// Realistic knit stiffnesses [N/m]: strongly anisotropic, with Poisson coupling.
InplaneParams sample_inplane() {
  InplaneParams p;
  p.kxx = 60.0;
  p.kxy = 12.0;
  p.kyy = 25.0;
  p.kss = 4.0;
  p.kn1 = 3.0;
  p.kn2 = 2.0;
  return p;
}

std::vector<double> test_angles() { return {0.0, pi / 4.0, pi / 2.0, 0.7313}; }

Eigen::Matrix3d rotation3(double a, double b, double c) {
  return (Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(b, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(c, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

// ---- InplaneMaterial ------------------------------------------------------------------

// Central differences of a matrix function over a step sweep, best step; relative to ‖·‖∞.
template <typename Fn, typename Arg>
double best_fd_error(const Fn& f, const Arg& F, const Eigen::MatrixXd& analytic) {
  double best = std::numeric_limits<double>::infinity();
  const double norm = std::max(analytic.lpNorm<Eigen::Infinity>(), 1e-300);
  for (double h = 1e-2; h >= 1e-8; h /= 10.0) {
    Eigen::MatrixXd fd(analytic.rows(), analytic.cols());
    for (int c = 0; c < static_cast<int>(F.size()); ++c) {
      Arg Fp = F, Fm = F;
      Fp.data()[c] += h;
      Fm.data()[c] -= h;
      const Eigen::MatrixXd d = (f(Fp) - f(Fm)) / (2.0 * h);
      fd.col(c) = Eigen::Map<const Eigen::VectorXd>(d.data(), d.size());
    }
    best = std::min(best, (fd - analytic).lpNorm<Eigen::Infinity>() / norm);
  }
  return best;
}

TEST(InplaneMaterialTest, DerivativesMatchFiniteDifferences) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  double worst_pk1 = 0.0, worst_dpk1 = 0.0;
  for (const double angle : test_angles()) {
    const InplaneMaterial m(sample_inplane(), angle);
    for (int trial = 0; trial < 5; ++trial) {
      Eigen::Matrix2d F = Eigen::Matrix2d::Identity();
      F += Eigen::Matrix2d::NullaryExpr([&] { return u(rng); });
      ASSERT_GT(F.determinant(), 0.2);
      const auto psi = [&](const Eigen::Matrix2d& G) {
        return Eigen::MatrixXd::Constant(1, 1, m.psi(G));
      };
      const auto pk1 = [&](const Eigen::Matrix2d& G) { return Eigen::MatrixXd(m.pk1(G)); };
      const Eigen::Matrix2d P = m.pk1(F);
      const double e1 = best_fd_error(psi, F, Eigen::Map<const Eigen::RowVector4d>(P.data()));
      const double e2 = best_fd_error(pk1, F, m.dpk1(F));
      EXPECT_LT(e1, 1e-7) << "pk1, angle " << angle;
      EXPECT_LT(e2, 1e-7) << "dpk1, angle " << angle;
      EXPECT_LE((m.dpk1(F) - m.dpk1(F).transpose()).norm(), 1e-10 * m.dpk1(F).norm());
      worst_pk1 = std::max(worst_pk1, e1);
      worst_dpk1 = std::max(worst_dpk1, e2);

      // Surface F (3×2): a tilted, rotated, stretched triangle.
      Matrix32 F3 = rotation3(u(rng), u(rng), u(rng)).leftCols<2>() * F;
      F3 += Matrix32::NullaryExpr([&] { return 0.3 * u(rng); });
      const auto psi3 = [&](const Matrix32& G) {
        return Eigen::MatrixXd::Constant(1, 1, m.psi_surface(G));
      };
      const auto pk13 = [&](const Matrix32& G) { return Eigen::MatrixXd(m.pk1_surface(G)); };
      const Matrix32 P3 = m.pk1_surface(F3);
      const double e3 =
          best_fd_error(psi3, F3, Eigen::Map<const Eigen::Matrix<double, 1, 6>>(P3.data()));
      const double e4 = best_fd_error(pk13, F3, m.dpk1_surface(F3));
      EXPECT_LT(e3, 1e-7) << "3x2 pk1, angle " << angle;
      EXPECT_LT(e4, 1e-7) << "3x2 dpk1, angle " << angle;
      worst_pk1 = std::max(worst_pk1, e3);
      worst_dpk1 = std::max(worst_dpk1, e4);
    }
  }
  std::printf("InplaneMaterial FD: worst best-step rel. error pk1 %.2e, dpk1 %.2e\n", worst_pk1,
              worst_dpk1);
}

TEST(InplaneMaterialTest, ZeroAtRestAndAnalyticUniaxial) {
  const InplaneParams p = sample_inplane();
  for (const double angle : test_angles()) {
    const InplaneMaterial m(p, angle);
    EXPECT_EQ(m.psi(Eigen::Matrix2d::Identity()), 0.0);
    EXPECT_LE(m.pk1(Eigen::Matrix2d::Identity()).norm(), 1e-14);
    EXPECT_EQ(m.psi_surface(Matrix32::Identity()), 0.0);
    EXPECT_LE(m.pk1_surface(Matrix32::Identity()).norm(), 1e-14);
  }
  // F = diag(1+s, 1): E = diag(e, 0), e = ((1+s)² − 1)/2, J = 1 + s.
  const double s = 0.2;
  const double e = 0.5 * ((1 + s) * (1 + s) - 1.0);
  const double area = p.kn1 * s * s + p.kn2 * std::log(1 + s) * std::log(1 + s);
  const Eigen::Matrix2d F = Eigen::Vector2d(1 + s, 1.0).asDiagonal();
  // Weft along lab x: ε = (e, 0, 0).
  EXPECT_NEAR(InplaneMaterial(p, 0.0).psi(F), 0.5 * p.kxx * e * e + area, 1e-13);
  // Warp along lab x: ε = (0, e, 0).
  EXPECT_NEAR(InplaneMaterial(p, pi / 2).psi(F), 0.5 * p.kyy * e * e + area, 1e-13);
  // Bias: E_m = Rᵀ diag(e, 0) R = [[e/2, −e/2], [−e/2, e/2]], ε = (e/2, e/2, −e).
  const double bias =
      0.5 * (p.kxx * e * e / 4 + 2 * p.kxy * e * e / 4 + p.kyy * e * e / 4 + p.kss * e * e);
  EXPECT_NEAR(InplaneMaterial(p, pi / 4).psi(F), bias + area, 1e-13);
  // The stretch stress is P00 = (1+s) S00 + f'(J) (thesis: σ_s = uᵀ P u).
  const double f1 = 2 * p.kn1 * s + 2 * p.kn2 * std::log(1 + s) / (1 + s);
  EXPECT_NEAR(InplaneMaterial(p, 0.0).pk1(F)(0, 0), (1 + s) * p.kxx * e + f1, 1e-12);
  // The orthogonal stress carries the Poisson coupling: P11 = S11 + f'(J) (1+s) = kxy e + …
  EXPECT_NEAR(InplaneMaterial(p, 0.0).pk1(F)(1, 1), p.kxy * e + f1 * (1 + s), 1e-12);
}

TEST(InplaneMaterialTest, SurfaceMatchesPlanarForAnyEmbedding) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  for (const double angle : test_angles()) {
    const InplaneMaterial m(sample_inplane(), angle);
    for (int trial = 0; trial < 4; ++trial) {
      Eigen::Matrix2d F =
          Eigen::Matrix2d::Identity() + Eigen::Matrix2d::NullaryExpr([&] { return u(rng); });
      const Eigen::Matrix3d Q = rotation3(3 * u(rng), 3 * u(rng), 3 * u(rng));
      const Matrix32 F3 = Q.leftCols<2>() * F;
      EXPECT_NEAR(m.psi_surface(F3), m.psi(F), 1e-12 * std::max(1.0, m.psi(F)));
      // P3 = Q P (the stress rotates with the embedding).
      EXPECT_LE((m.pk1_surface(F3) - Q.leftCols<2>() * m.pk1(F)).norm(), 1e-11 * m.pk1(F).norm());
    }
  }
}

TEST(InplaneMaterialTest, InversionGivesInfinityNeverNaN) {
  const InplaneParams p = sample_inplane();
  const InplaneMaterial m(p, 0.3);
  Eigen::Matrix2d inverted;
  inverted << -0.8, 0.1, 0.05, 1.1;  // det < 0
  EXPECT_EQ(m.psi(inverted), std::numeric_limits<double>::infinity());
  EXPECT_TRUE(m.pk1(inverted).isZero());
  EXPECT_TRUE(m.dpk1(inverted).isZero());
  const Eigen::Matrix2d collapsed = Eigen::Vector2d(1.0, 0.0).asDiagonal();  // J = 0
  EXPECT_EQ(m.psi(collapsed), std::numeric_limits<double>::infinity());
  EXPECT_TRUE(m.pk1(collapsed).allFinite());
  // Without the log barrier the signed J enters (J − 1)² as in plain StVK: finite, smooth.
  InplaneParams q = p;
  q.kn2 = 0.0;
  const InplaneMaterial plain(q, 0.3);
  const double J = inverted.determinant();
  const InplaneMaterial stvk_only({q.kxx, q.kxy, q.kyy, q.kss, 0.0, 0.0}, 0.3);
  EXPECT_NEAR(plain.psi(inverted), stvk_only.psi(inverted) + q.kn1 * (J - 1) * (J - 1), 1e-12);
  EXPECT_TRUE(plain.pk1(inverted).allFinite());
  EXPECT_TRUE(plain.dpk1(inverted).allFinite());
  // Surface F of rank 1 (a triangle collapsed onto a line in 3-D).
  Matrix32 degenerate;
  degenerate << 1.0, 2.0, 0.5, 1.0, 0.0, 0.0;
  EXPECT_EQ(m.psi_surface(degenerate), std::numeric_limits<double>::infinity());
  EXPECT_TRUE(m.pk1_surface(degenerate).allFinite());
  EXPECT_TRUE(m.dpk1_surface(degenerate).allFinite());
  EXPECT_TRUE(std::isfinite(plain.psi_surface(degenerate)));
  EXPECT_TRUE(plain.pk1_surface(degenerate).allFinite());
  EXPECT_TRUE(plain.dpk1_surface(degenerate).allFinite());
}

// ---- MembraneTerm ---------------------------------------------------------------------

TEST(MembraneTermTest, DerivativesMatchFiniteDifferences) {
  double worst_g = 0.0, worst_h = 0.0;
  unsigned seed = 1;
  for (const int dim : {2, 3}) {
    for (const double angle : test_angles()) {
      const ShellMesh mesh = jittered_mesh(angle, seed);
      const MembraneTerm term(mesh, sample_inplane(), dim);
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

Eigen::VectorXd affine(const ShellMesh& mesh, const Eigen::Matrix2d& F) {
  Eigen::VectorXd x(2 * mesh.vertex_count());
  for (int v = 0; v < mesh.vertex_count(); ++v)
    x.segment<2>(2 * v) = F * mesh.rest.row(v).transpose();
  return x;
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
  const InplaneParams p = sample_inplane();
  for (const int dim : {2, 3}) {
    const ShellMesh mesh = jittered_mesh(0.6, 9);
    const Eigen::VectorXd x = random_deformation(mesh, dim, 33);
    const MembraneTerm term(mesh, p, dim);
    const Eigen::Matrix<double, 6, 1> v = term.value_per_parameter(x);
    Eigen::MatrixXd G = Eigen::MatrixXd::Zero(x.size(), 6);
    term.add_gradient_per_parameter(x, G);
    const std::array<double, 6> base{p.kxx, p.kxy, p.kyy, p.kss, p.kn1, p.kn2};
    // E is linear in p: E = Σ p_k ∂E/∂p_k.
    double sum = 0.0;
    for (int k = 0; k < 6; ++k) sum += base[static_cast<std::size_t>(k)] * v(k);
    EXPECT_NEAR(sum, term.value(x), 1e-12 * term.value(x));
    for (int k = 0; k < 6; ++k) {
      const double h = 1e-3 * base[static_cast<std::size_t>(k)];
      std::array<double, 6> up = base, down = base;
      up[static_cast<std::size_t>(k)] += h;
      down[static_cast<std::size_t>(k)] -= h;
      const MembraneTerm tu(mesh, {up[0], up[1], up[2], up[3], up[4], up[5]}, dim);
      const MembraneTerm td(mesh, {down[0], down[1], down[2], down[3], down[4], down[5]}, dim);
      const double fd_value = (tu.value(x) - td.value(x)) / (2 * h);
      const Eigen::VectorXd fd_grad = (gradient_of(tu, x) - gradient_of(td, x)) / (2 * h);
      EXPECT_NEAR(fd_value, v(k), 1e-8 * std::abs(v(k))) << "parameter " << k << ", dim " << dim;
      EXPECT_LE((fd_grad - G.col(k)).lpNorm<Eigen::Infinity>(),
                1e-8 * G.col(k).lpNorm<Eigen::Infinity>())
          << "parameter " << k << ", dim " << dim;
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

// ---- BendingTerm ----------------------------------------------------------------------

BendingParams sample_bending() {
  BendingParams p;
  p.ktheta = {2e-6, 3.5e-6, 5e-6};  // N·m, a light knit
  return p;
}

// Rest mesh rolled onto a cylinder of radius R whose axis is the lab x axis: lab y becomes
// arc length, so every rest length along the surface is kept (isometric bending).
Eigen::VectorXd rolled(const ShellMesh& mesh, double R) {
  Eigen::VectorXd x(3 * mesh.vertex_count());
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    const double phi = mesh.rest(v, 1) / R;
    x.segment<3>(3 * v) << mesh.rest(v, 0), R * std::sin(phi), R * (1.0 - std::cos(phi));
  }
  return x;
}

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

// Meshes above the parallel threshold (512 elements) run the OpenMP path: check it by
// directional differences, Hessian-vector products, and run-to-run reproducibility.
void expect_directional_derivatives(const EnergyTerm& term, const Eigen::VectorXd& x,
                                    const Eigen::VectorXd& direction, double length_scale) {
  const Eigen::VectorXd g = gradient_of(term, x);
  const Eigen::MatrixXd H = testing::dense_hessian(term, x, false);
  double best_value = std::numeric_limits<double>::infinity(), best_hv = best_value;
  for (double h = 1e-3 * length_scale; h >= 1e-9 * length_scale; h /= 10.0) {
    const double fd = (term.value(x + h * direction) - term.value(x - h * direction)) / (2 * h);
    best_value = std::min(best_value, std::abs(fd - g.dot(direction)) / std::abs(g.dot(direction)));
    const Eigen::VectorXd hv =
        (gradient_of(term, x + h * direction) - gradient_of(term, x - h * direction)) / (2 * h);
    best_hv = std::min(best_hv, (hv - H * direction).lpNorm<Eigen::Infinity>() /
                                    (H * direction).lpNorm<Eigen::Infinity>());
  }
  EXPECT_LT(best_value, 1e-6) << term.name();
  EXPECT_LT(best_hv, 1e-6) << term.name();
  EXPECT_EQ(term.value(x), term.value(x)) << term.name();
  EXPECT_EQ(gradient_of(term, x), g) << term.name();
}

TEST(EnergyParallelAssemblyTest, LargeMeshesMatchDirectionalDifferences) {
  const ShellMesh mesh = grid_mesh(17, 17, 0.06, 0.06, 0.5);  // 578 triangles, 833 edges
  ASSERT_GT(mesh.triangle_count(), 512);
  ASSERT_GT(static_cast<int>(mesh.interior_edges.size()), 512);
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const int dim : {2, 3}) {
    const MembraneTerm term(mesh, sample_inplane(), dim);
    const Eigen::VectorXd x = random_deformation(mesh, dim, 50);
    const Eigen::VectorXd d = Eigen::VectorXd::NullaryExpr(x.size(), [&] { return u(rng); });
    expect_directional_derivatives(term, x, d, 0.06);
  }
  const BendingTerm bending(mesh, sample_bending());
  const Eigen::VectorXd x = add_noise(rolled(mesh, 0.03), 3e-4, 51);
  const Eigen::VectorXd d = Eigen::VectorXd::NullaryExpr(x.size(), [&] { return u(rng); });
  expect_directional_derivatives(bending, x, d, 0.06);
}

// ---- the checking routine itself ------------------------------------------------------

// E = Σ x_i³ with a deliberately wrong gradient or Hessian (relative error 1e-4).
class CubicTerm final : public EnergyTerm {
 public:
  CubicTerm(double gradient_error, double hessian_error)
      : m_gradient_error(gradient_error), m_hessian_error(hessian_error) {}
  [[nodiscard]] std::string name() const override { return "cubic"; }
  [[nodiscard]] double value(const Eigen::VectorXd& x) const override {
    return x.array().cube().sum();
  }
  void add_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override {
    g.array() += 3.0 * (1.0 + m_gradient_error) * x.array().square();
  }
  void add_hessian(const Eigen::VectorXd& x, Triplets& h, bool /*project_psd*/) const override {
    for (Eigen::Index i = 0; i < x.size(); ++i) {
      h.emplace_back(static_cast<int>(i), static_cast<int>(i),
                     6.0 * (1.0 + m_hessian_error) * std::abs(x(i)));
    }
  }

 private:
  double m_gradient_error, m_hessian_error;
};

TEST(EnergyDerivativeCheckTest, DetectsWrongDerivatives) {
  const Eigen::VectorXd x = Eigen::Vector3d(0.3, 0.7, 1.1);
  DerivativeCheckOptions o;
  o.check_psd_projection = false;
  expect_derivatives_match(CubicTerm(0.0, 0.0), x, o);  // x > 0: |x| = x, all consistent
  o.check_hessian = false;
  EXPECT_NONFATAL_FAILURE(expect_derivatives_match(CubicTerm(1e-4, 0.0), x, o),
                          "gradient vs FD of value");
  o.check_hessian = true;
  EXPECT_NONFATAL_FAILURE(expect_derivatives_match(CubicTerm(0.0, 1e-4), x, o),
                          "Hessian vs FD of gradient");
}

// ---- GravityTerm ----------------------------------------------------------------------

TEST(GravityTermTest, LiftedFlatSheetWeighsTotalMassTimesHeight) {
  const ShellMesh mesh = jittered_mesh(0.0, 4);
  const double rho = 0.25;  // kg/m²
  const double lift = 0.037;
  const GravityTerm term(mesh, rho);
  EXPECT_NEAR(term.total_mass(), rho * total_area(mesh), 1e-15);
  Eigen::VectorXd x = embed(mesh, 3);
  EXPECT_EQ(term.value(x), 0.0);
  for (int v = 0; v < mesh.vertex_count(); ++v) x(3 * v + 2) += lift;
  EXPECT_NEAR(term.value(x), rho * total_area(mesh) * 9.81 * lift, 1e-15);
  // Any in-plane motion leaves the energy unchanged; the gradient is the weight per vertex.
  const Eigen::VectorXd g = gradient_of(term, random_deformation(mesh, 3, 8));
  EXPECT_NEAR(g.sum(), term.total_mass() * 9.81, 1e-15);
  Triplets h;
  term.add_hessian(x, h, true);
  EXPECT_TRUE(h.empty());
  DerivativeCheckOptions o;
  o.length_scale = mesh_size(mesh);
  const auto r = expect_derivatives_match(term, random_deformation(mesh, 3, 12), o);
  std::printf("GravityTerm FD: gradient %.2e, Hessian %.2e\n", r.gradient_error, r.hessian_error);
}

}  // namespace
}  // namespace yarnfit::shell
