#include "shell_fit/energies/bending_term.hpp"

#include <numbers>

#include <Eigen/Geometry>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>

#include "numerics/psd_projection.hpp"
#include "numerics/terms/element_assembly.hpp"
#include "numerics/util/error.hpp"

namespace yarnfit::shell {

namespace {

using Vector12 = Eigen::Matrix<double, 12, 1>;
using Matrix12 = Eigen::Matrix<double, 12, 12>;

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d s;
  s << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return s;
}

// The four stencil positions: x0, x1 (the edge), xa, xb (opposite vertices).
struct Stencil {
  std::array<Eigen::Vector3d, 4> p;
};

Stencil gather(const BendingTerm::Edge& e, const Eigen::VectorXd& x) {
  Stencil s;
  for (std::size_t i = 0; i < 4; ++i) s.p[i] = x.segment<3>(3 * e.v[i]);
  return s;
}

double dihedral(const Stencil& s) {
  const Eigen::Vector3d e = s.p[1] - s.p[0];
  const Eigen::Vector3d na = e.cross(s.p[2] - s.p[0]);
  const Eigen::Vector3d nb = (s.p[3] - s.p[0]).cross(e);
  const double len = e.norm();
  if (!(len > 0.0)) return 0.0;
  // atan2(sin, cos) with both scaled by |n_a||n_b|, which atan2 ignores.
  return std::atan2(nb.cross(na).dot(e) / len, na.dot(nb));
}

// θ, ∇θ and (optionally) ∇²θ of one stencil. Returns false where the stencil is degenerate
// (a zero-length edge or a zero-area deformed triangle): the derivatives are unbounded
// there, and the caller then adds nothing rather than NaN.
bool dihedral_derivatives(const Stencil& s, double& theta, Vector12& grad, Matrix12* hess) {
  const Eigen::Vector3d& x0 = s.p[0];
  const Eigen::Vector3d& x1 = s.p[1];
  const Eigen::Vector3d& xa = s.p[2];
  const Eigen::Vector3d& xb = s.p[3];
  const Eigen::Vector3d e = x1 - x0;
  const double L = e.norm();
  const std::array<Eigen::Vector3d, 2> n{e.cross(xa - x0), (xb - x0).cross(e)};
  const std::array<double, 2> n2{n[0].squaredNorm(), n[1].squaredNorm()};
  theta = dihedral(s);
  if (!(L > 0.0) || !(n2[0] > 0.0) || !(n2[1] > 0.0)) return false;
  const Eigen::Vector3d eh = e / L;
  const std::array<Eigen::Vector3d, 2> w{n[0] / n2[0], n[1] / n2[1]};

  // ∂θ/∂x_i = Σ_t c[i][t] w_t (Bridson et al. 2003), t = 0 for triangle (x0, x1, xa), 1 for b.
  const std::array<const Eigen::Vector3d*, 2> opp{&xa, &xb};
  double c[4][2];
  for (std::size_t t = 0; t < 2; ++t) {
    c[0][t] = (*opp[t] - x1).dot(eh);
    c[1][t] = -(*opp[t] - x0).dot(eh);
    c[2][t] = t == 0 ? L : 0.0;
    c[3][t] = t == 1 ? L : 0.0;
  }
  for (int i = 0; i < 4; ++i) grad.segment<3>(3 * i) = c[i][0] * w[0] + c[i][1] * w[1];
  if (hess == nullptr) return true;

  // ∂n_t/∂x_j (3×3 blocks): n_a = e × (xa − x0), n_b = (xb − x0) × e.
  std::array<std::array<Eigen::Matrix3d, 4>, 2> dn;
  dn[0] = {skew(xa - x1), -skew(xa - x0), skew(e), Eigen::Matrix3d::Zero()};
  dn[1] = {-skew(xb - x1), skew(xb - x0), Eigen::Matrix3d::Zero(), -skew(e)};
  // ∂w_t = M_t ∂n_t with M_t = (I − 2 n̂ n̂ᵀ)/|n|².
  std::array<Eigen::Matrix3d, 2> M;
  for (std::size_t t = 0; t < 2; ++t) {
    M[t] = (Eigen::Matrix3d::Identity() - 2.0 * n[t] * n[t].transpose() / n2[t]) / n2[t];
  }
  // Gradients of the coefficients c[i][t] (12-vectors). ∂ê/∂x1 = Π/L = −∂ê/∂x0, Π = I − êêᵀ.
  const Eigen::Matrix3d Pi = Eigen::Matrix3d::Identity() - eh * eh.transpose();
  // d/dx of (p − q)·ê, p at block ip, q at block iq.
  const auto projection_gradient = [&](const Eigen::Vector3d& p, int ip, const Eigen::Vector3d& q,
                                       int iq) {
    Vector12 g = Vector12::Zero();
    g.segment<3>(3 * ip) += eh;
    g.segment<3>(3 * iq) -= eh;
    const Eigen::Vector3d r = Pi * (p - q) / L;
    g.segment<3>(3) += r;
    g.segment<3>(0) -= r;
    return g;
  };
  Vector12 dL = Vector12::Zero();
  dL.segment<3>(0) = -eh;
  dL.segment<3>(3) = eh;
  std::array<std::array<Vector12, 2>, 4> dc;
  for (std::size_t t = 0; t < 2; ++t) {
    const int io = 2 + static_cast<int>(t);
    dc[0][t] = projection_gradient(*opp[t], io, x1, 1);
    dc[1][t] = -projection_gradient(*opp[t], io, x0, 0);
    dc[2][t] = t == 0 ? dL : Vector12::Zero();
    dc[3][t] = t == 1 ? dL : Vector12::Zero();
  }
  Matrix12& H = *hess;
  H.setZero();
  for (std::size_t i = 0; i < 4; ++i) {
    for (std::size_t t = 0; t < 2; ++t) {
      // w_t ⊗ ∂c[i][t]: the row block of x_i over all 12 columns.
      H.block<3, 12>(3 * static_cast<int>(i), 0).noalias() += w[t] * dc[i][t].transpose();
      if (c[i][t] == 0.0) continue;
      for (std::size_t j = 0; j < 4; ++j) {
        H.block<3, 3>(3 * static_cast<int>(i), 3 * static_cast<int>(j)).noalias() +=
            c[i][t] * (M[t] * dn[t][j]);
      }
    }
  }
  // Symmetric analytically; drop the round-off asymmetry.
  H = 0.5 * (H + H.transpose()).eval();
  return true;
}

void check_bending_size(const Eigen::VectorXd& x, int dofs, const char* what) {
  if (x.size() != dofs) {
    throw Error(ErrorCategory::input, std::string("BendingTerm::") + what + ": expected " +
                                std::to_string(dofs) + " coordinates, got " +
                                std::to_string(x.size()));
  }
}

// A_e / H²: the energy of edge e per unit k_θ and unit θ² (κ = θ/H, see the header).
double edge_weight(const BendingTerm::Edge& e) {
  return e.area / (e.rest_height * e.rest_height);
}

// One edge as a kernel of the assembler (numerics/terms/element_assembly.hpp), with the
// stiffness of each edge given by `stiffness` (k_θ(e), or a weight for the per-parameter
// derivatives).
template <typename Stiffness>
struct EdgeKernel {
  static constexpr int nodes_per_element = 4;
  static constexpr int dofs_per_node = 3;
  static constexpr numerics::ElementSum summation = numerics::ElementSum::per_term;
  static constexpr bool zero_energy_is_inactive = false;
  static constexpr int parallel_threshold = 512;  // fewer elements: the OpenMP team costs more than it saves

