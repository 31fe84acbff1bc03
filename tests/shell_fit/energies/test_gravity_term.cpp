// Gravity with lumped masses (shell_fit/energies/gravity_term.hpp): the weight of a lifted
// sheet, its constant gradient, no Hessian, and the derivative check.

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
#include "shell_fit/energies/gravity_term.hpp"
#include "tests/shell_fit/energies/shell_fixtures.hpp"

namespace yarnfit::shell {
namespace {

using namespace fixtures;
using Matrix32 = Eigen::Matrix<double, 3, 2>;

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
  numerics::Triplets h;
  term.add_hessian(x, h, {true, false});
  EXPECT_TRUE(h.empty());
  DerivativeCheckOptions o;
  o.length_scale = mesh_size(mesh);
  const auto r = expect_derivatives_match(term, random_deformation(mesh, 3, 12), o);
  std::printf("GravityTerm FD: gradient %.2e, Hessian %.2e\n", r.gradient_error, r.hessian_error);
}

}  // namespace
}  // namespace yarnfit::shell
