#pragma once
// The yarn model's energy terms over a periodic tile (thesis 6.4; SPEC §4): each term is a
// numerics::EnergyTerm in the tile's free DOFs g (3 per vertex), made of the canonical
// periodic elements of one kind (yarn_tile.hpp): an element sees the 3-D positions of its
// vertices' copies x = Φ + R g (tile_placement.hpp), its energy comes from the element
// functions of yarn_elements.hpp, and its derivatives are turned back into g-space,
// ∂E/∂g_v = R_vᵀ ∂E/∂x_v and ∂²E/∂g∂g = Rᵀ (∂²E/∂x∂x) R, which is the identity map for an
// in-plane χ.
//
// Beyond the energy, every yarn term gives its share of the coarse first Piola-Kirchhoff
// stress at fixed g (3.23): Σ_elements Σ_i (∂E/∂x_i)_{xy} ⊗ X_i, X_i the reference position of
// the element's vertex copy (divided by the tile area by the caller).
//
// And the derivatives at fixed g that the fit's sensitivities need
// (homogenise/sensitivity.hpp), each summed over the elements like the energy: with respect
// to the yarn parameters θ, and, for an in-plane χ (x = F X + g, so ∂x_i/∂F_ab = e_a X_i,b),
// with respect to the coarse deformation gradient F.

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <span>
#include <stdexcept>

#include "numerics/terms/element_assembly.hpp"
#include "yarn_fit/energies/yarn_elements.hpp"
#include "yarn_fit/model/yarn_params.hpp"
#include "yarn_fit/periodic/tile_placement.hpp"
#include "yarn_fit/periodic/yarn_tile.hpp"

namespace yarnfit::yarn {

// vec(F) = (F00, F10, F01, F11): F_ab is entry a + 2b.
inline constexpr int affine_index(int a, int b) { return a + 2 * b; }

// For the parameters θ_0 … θ_k−1 a caller asks for (columns), at fixed g.
struct ParameterDerivatives {
  Eigen::VectorXd energy;    // ∂E/∂θ_k [J per unit of θ_k]
  Eigen::MatrixXd gradient;  // n × k: ∂(∇_g E)/∂θ_k
  Eigen::MatrixXd affine;    // 4 × k: ∂²E/∂vec(F)∂θ_k (κ = 0; the coarse stress × area, differentiated)

  ParameterDerivatives(int dofs, int params)
      : energy(Eigen::VectorXd::Zero(params)),
        gradient(Eigen::MatrixXd::Zero(dofs, params)),
        affine(Eigen::MatrixXd::Zero(4, params)) {}
};

// With respect to F, at fixed g (κ = 0 only).
struct AffineDerivatives {
  Eigen::MatrixXd gradient;  // n × 4: ∂(∇_g E)/∂vec(F)
  Eigen::Matrix4d hessian = Eigen::Matrix4d::Zero();  // ∂²E/∂vec(F)²

  explicit AffineDerivatives(int dofs) : gradient(Eigen::MatrixXd::Zero(dofs, 4)) {}
};

class YarnTerm : public numerics::EnergyTerm {
 public:
  // Adds this term's Σ (∂E/∂x_i)_{xy} X_iᵀ [J] (the coarse stress times the tile area) at g.
  virtual void add_coarse_stress(const Eigen::VectorXd& g, Eigen::Matrix2d& stress_times_area) const = 0;
  // Takes this term's stiffnesses and radii from `params` (already validated).
  virtual void set_params(const YarnParams& params) = 0;
  // Adds this term's share of the derivatives with respect to wanted[k] (column k); a
  // parameter the term does not depend on adds nothing. The `affine` part needs κ = 0.
  virtual void add_parameter_derivatives(const Eigen::VectorXd& g, std::span<const YarnParam> wanted,
                                         ParameterDerivatives& out) const = 0;
  // Adds this term's share of the F-derivatives; throws std::logic_error for κ ≠ 0.
  virtual void add_affine_derivatives(const Eigen::VectorXd& g, AffineDerivatives& out) const = 0;
};

// The vertices of one periodic element and the cells of their copies.
template <int NV>
struct ElementVertices {
  std::array<int, NV> vertex;
  std::array<Cell, NV> cell;
};

// CRTP base of the yarn terms. Derived provides
//   int element_count() const;
//   ElementVertices<NV> element_vertices(int e) const;
//   double element_in_space(int e, const std::array<Eigen::Vector3d, NV>& x, Vec<3NV>* gradient,
//                           Mat<3NV>* hessian, bool project_psd) const;   // derivatives in x
//   static constexpr std::array<YarnParam, K> sensitivity_params;      // what it depends on
//   bool element_sensitivity(int e, const std::array<Eigen::Vector3d, NV>& x, Vec<K>& d_energy,
//                            Eigen::Matrix<double, 3NV, K>& d_gradient) const;   // in x
template <class Derived, int NV>
class PeriodicTerm : public numerics::ElementTerm<Derived, YarnTerm> {
 public:
  static constexpr int nodes_per_element = NV;
  static constexpr int dofs_per_node = 3;
  // The tile's energy (6.8) is one flat sum over all its elements, in term order.
  static constexpr numerics::ElementSum summation = numerics::ElementSum::per_element;
  static constexpr bool energy_with_derivatives = true;
  static constexpr int parallel_threshold = 256;