  const std::vector<BendingTerm::Edge>& edges;
  Stiffness stiffness;

  [[nodiscard]] int element_count() const { return static_cast<int>(edges.size()); }
  [[nodiscard]] std::array<int, 4> element_nodes(int k) const { return edges[static_cast<std::size_t>(k)].v; }
  // E_e = k_θ(e) (A_e / H²) θ² and its derivatives 2 c θ ∇θ, 2 c (∇θ∇θᵀ + θ∇²θ); the energy
  // is computed only when no derivative is asked for (0 otherwise). A degenerate stencil has
  // zero derivatives.
  double element(int k, const Eigen::VectorXd& x, Vector12* gradient, Matrix12* hessian, bool project_psd) const {
    const BendingTerm::Edge& e = edges[static_cast<std::size_t>(k)];
    const double c = stiffness(e) * edge_weight(e);
    if (gradient == nullptr && hessian == nullptr) {
      const double theta = dihedral(gather(e, x));
      return c * theta * theta;
    }
    double theta = 0.0;
    Vector12 grad;
    Matrix12 hess;
    const bool ok = dihedral_derivatives(gather(e, x), theta, grad, hessian != nullptr ? &hess : nullptr);
    if (gradient != nullptr) {
      if (ok) *gradient = (2.0 * c * theta) * grad;
      else gradient->setZero();
    }
    if (hessian != nullptr) {
      hessian->setZero();
      if (ok) {
        *hessian = (2.0 * c) * (grad * grad.transpose() + theta * hess);
        if (project_psd) numerics::project_psd<12>(*hessian);
      }
    }
    return 0.0;
  }
};

template <typename Stiffness>
EdgeKernel<Stiffness> edge_kernel(const std::vector<BendingTerm::Edge>& edges, Stiffness stiffness) {
  return {edges, std::move(stiffness)};
}

const auto k_edge_stiffness = [](const BendingTerm::Edge& e) { return e.ktheta; };

}  // namespace

