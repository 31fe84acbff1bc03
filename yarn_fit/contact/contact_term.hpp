#pragma once
// Two-barrier yarn–yarn contact (6.7) over the candidate pairs of the Verlet list
// (contact_candidates.hpp): the segment-pair element of yarn_elements.hpp (contact_element),
// Simpson's rule on both segments. A pair beyond the cutoff has exactly zero energy and is
// left out of the gradient and the Hessian (and so of the Hessian's pattern).
//
// Line-search hook: the collision-free step. Moving g by t·dg keeps every candidate pair at
// least half its current segment distance apart when t ≤ ½ d / m, with d the pair's distance
// and m the largest motion of its segments' ends (distances shrink at most by the relative
// motion of the four vertices), so a step never crosses the inner barrier.

#include <string>

#include "yarn_fit/contact/contact_candidates.hpp"
#include "yarn_fit/energies/yarn_term.hpp"

namespace yarnfit::yarn {

class ContactTerm final : public PeriodicTerm<ContactTerm, 4> {
 public:
  static constexpr bool zero_energy_is_inactive = true;
  static constexpr std::array<YarnParam, 4> sensitivity_params{YarnParam::kc1, YarnParam::r1, YarnParam::kc2,
                                                               YarnParam::r2};

  ContactTerm(const YarnTile& tile, const TilePlacement& placement, const ContactCandidates& candidates,
              const YarnParams& params)
      : PeriodicTerm(tile, placement), m_placement(&placement), m_candidates(&candidates) {
    set_params(params);
  }
  [[nodiscard]] std::string name() const override { return "contact"; }
  void set_params(const YarnParams& p) override { m_model = {p.kc1, p.r1, p.kc2, p.r2}; }
  [[nodiscard]] const TwoBarrierContact& model() const { return m_model; }

  [[nodiscard]] int element_count() const { return static_cast<int>(m_candidates->pairs().size()); }
  [[nodiscard]] ElementVertices<4> element_vertices(int e) const {
    const ContactCandidate& cc = m_candidates->pairs()[static_cast<std::size_t>(e)];
    const TileEdgeElement& ea = tile().edges[static_cast<std::size_t>(cc.a)];
    const TileEdgeElement& eb = tile().edges[static_cast<std::size_t>(cc.b)];
    return {{ea.v0, ea.v1, eb.v0, eb.v1}, {Cell{0, 0}, ea.cell1, cc.cell, cc.cell + eb.cell1}};
  }
  double element_in_space(int e, const std::array<Eigen::Vector3d, 4>& x, Vec<12>* gradient, Mat<12>* hessian,
                          bool project_psd) const {
    const ContactCandidate& cc = m_candidates->pairs()[static_cast<std::size_t>(e)];
    return contact_element(x[0], x[1], x[2], x[3], tile().edges[static_cast<std::size_t>(cc.a)].rest_length,
                           tile().edges[static_cast<std::size_t>(cc.b)].rest_length, m_model, gradient, hessian,
                           project_psd);
  }

  bool element_sensitivity(int e, const std::array<Eigen::Vector3d, 4>& x, Vec<4>& d_energy,
                           Eigen::Matrix<double, 12, 4>& d_gradient) const {
    const ContactCandidate& cc = m_candidates->pairs()[static_cast<std::size_t>(e)];
    return contact_element_sensitivity(x[0], x[1], x[2], x[3], tile().edges[static_cast<std::size_t>(cc.a)].rest_length,
                                       tile().edges[static_cast<std::size_t>(cc.b)].rest_length, m_model, d_energy,
                                       d_gradient);
  }

  // Largest t ∈ (0, 1] keeping every candidate pair at least half its distance apart.
  [[nodiscard]] double max_step(const Eigen::VectorXd& g, const Eigen::VectorXd& dg) const override;
  // Smallest centreline distance between candidate segments [m] (+inf with no candidates).
  [[nodiscard]] double min_distance(const Eigen::VectorXd& g) const;

 private:
  const TilePlacement* m_placement;
  const ContactCandidates* m_candidates;
  TwoBarrierContact m_model;
};

}  // namespace yarnfit::yarn