  PeriodicTerm(const YarnTile& tile, const TilePlacement& placement) : m_tile(&tile), m_placement(&placement) {}

  [[nodiscard]] std::array<int, NV> element_nodes(int e) const { return self().element_vertices(e).vertex; }

  // The element in g-space (the assembler's kernel).
  double element(int e, const Eigen::VectorXd& g, Vec<3 * NV>* gradient, Mat<3 * NV>* hessian, bool project_psd) const {
    const ElementVertices<NV> ev = self().element_vertices(e);
    std::array<Eigen::Vector3d, NV> x;
    for (int i = 0; i < NV; ++i)
      x[static_cast<std::size_t>(i)] =
          m_placement->position(g, ev.vertex[static_cast<std::size_t>(i)], ev.cell[static_cast<std::size_t>(i)]);
    const double energy = self().element_in_space(e, x, gradient, hessian, project_psd);
    if (!m_placement->curved() || !std::isfinite(energy)) return energy;
    if (gradient != nullptr) {
      for (int i = 0; i < NV; ++i) {
        const Eigen::Matrix3d& r = rotation(ev, i);
        gradient->template segment<3>(3 * i) = (r.transpose() * gradient->template segment<3>(3 * i)).eval();
      }
    }
    if (hessian != nullptr) {
      Mat<3 * NV> r = Mat<3 * NV>::Zero();
      for (int i = 0; i < NV; ++i) r.template block<3, 3>(3 * i, 3 * i) = rotation(ev, i);
      *hessian = (r.transpose() * *hessian * r).eval();
    }
    return energy;
  }

  void add_coarse_stress(const Eigen::VectorXd& g, Eigen::Matrix2d& p) const override {
    const int count = self().element_count();
    Vec<3 * NV> local;
    for (int e = 0; e < count; ++e) {
      const ElementVertices<NV> ev = self().element_vertices(e);
      std::array<Eigen::Vector3d, NV> x;
      for (int i = 0; i < NV; ++i)
        x[static_cast<std::size_t>(i)] =
            m_placement->position(g, ev.vertex[static_cast<std::size_t>(i)], ev.cell[static_cast<std::size_t>(i)]);
      const double energy = self().element_in_space(e, x, &local, nullptr, false);
      if (!std::isfinite(energy) || energy == 0.0) continue;
      for (int i = 0; i < NV; ++i) {
        const Eigen::Vector3d ref =
            m_tile->reference_at(ev.vertex[static_cast<std::size_t>(i)], ev.cell[static_cast<std::size_t>(i)]);
        p += local.template segment<2>(3 * i) * ref.head<2>().transpose();
      }
    }
  }

