#include "yarn_fit/periodic/yarn_system.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "numerics/util/error.hpp"
#include "yarn_fit/energies/yarn_bending_term.hpp"
#include "yarn_fit/energies/yarn_stretch_term.hpp"
#include "numerics/util/non_finite.hpp"

namespace yarnfit::yarn {
namespace {

using numerics::k_inf;

}  // namespace

std::vector<YarnTermKind> all_yarn_terms() { return {YarnTermKind::stretch, YarnTermKind::bending, YarnTermKind::contact}; }

YarnSystem::YarnSystem(YarnTile tile, const YarnParams& params, std::vector<YarnTermKind> terms)
    : m_tile(std::move(tile)), m_kinds(std::move(terms)), m_map(CoarseDeformation{}) {
  if (const db::Problems invalid = params.problems(); !invalid.empty())
    throw Error(ErrorCategory::input, "yarn parameters: " + invalid.one_line());
  m_params = params;
  m_placement.update(m_tile, m_map);
  build_constraints();
  build_terms();
}

YarnSystem::YarnSystem(const YarnSystem& other)
    : m_tile(other.m_tile),
      m_params(other.m_params),
      m_kinds(other.m_kinds),
      m_map(other.m_map),
      m_placement(other.m_placement),
      m_candidates(other.m_candidates),
      m_constraints(other.m_constraints) {
  build_terms();
}

YarnSystem& YarnSystem::operator=(const YarnSystem& other) {
  if (this == &other) return *this;
  m_tile = other.m_tile;
  m_params = other.m_params;
  m_kinds = other.m_kinds;
  m_map = other.m_map;
  m_placement = other.m_placement;
  m_candidates = other.m_candidates;
  m_constraints = other.m_constraints;
  build_terms();
  return *this;
}

YarnSystem::~YarnSystem() = default;

void YarnSystem::build_terms() {
  m_terms.clear();
  m_term_list.clear();
  m_contact = nullptr;
  for (const YarnTermKind kind : m_kinds) {
    switch (kind) {
      case YarnTermKind::stretch:
        m_terms.push_back(std::make_unique<YarnStretchTerm>(m_tile, m_placement, m_params));
        break;
      case YarnTermKind::bending:
        m_terms.push_back(std::make_unique<YarnBendingTerm>(m_tile, m_placement, m_params));
        break;
      case YarnTermKind::contact: {
        auto contact = std::make_unique<ContactTerm>(m_tile, m_placement, m_candidates, m_params);
        m_contact = contact.get();
        m_terms.push_back(std::move(contact));
        break;
      }
    }
    m_term_list.push_back(m_terms.back().get());
  }
}

std::vector<std::string> YarnSystem::effects() const {
  std::vector<std::string> out = numerics::term_names(m_term_list);
  if (deformation().curved()) out.emplace_back("co-rotation");
  return out;
}

void YarnSystem::set_params(const YarnParams& params) {
  if (const db::Problems invalid = params.problems(); !invalid.empty())
    throw Error(ErrorCategory::input, "yarn parameters: " + invalid.one_line());
  m_params = params;
  for (const auto& term : m_terms) term->set_params(params);
  m_candidates.invalidate();
}

void YarnSystem::set_tile(YarnTile tile) {
  if (tile.vertex_count() != m_tile.vertex_count() || tile.edge_count() != m_tile.edge_count())
    throw Error(ErrorCategory::input, "yarn system: set_tile needs the same vertices and edges");
  m_tile = std::move(tile);
  m_placement.update(m_tile, m_map);
  build_constraints();
  m_candidates.invalidate();
}

void YarnSystem::set_deformation(const CoarseDeformation& chi) {
  m_map = CoarseMap(chi);
  m_placement.update(m_tile, m_map);
  m_candidates.invalidate();
}

void YarnSystem::build_constraints() {
  const int n = m_tile.vertex_count();
  int pinned = 0;
  for (const auto& y : m_tile.yarns) pinned += static_cast<int>(y.pinned_vertices.size());
  m_constraints = Eigen::MatrixXd::Zero(3 + pinned, 3 * n);
  for (int v = 0; v < n; ++v)
    for (int k = 0; k < 3; ++k) m_constraints(k, 3 * v + k) = 1.0;
  int row = 3;
  for (const auto& y : m_tile.yarns) {
    for (const int p : y.pinned_vertices) {
      m_constraints.block<1, 3>(row, 3 * p) = y.slide_direction.transpose();
      ++row;
    }
  }
}

// ---------------------------------------------------------------------------------------
// Sums over the terms: one flat running total over all elements (6.8), in term order.

double YarnSystem::energy(const Eigen::VectorXd& g) const {
  double total = 0.0;
  for (const auto& term : m_terms) term->add_value(g, total);
  return std::isfinite(total) ? total : k_inf;
}

double YarnSystem::energy_gradient(const Eigen::VectorXd& g, Eigen::VectorXd& gradient) const {
  gradient = Eigen::VectorXd::Zero(dof_count());
  double total = 0.0;
  for (const auto& term : m_terms) term->add_value_gradient(g, total, gradient);
  return std::isfinite(total) ? total : k_inf;
}

void YarnSystem::hessian(const Eigen::VectorXd& g, Triplets& out, bool project_psd, bool lower_only) const {
  for (const auto& term : m_terms) term->add_hessian(g, out, {project_psd, lower_only});
}

std::vector<std::pair<std::string, double>> YarnSystem::energy_by_term(const Eigen::VectorXd& g) const {
  std::vector<std::pair<std::string, double>> out;
  for (const auto& term : m_terms) out.emplace_back(term->name(), term->value(g));
  return out;
}

Eigen::Matrix2d YarnSystem::coarse_stress(const Eigen::VectorXd& g) const {
  Eigen::Matrix2d p = Eigen::Matrix2d::Zero();
  for (const auto& term : m_terms) term->add_coarse_stress(g, p);
  return p / area();
}

ParameterDerivatives YarnSystem::parameter_derivatives(const Eigen::VectorXd& g,
                                                      std::span<const YarnParam> wanted) const {
  ParameterDerivatives out(dof_count(), static_cast<int>(wanted.size()));
  for (const auto& term : m_terms) term->add_parameter_derivatives(g, wanted, out);
  return out;
}

AffineDerivatives YarnSystem::affine_derivatives(const Eigen::VectorXd& g) const {
  AffineDerivatives out(dof_count());
  for (const auto& term : m_terms) term->add_affine_derivatives(g, out);
  return out;
}

double YarnSystem::energy_with(const Eigen::VectorXd& g, const CoarseDeformation& chi) const {
  YarnSystem copy = *this;
  copy.set_deformation(chi);
  // The candidate list was built for the current map; a central-difference step moves
  // vertices by far less than the skin, so it stays valid.
  copy.m_candidates = m_candidates;
  return copy.energy(g);
}

double YarnSystem::d_energy_density(const Eigen::VectorXd& g, Coordinate q) const {
  const CoarseDeformation chi = deformation();
  if (!chi.curved() && q != Coordinate::curvature) {
    const Eigen::Matrix2d p = coarse_stress(g);
    const Eigen::Vector2d u = chi.u();
    const Eigen::Vector2d v = chi.v();
    return q == Coordinate::stretch ? u.dot(p * u) : -v.dot(p * v);
  }
  // Central differences of the map at fixed g (the co-rotated map's derivative). The step
  // is small against the coordinate's scale: 1e-6 in s and c, 1e-6 / radius in κ.
  const double h = q == Coordinate::curvature ? 1e-6 / m_tile.radius : 1e-6;
  CoarseDeformation plus = chi, minus = chi;
  double* pp = q == Coordinate::stretch ? &plus.stretch : q == Coordinate::compression ? &plus.compression : &plus.curvature;
  double* pm = q == Coordinate::stretch ? &minus.stretch : q == Coordinate::compression ? &minus.compression : &minus.curvature;
  *pp += h;
  *pm -= h;
  return (energy_with(g, plus) - energy_with(g, minus)) / (2.0 * h) / area();
}

// ---------------------------------------------------------------------------------------
// Contacts

void YarnSystem::rebuild_contacts(const Eigen::VectorXd& g) {
  const double cutoff = m_contact != nullptr ? m_contact->model().cutoff_distance() : 0.0;
  m_candidates.rebuild(m_tile, m_placement, g, cutoff, contact_skin(), std::max(m_params.r1, m_params.r2),
                       m_contact != nullptr);
}

bool YarnSystem::contacts_stale(const Eigen::VectorXd& g, double pending_step) const {
  return m_candidates.stale(g, pending_step);
}

double YarnSystem::collision_free_fraction(const Eigen::VectorXd& g, const Eigen::VectorXd& dg) const {
  return m_contact != nullptr ? m_contact->max_step(g, dg) : 1.0;
}

double YarnSystem::min_contact_distance(const Eigen::VectorXd& g) const {
  return m_contact != nullptr ? m_contact->min_distance(g) : k_inf;
}

}  // namespace yarnfit::yarn
