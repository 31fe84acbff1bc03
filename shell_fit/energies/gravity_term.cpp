#include "shell_fit/energies/gravity_term.hpp"
#include "numerics/util/error.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace yarnfit::shell {

GravityTerm::GravityTerm(const ShellMesh& mesh, double areal_density, double g) : m_g(g) {
  if (!std::isfinite(areal_density) || areal_density < 0.0) {
    throw Error(ErrorCategory::input, 
        "GravityTerm: areal density must be finite and >= 0 [kg/m^2], got " +
        std::to_string(areal_density));
  }
  if (!std::isfinite(g) || g < 0.0) {
    throw Error(ErrorCategory::input, "GravityTerm: g must be finite and >= 0 [m/s^2], got " +
                                std::to_string(g));
  }
  m_masses = Eigen::VectorXd::Zero(mesh.vertex_count());
  for (int t = 0; t < mesh.triangle_count(); ++t) {
    const double share = areal_density * mesh.rest_area(t) / 3.0;
    for (int i = 0; i < 3; ++i) m_masses(mesh.triangles(t, i)) += share;
  }
}

void GravityTerm::add_value(const Eigen::VectorXd& x, double& energy) const {
  if (x.size() != dim * m_masses.size()) {
    throw Error(ErrorCategory::input, "GravityTerm::value: expected " +
                                std::to_string(dim * m_masses.size()) + " coordinates, got " +
                                std::to_string(x.size()));
  }
  double e = 0.0;
  for (Eigen::Index v = 0; v < m_masses.size(); ++v) e += m_masses(v) * m_g * x(dim * v + 2);
  energy += e;
}

void GravityTerm::add_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const {
  if (x.size() != dim * m_masses.size() || g.size() != x.size()) {
    throw Error(ErrorCategory::input, "GravityTerm::add_gradient: expected " +
                                std::to_string(dim * m_masses.size()) + " coordinates");
  }
  for (Eigen::Index v = 0; v < m_masses.size(); ++v) g(dim * v + 2) += m_masses(v) * m_g;
}

void GravityTerm::add_hessian(const Eigen::VectorXd& /*x*/, numerics::Triplets& /*h*/,
                              const numerics::HessianOptions& /*options*/) const {
  // Linear energy: nothing to add.
}

}  // namespace yarnfit::shell