BendingTerm::BendingTerm(const ShellMesh& mesh, const BendingParams& params)
    : m_vertex_count(mesh.vertex_count()), m_params(params) {
  m_edges.reserve(mesh.interior_edges.size());
  for (const InteriorEdge& ie : mesh.interior_edges) {
    Edge e;
    e.v = {ie.v0, ie.v1, ie.a, ie.b};
    // Orient the edge as triangle t0 runs it (v0 → v1 counter-clockwise, a on the left), so
    // n_a and n_b are the rest normals of the CCW triangles and the sign of θ means the same
    // on every edge.
    {
      const Eigen::Vector2d d0 = mesh.rest.row(ie.v1) - mesh.rest.row(ie.v0);
      const Eigen::Vector2d r0 = mesh.rest.row(ie.a) - mesh.rest.row(ie.v0);
      if (d0.x() * r0.y() - d0.y() * r0.x() < 0.0) std::swap(e.v[0], e.v[1]);
    }
    const Eigen::Vector2d X0 = mesh.rest.row(e.v[0]).transpose();
    const Eigen::Vector2d d = mesh.rest.row(e.v[1]).transpose() - X0;
    const double L = d.norm();
    const auto altitude = [&](int v) {
      const Eigen::Vector2d r = mesh.rest.row(v).transpose() - X0;
      return std::abs(d.x() * r.y() - d.y() * r.x()) / L;
    };
    const double ha = L > 0.0 ? altitude(ie.a) : 0.0;
    const double hb = L > 0.0 ? altitude(ie.b) : 0.0;
    if (!(ha > 0.0) || !(hb > 0.0)) {
      throw Error(ErrorCategory::input, "BendingTerm: degenerate rest triangle at interior edge (" +
                                  std::to_string(ie.v0) + ", " + std::to_string(ie.v1) + ")");
    }
    e.rest_height = 0.5 * (ha + hb);
    // The full rest area of the two incident triangles (½ L h each), see the header.
    e.area = 0.5 * L * ha + 0.5 * L * hb;
    e.rest_angle = std::atan2(d.y(), d.x()) - mesh.material_angle;
    for (std::size_t j = 0; j < 3; ++j) {
      BendingParams unit;
      unit.ktheta[j] = 1.0;
      // An edge folds under curvature *across* it: it measures the bending stiffness of the
      // direction perpendicular to it (a weft bending test folds the edges that cross the weft).
      e.weights[j] = interpolate_ktheta(unit, e.rest_angle + std::numbers::pi / 2.0);
    }
    m_edges.push_back(e);
  }
  set_params(params);
}

void BendingTerm::set_params(const BendingParams& params) {
  m_params = params;
  for (Edge& e : m_edges) {
    e.ktheta = e.weights[0] * params.ktheta[0] + e.weights[1] * params.ktheta[1] +
               e.weights[2] * params.ktheta[2];
  }
}

double BendingTerm::dihedral_angle(const Eigen::VectorXd& x, int e) const {
  check_bending_size(x, dof_count(), "dihedral_angle");
  return dihedral(gather(m_edges.at(static_cast<std::size_t>(e)), x));
}

double BendingTerm::curvature(const Eigen::VectorXd& x, int e) const {
  return dihedral_angle(x, e) / m_edges.at(static_cast<std::size_t>(e)).rest_height;
}

void BendingTerm::add_value(const Eigen::VectorXd& x, double& energy) const {
  check_bending_size(x, dof_count(), "value");
  numerics::add_element_values(edge_kernel(m_edges, k_edge_stiffness), x, energy);
}

void BendingTerm::add_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const {
  check_bending_size(x, dof_count(), "add_gradient");
  check_bending_size(g, dof_count(), "add_gradient (gradient buffer)");
  numerics::add_element_gradients(edge_kernel(m_edges, k_edge_stiffness), x, g.data());
}

void BendingTerm::add_hessian(const Eigen::VectorXd& x, numerics::Triplets& h,
                              const numerics::HessianOptions& options) const {
  check_bending_size(x, dof_count(), "add_hessian");
  numerics::add_element_hessians(edge_kernel(m_edges, k_edge_stiffness), x, h, options);
}

void BendingTerm::add_gradient_per_parameter(const Eigen::VectorXd& x, Eigen::MatrixXd& G) const {
  check_bending_size(x, dof_count(), "add_gradient_per_parameter");
  if (G.rows() != dof_count() || G.cols() != parameter_count) {
    throw Error(ErrorCategory::input, "BendingTerm::add_gradient_per_parameter: G must be " +
                                std::to_string(dof_count()) + " x 3, got " +
                                std::to_string(G.rows()) + " x " + std::to_string(G.cols()));
  }
  for (std::size_t j = 0; j < 3; ++j) {
    numerics::add_element_gradients(edge_kernel(m_edges, [j](const Edge& e) { return e.weights[j]; }), x,
                                    G.col(static_cast<Eigen::Index>(j)).data());
  }
}

Eigen::Vector3d BendingTerm::value_per_parameter(const Eigen::VectorXd& x) const {
  check_bending_size(x, dof_count(), "value_per_parameter");
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  for (const Edge& e : m_edges) {
    const double theta = dihedral(gather(e, x));
    const double u = edge_weight(e) * theta * theta;
    for (std::size_t j = 0; j < 3; ++j) v(static_cast<Eigen::Index>(j)) += e.weights[j] * u;
  }
  return v;
}

}  // namespace yarnfit::shell