  void add_parameter_derivatives(const Eigen::VectorXd& g, std::span<const YarnParam> wanted,
                                 ParameterDerivatives& out) const override {
    constexpr auto own = Derived::sensitivity_params;
    constexpr int K = static_cast<int>(own.size());
    std::array<int, K> column;
    bool any = false;
    for (int k = 0; k < K; ++k) {
      column[static_cast<std::size_t>(k)] = -1;
      for (std::size_t w = 0; w < wanted.size(); ++w)
        if (wanted[w] == own[static_cast<std::size_t>(k)]) column[static_cast<std::size_t>(k)] = static_cast<int>(w);
      any = any || column[static_cast<std::size_t>(k)] >= 0;
    }
    if (!any) return;
    Vec<K> d_energy;
    Eigen::Matrix<double, 3 * NV, K> d_gradient;
    for (int e = 0; e < self().element_count(); ++e) {
      const ElementVertices<NV> ev = self().element_vertices(e);
      const std::array<Eigen::Vector3d, NV> x = positions(g, ev);
      if (!self().element_sensitivity(e, x, d_energy, d_gradient)) continue;
      for (int k = 0; k < K; ++k) {
        const int col = column[static_cast<std::size_t>(k)];
        if (col < 0) continue;
        out.energy[col] += d_energy[k];
        for (int i = 0; i < NV; ++i) {
          const Eigen::Vector3d local = d_gradient.template block<3, 1>(3 * i, k);
          const int v = ev.vertex[static_cast<std::size_t>(i)];
          out.gradient.template block<3, 1>(3 * v, col) +=
              m_placement->curved() ? Eigen::Vector3d(rotation(ev, i).transpose() * local) : local;
          if (m_placement->curved()) continue;
          const Eigen::Vector3d ref = m_tile->reference_at(v, ev.cell[static_cast<std::size_t>(i)]);
          for (int a = 0; a < 2; ++a)
            for (int b = 0; b < 2; ++b) out.affine(affine_index(a, b), col) += local[a] * ref[b];
        }
      }
    }
  }

  void add_affine_derivatives(const Eigen::VectorXd& g, AffineDerivatives& out) const override {
    if (m_placement->curved()) throw std::logic_error("yarn term: F-derivatives need an in-plane coarse deformation");
    Vec<3 * NV> gradient;
    Mat<3 * NV> hessian;
    Eigen::Matrix<double, 3 * NV, 4> velocity;  // ∂x/∂vec(F) of the element's vertex copies
    for (int e = 0; e < self().element_count(); ++e) {
      const ElementVertices<NV> ev = self().element_vertices(e);
      hessian.setZero();
      const double energy = self().element_in_space(e, positions(g, ev), &gradient, &hessian, false);
      if (!std::isfinite(energy)) continue;
      if constexpr (Derived::zero_energy_is_inactive) {
        if (energy == 0.0) continue;
      }
      velocity.setZero();
      for (int i = 0; i < NV; ++i) {
        const Eigen::Vector3d ref =
            m_tile->reference_at(ev.vertex[static_cast<std::size_t>(i)], ev.cell[static_cast<std::size_t>(i)]);
        for (int a = 0; a < 2; ++a)
          for (int b = 0; b < 2; ++b) velocity(3 * i + a, affine_index(a, b)) = ref[b];
      }
      const Eigen::Matrix<double, 3 * NV, 4> hv = hessian * velocity;
      for (int i = 0; i < NV; ++i)
        out.gradient.template middleRows<3>(3 * ev.vertex[static_cast<std::size_t>(i)]) +=
            hv.template middleRows<3>(3 * i);
      out.hessian += velocity.transpose() * hv;
    }
  }

 protected:
  [[nodiscard]] const YarnTile& tile() const { return *m_tile; }
  [[nodiscard]] const TilePlacement& placement() const { return *m_placement; }

 private:
  const Derived& self() const { return static_cast<const Derived&>(*this); }
  std::array<Eigen::Vector3d, NV> positions(const Eigen::VectorXd& g, const ElementVertices<NV>& ev) const {
    std::array<Eigen::Vector3d, NV> x;
    for (int i = 0; i < NV; ++i)
      x[static_cast<std::size_t>(i)] =
          m_placement->position(g, ev.vertex[static_cast<std::size_t>(i)], ev.cell[static_cast<std::size_t>(i)]);
    return x;
  }
  const Eigen::Matrix3d& rotation(const ElementVertices<NV>& ev, int i) const {
    return m_placement->at(ev.vertex[static_cast<std::size_t>(i)], ev.cell[static_cast<std::size_t>(i)]).rotation;
  }
  const YarnTile* m_tile;
  const TilePlacement* m_placement;
};

}  // namespace yarnfit::yarn
