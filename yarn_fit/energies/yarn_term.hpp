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

#include <Eigen/Core>
#include <array>
#include <cmath>

#include "numerics/terms/element_assembly.hpp"
#include "yarn_fit/energies/yarn_elements.hpp"
#include "yarn_fit/model/yarn_params.hpp"
#include "yarn_fit/periodic/tile_placement.hpp"
#include "yarn_fit/periodic/yarn_tile.hpp"

namespace yarnfit::yarn {

class YarnTerm : public numerics::EnergyTerm {
 public:
  // Adds this term's Σ (∂E/∂x_i)_{xy} X_iᵀ [J] (the coarse stress times the tile area) at g.
  virtual void add_coarse_stress(const Eigen::VectorXd& g, Eigen::Matrix2d& stress_times_area) const = 0;
  // Takes this term's stiffnesses and radii from `params` (already validated).
  virtual void set_params(const YarnParams& params) = 0;
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

 protected:
  [[nodiscard]] const YarnTile& tile() const { return *m_tile; }

 private:
  const Derived& self() const { return static_cast<const Derived&>(*this); }
  const Eigen::Matrix3d& rotation(const ElementVertices<NV>& ev, int i) const {
    return m_placement->at(ev.vertex[static_cast<std::size_t>(i)], ev.cell[static_cast<std::size_t>(i)]).rotation;
  }
  const YarnTile* m_tile;
  const TilePlacement* m_placement;
};

}  // namespace yarnfit::yarn
