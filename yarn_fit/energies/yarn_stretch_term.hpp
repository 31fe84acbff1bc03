#pragma once
// Biphasic yarn stretch (6.5) over the tile's edges: W = L̄ · w(ε) per edge, the element of
// yarn_elements.hpp (stretch_element), each periodic edge once (yarn_tile.hpp).

#include <string>

#include "yarn_fit/energies/yarn_term.hpp"

namespace yarnfit::yarn {

class YarnStretchTerm final : public PeriodicTerm<YarnStretchTerm, 2> {
 public:
  static constexpr bool zero_energy_is_inactive = false;
  static constexpr std::array<YarnParam, 3> sensitivity_params{YarnParam::ks1, YarnParam::eps_s, YarnParam::ks2};

  YarnStretchTerm(const YarnTile& tile, const TilePlacement& placement, const YarnParams& params)
      : PeriodicTerm(tile, placement) {
    set_params(params);
  }
  [[nodiscard]] std::string name() const override { return "stretch"; }
  void set_params(const YarnParams& p) override { m_model = {p.ks1, p.ks2, p.eps_s}; }

  [[nodiscard]] int element_count() const { return tile().edge_count(); }
  [[nodiscard]] ElementVertices<2> element_vertices(int e) const {
    const TileEdgeElement& edge = tile().edges[static_cast<std::size_t>(e)];
    return {{edge.v0, edge.v1}, {Cell{0, 0}, edge.cell1}};
  }
  double element_in_space(int e, const std::array<Eigen::Vector3d, 2>& x, Vec<6>* gradient, Mat<6>* hessian,
                          bool project_psd) const {
    return stretch_element(x[0], x[1], tile().edges[static_cast<std::size_t>(e)].rest_length, m_model, gradient,
                           hessian, project_psd);
  }
  bool element_sensitivity(int e, const std::array<Eigen::Vector3d, 2>& x, Vec<3>& d_energy,
                           Eigen::Matrix<double, 6, 3>& d_gradient) const {
    return stretch_element_sensitivity(x[0], x[1], tile().edges[static_cast<std::size_t>(e)].rest_length, m_model,
                                       d_energy, d_gradient);
  }

 private:
  BiphasicStretch m_model;
};

}  // namespace yarnfit::yarn
