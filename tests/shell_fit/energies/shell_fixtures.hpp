#pragma once
// Meshes, states and parameters shared by the shell energy tests (test_inplane_material,
// test_membrane_term, test_bending_term, test_gravity_term), built by hand so that they do
// not depend on shell_fit/mesh.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "numerics/terms/energy_term.hpp"
#include "shell_fit/core/shell_mesh.hpp"
#include "shell_fit/core/shell_params.hpp"
#include "tests/support/derivative_check.hpp"

namespace yarnfit::shell::fixtures {

using testing::DerivativeCheckOptions;
using testing::expect_derivatives_match;
using testing::gradient_of;
inline constexpr double pi = std::numbers::pi;

// (nx × ny) cells on [0, lx] × [0, ly], each split along the same diagonal into two
// counter-clockwise right triangles; interior edges built.
inline ShellMesh grid_mesh(int nx, int ny, double lx, double ly, double material_angle) {
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
inline ShellMesh jittered_mesh(double material_angle, unsigned seed) {
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

inline Eigen::VectorXd embed(const ShellMesh& mesh, int dim) {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(dim * mesh.vertex_count());
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    x(dim * v) = mesh.rest(v, 0);
    x(dim * v + 1) = mesh.rest(v, 1);
  }
  return x;
}

// x = A X + noise: a random affine map near the identity (stretch, shear, in 3-D also a tilt)
// plus per-vertex noise, all far from inversion.
inline Eigen::VectorXd random_deformation(const ShellMesh& mesh, int dim, unsigned seed,
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

inline Eigen::VectorXd add_noise(Eigen::VectorXd x, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  for (Eigen::Index i = 0; i < x.size(); ++i) x(i) += u(rng);
  return x;
}

inline double mesh_size(const ShellMesh& mesh) {
  return (mesh.rest.colwise().maxCoeff() - mesh.rest.colwise().minCoeff()).norm();
}

inline double total_area(const ShellMesh& mesh) {
  double a = 0.0;
  for (int t = 0; t < mesh.triangle_count(); ++t) a += mesh.rest_area(t);
  return a;
}

// Realistic knit stiffnesses [N/m]: strongly anisotropic, with Poisson coupling.
inline InplaneParams sample_inplane() {
  InplaneParams p;
  p.kxx = 60.0;
  p.kxy = 12.0;
  p.kyy = 25.0;
  p.kss = 4.0;
  p.kn1 = 3.0;
  p.kn2 = 2.0;
  return p;
}

// The same with lock-up along weft, warp and shear (the stiffening model), rates from a
// polynomial-like 0.5 to a sharp 6.
inline InplaneParams sample_stiffening() {
  const InplaneParams k = sample_inplane();
  return {k.kxx, k.kxy, k.kyy, k.kss, k.kn1, k.kn2, /*lxx, bxx*/ 400.0, 6.0, /*lyy, byy*/ 150.0, 0.5,
          /*lss, bss*/ 30.0, 3.0, /*axx, ayy*/ 0.4, 0.8};
}

inline std::vector<double> test_angles() { return {0.0, pi / 4.0, pi / 2.0, 0.7313}; }

inline Eigen::Matrix3d rotation3(double a, double b, double c) {
  return (Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(b, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(c, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

inline Eigen::VectorXd affine(const ShellMesh& mesh, const Eigen::Matrix2d& F) {
  Eigen::VectorXd x(2 * mesh.vertex_count());
  for (int v = 0; v < mesh.vertex_count(); ++v)
    x.segment<2>(2 * v) = F * mesh.rest.row(v).transpose();
  return x;
}

inline BendingParams sample_bending() {
  BendingParams p;
  p.ktheta = {2e-6, 3.5e-6, 5e-6};  // N·m, a light knit
  return p;
}

// Rest mesh rolled onto a cylinder of radius R whose axis is the lab x axis: lab y becomes
// arc length, so every rest length along the surface is kept (isometric bending).
inline Eigen::VectorXd rolled(const ShellMesh& mesh, double R) {
  Eigen::VectorXd x(3 * mesh.vertex_count());
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    const double phi = mesh.rest(v, 1) / R;
    x.segment<3>(3 * v) << mesh.rest(v, 0), R * std::sin(phi), R * (1.0 - std::cos(phi));
  }
  return x;
}

inline void expect_directional_derivatives(const numerics::EnergyTerm& term, const Eigen::VectorXd& x,
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

}  // namespace yarnfit::shell::fixtures
