#include "shell_fit/energies/membrane_term.hpp"

#include <Eigen/LU>
#include <cstddef>
#include <stdexcept>
#include <string>

#include "numerics/psd_projection.hpp"
#include "numerics/terms/element_assembly.hpp"
#include "numerics/util/error.hpp"

namespace yarnfit::shell {

namespace {

std::vector<InplaneMaterial> unit_materials(const InplaneParams& p, double angle) {
  std::vector<InplaneMaterial> out;
  out.reserve(MembraneTerm::parameter_count);
  for (int k = 0; k < MembraneTerm::parameter_count; ++k) out.push_back(InplaneMaterial::parameter_derivative(p, angle, k));
  return out;
}

// The per-element kernels, written once for dim = 2 and dim = 3 (Dim rows of F).
template <int Dim>
struct Kernel {
  static constexpr int n = 3 * Dim;  // local dofs
  using MatrixF = Eigen::Matrix<double, Dim, 2>;
  using VectorL = Eigen::Matrix<double, n, 1>;
  using MatrixL = Eigen::Matrix<double, n, n>;

  static MatrixF deformation_gradient(const MembraneTerm::Element& e, const Eigen::VectorXd& x) {
    MatrixF F = MatrixF::Zero();
    for (int i = 0; i < 3; ++i) {
      F.noalias() += x.segment<Dim>(Dim * e.v[static_cast<std::size_t>(i)]) * e.b.row(i);
    }
    return F;
  }

  // The planar and the surface law (J = det F vs J = √det C).
  static double psi(const InplaneMaterial& m, const MatrixF& F) {
    if constexpr (Dim == 2) {
      return m.psi(F);
    } else {
      return m.psi_surface(F);
    }
  }
  static MatrixF pk1(const InplaneMaterial& m, const MatrixF& F) {
    if constexpr (Dim == 2) {
      return m.pk1(F);
    } else {
      return m.pk1_surface(F);
    }
  }
  static Eigen::Matrix<double, 2 * Dim, 2 * Dim> dpk1(const InplaneMaterial& m, const MatrixF& F) {
    if constexpr (Dim == 2) {
      return m.dpk1(F);
    } else {
      return m.dpk1_surface(F);
    }
  }

  static double value(const InplaneMaterial& m, const MembraneTerm::Element& e,
                      const Eigen::VectorXd& x) {
    return e.area * psi(m, deformation_gradient(e, x));
  }

  // ∂E_t/∂x_i = A P b_i
  static VectorL gradient(const InplaneMaterial& m, const MembraneTerm::Element& e,
                          const Eigen::VectorXd& x) {
    const MatrixF P = pk1(m, deformation_gradient(e, x));
    VectorL g;
    for (int i = 0; i < 3; ++i)
      g.template segment<Dim>(Dim * i) = e.area * (P * e.b.row(i).transpose());
    return g;
  }

  // A Gᵀ (∂P/∂F) G with G = ∂vec(F)/∂x_local: G(k + Dim j, Dim i + k) = b_i[j].
  static MatrixL hessian(const InplaneMaterial& m, const MembraneTerm::Element& e,
                         const Eigen::VectorXd& x) {
    const auto D = dpk1(m, deformation_gradient(e, x));
    Eigen::Matrix<double, 2 * Dim, n> G = Eigen::Matrix<double, 2 * Dim, n>::Zero();
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 2; ++j) {
        for (int k = 0; k < Dim; ++k) G(k + Dim * j, Dim * i + k) = e.b(i, j);
      }
    }
    return e.area * (G.transpose() * D * G);
  }
};

void check_membrane_size(const Eigen::VectorXd& x, int dofs, const char* what) {
  if (x.size() != dofs) {
    throw Error(ErrorCategory::input, std::string("MembraneTerm::") + what + ": expected " +
                                std::to_string(dofs) + " coordinates, got " +
                                std::to_string(x.size()));
  }
}

// One membrane element as a kernel of the assembler (numerics/terms/element_assembly.hpp),
// for the working law or one of the unit-parameter laws.
template <int Dim>
struct MembraneKernel {
  using K = Kernel<Dim>;
  static constexpr int nodes_per_element = 3;
  static constexpr int dofs_per_node = Dim;
  static constexpr numerics::ElementSum summation = numerics::ElementSum::per_term;
  static constexpr bool zero_energy_is_inactive = false;
  static constexpr int parallel_threshold = 512;  // fewer elements: the OpenMP team costs more than it saves

  const std::vector<MembraneTerm::Element>& elements;
  const InplaneMaterial& material;

  [[nodiscard]] int element_count() const { return static_cast<int>(elements.size()); }
  [[nodiscard]] std::array<int, 3> element_nodes(int e) const { return elements[static_cast<std::size_t>(e)].v; }
  // The energy when no derivative is asked for; with derivatives it is not computed (0).
  double element(int e, const Eigen::VectorXd& x, typename K::VectorL* gradient, typename K::MatrixL* hessian,
                 bool project_psd) const {
    const auto& el = elements[static_cast<std::size_t>(e)];
    if (gradient != nullptr) *gradient = K::gradient(material, el, x);
    if (hessian != nullptr) {
      *hessian = K::hessian(material, el, x);
      if (project_psd) numerics::project_psd<K::n>(*hessian);
    }
    return gradient == nullptr && hessian == nullptr ? K::value(material, el, x) : 0.0;
  }
};

