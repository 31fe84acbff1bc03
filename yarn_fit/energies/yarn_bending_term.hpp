#pragma once
// Rod bending with rest curvature (6.6) at every vertex of the tile: the corner element of
// yarn_elements.hpp (bending_element) between the vertex's incoming and outgoing edges, with
// the corner's rest curvature vector, the two edges' rest lengths and their anchor frames.
// Under a curved coarse map an edge's anchor turns with the co-rotated frame of its first
// vertex's copy, so the two corners that share an edge carry the same frame onto it.

#include <string>

#include "yarn_fit/energies/yarn_term.hpp"

namespace yarnfit::yarn {

class YarnBendingTerm final : public PeriodicTerm<YarnBendingTerm, 3> {
 public:
  static constexpr bool zero_energy_is_inactive = false;
  static constexpr std::array<YarnParam, 1> sensitivity_params{YarnParam::kb};

  YarnBendingTerm(const YarnTile& tile, const TilePlacement& placement, const YarnParams& params)
      : PeriodicTerm(tile, placement) {
    set_params(params);
  }
  [[nodiscard]] std::string name() const override { return "bending"; }
  void set_params(const YarnParams& p) override { m_model = {p.kb}; }

  [[nodiscard]] int element_count() const { return static_cast<int>(tile().corners.size()); }
  [[nodiscard]] ElementVertices<3> element_vertices(int e) const {
    const TileCorner& c = tile().corners[static_cast<std::size_t>(e)];
    return {{c.v_prev, c.vertex, c.v_next}, {c.cell_prev, Cell{0, 0}, c.cell_next}};
  }
  double element_in_space(int e, const std::array<Eigen::Vector3d, 3>& x, Vec<9>* gradient, Mat<9>* hessian,
                          bool project_psd) const {
    const TileCorner& c = tile().corners[static_cast<std::size_t>(e)];
    const double la = tile().edges[static_cast<std::size_t>(c.edge_in)].rest_length;
    const double lb = tile().edges[static_cast<std::size_t>(c.edge_out)].rest_length;
    return bending_element(x[0], x[1], x[2], la, lb, frames(c), c.rest_curvature, m_model, gradient, hessian,
                           project_psd);
  }
  bool element_sensitivity(int e, const std::array<Eigen::Vector3d, 3>& x, Vec<1>& d_energy,
                           Eigen::Matrix<double, 9, 1>& d_gradient) const {
    const TileCorner& c = tile().corners[static_cast<std::size_t>(e)];
    const double la = tile().edges[static_cast<std::size_t>(c.edge_in)].rest_length;
    const double lb = tile().edges[static_cast<std::size_t>(c.edge_out)].rest_length;
    Vec<9> dg;
    const bool ok =
        bending_element_sensitivity(x[0], x[1], x[2], la, lb, frames(c), c.rest_curvature, d_energy[0], dg);
    d_gradient = dg;
    return ok;
  }

 private:
  [[nodiscard]] CornerFrames frames(const TileCorner& c) const {
    const EdgeAnchor& in = tile().edges[static_cast<std::size_t>(c.edge_in)].anchor;
    const EdgeAnchor& out = tile().edges[static_cast<std::size_t>(c.edge_out)].anchor;
    if (!placement().curved()) return {in, out};
    const Eigen::Matrix3d& r_in = placement().at(c.v_prev, c.cell_prev).rotation;
    const Eigen::Matrix3d& r_out = placement().at(c.vertex, Cell{0, 0}).rotation;
    return {{r_in * in.tangent, r_in * in.director}, {r_out * out.tangent, r_out * out.director}};
  }

  RodBending m_model;
};

}  // namespace yarnfit::yarn