// Calls f(kernel) with the kernel of the term's dimension.
template <class F>
void with_kernel(int dim, const std::vector<MembraneTerm::Element>& elements, const InplaneMaterial& m, F&& f) {
  if (dim == 2) {
    f(MembraneKernel<2>{elements, m});
  } else {
    f(MembraneKernel<3>{elements, m});
  }
}

}  // namespace

MembraneTerm::MembraneTerm(const ShellMesh& mesh, const InplaneParams& params, int dim)
    : m_dim(dim),
      m_vertex_count(mesh.vertex_count()),
      m_material(params, mesh.material_angle),
      m_unit_materials(unit_materials(params, mesh.material_angle)) {
  if (dim != 2 && dim != 3) {
    throw Error(ErrorCategory::input, "MembraneTerm: dim must be 2 or 3, got " + std::to_string(dim));
  }
  m_elements.reserve(static_cast<std::size_t>(mesh.triangle_count()));
  for (int t = 0; t < mesh.triangle_count(); ++t) {
    Element e;
    for (int i = 0; i < 3; ++i) e.v[static_cast<std::size_t>(i)] = mesh.triangles(t, i);
    const Eigen::Vector2d X0 = mesh.rest.row(e.v[0]).transpose();
    Eigen::Matrix2d Dm;
    Dm.col(0) = mesh.rest.row(e.v[1]).transpose() - X0;
    Dm.col(1) = mesh.rest.row(e.v[2]).transpose() - X0;
    e.area = 0.5 * Dm.determinant();
    if (!(e.area > 0.0)) {
      throw Error(ErrorCategory::input, "MembraneTerm: triangle " + std::to_string(t) +
                                  " has non-positive rest area (must be counter-clockwise)");
    }
    const Eigen::Matrix2d Dm_inv = Dm.inverse();
    e.b.row(1) = Dm_inv.row(0);
    e.b.row(2) = Dm_inv.row(1);
    e.b.row(0) = -(Dm_inv.row(0) + Dm_inv.row(1));
    m_elements.push_back(e);
  }
}

void MembraneTerm::set_params(const InplaneParams& params) {
  m_material = InplaneMaterial(params, m_material.material_angle());
  m_unit_materials = unit_materials(params, m_material.material_angle());
}

void MembraneTerm::add_value(const Eigen::VectorXd& x, double& energy) const {
  check_membrane_size(x, dof_count(), "value");
  with_kernel(m_dim, m_elements, m_material, [&](const auto& k) { numerics::add_element_values(k, x, energy); });
}

void MembraneTerm::add_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const {
  check_membrane_size(x, dof_count(), "add_gradient");
  check_membrane_size(g, dof_count(), "add_gradient (gradient buffer)");
  with_kernel(m_dim, m_elements, m_material, [&](const auto& k) { numerics::add_element_gradients(k, x, g.data()); });
}

void MembraneTerm::add_hessian(const Eigen::VectorXd& x, numerics::Triplets& h, const numerics::HessianOptions& options) const {
  check_membrane_size(x, dof_count(), "add_hessian");
  with_kernel(m_dim, m_elements, m_material, [&](const auto& k) { numerics::add_element_hessians(k, x, h, options); });
}

void MembraneTerm::add_gradient_per_parameter(const Eigen::VectorXd& x, Eigen::MatrixXd& G) const {
  check_membrane_size(x, dof_count(), "add_gradient_per_parameter");
  if (G.rows() != dof_count() || G.cols() != parameter_count) {
    throw Error(ErrorCategory::input, "MembraneTerm::add_gradient_per_parameter: G must be " +
                                std::to_string(dof_count()) + " x " + std::to_string(parameter_count) + ", got " +
                                std::to_string(G.rows()) + " x " + std::to_string(G.cols()));
  }
  for (int k = 0; k < parameter_count; ++k) {
    double* column = G.col(k).data();  // column-major: a column is contiguous
    with_kernel(m_dim, m_elements, m_unit_materials[static_cast<std::size_t>(k)],
                [&](const auto& kernel) { numerics::add_element_gradients(kernel, x, column); });
  }
}

MembraneTerm::ParameterVector MembraneTerm::value_per_parameter(const Eigen::VectorXd& x) const {
  check_membrane_size(x, dof_count(), "value_per_parameter");
  ParameterVector v;
  for (int k = 0; k < parameter_count; ++k) {
    double e = 0.0;
    with_kernel(m_dim, m_elements, m_unit_materials[static_cast<std::size_t>(k)],
                [&](const auto& kernel) { numerics::add_element_values(kernel, x, e); });
    v(k) = e;
  }
  return v;
}

}  // namespace yarnfit::shell
