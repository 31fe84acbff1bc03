#pragma once
// The periodic yarn system: energy (6.8), gradient and Hessian of one tile under a uniform
// coarse deformation, as functions of the free degrees of freedom g (3 per vertex, the
// co-rotated fluctuations of coarse_map.hpp). Elements are the canonical periodic elements
// of yarn_tile.hpp; their derivatives are mapped to g through x = Φ + R g.
//
// A scene is a list of terms (SPEC §4): the system simulates exactly the yarn terms it is
// given — stretch (yarn_stretch_term.hpp), bending (yarn_bending_term.hpp) and contact
// (contact/contact_term.hpp) — and its effects are their names, plus "co-rotation" when
// κ ≠ 0. Twist is not modelled (thesis 6.6: negligible for these fits; SPEC §3: off by
// default), so the twist DOFs and the zero-total-twist constraint of 3.3.3 do not arise.
//
// Constraints C g = 0 (3.19, 3.29), linear and independent of χ:
//  * zero mean fluctuation: Σ_v g_v = 0 (3 rows);
//  * no parametric sliding: one vertex per periodic yarn, g_v · t = 0 with t the in-plane
//    direction of the yarn's period (a vertex of a yarn that crosses the tile boundary in
//    direction t cannot slide along the yarn without moving along t). The thesis pins the
//    vertex to its deformed boundary plane, which makes the constraint depend on χ; this
//    form removes the same null space and keeps the constraint fixed, so the stress (3.23)
//    needs no constraint-force term.
//
// Contacts use a Verlet list (contact/contact_candidates.hpp): candidate segment pairs
// within the cutoff plus a skin of 1.5 R1, rebuilt before any vertex could have moved by half
// the skin since the last build.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "numerics/linear/shifted_ldlt.hpp"
#include "numerics/terms/scene.hpp"
#include "yarn_fit/contact/contact_candidates.hpp"
#include "yarn_fit/contact/contact_term.hpp"
#include "yarn_fit/energies/yarn_term.hpp"
#include "yarn_fit/model/yarn_params.hpp"
#include "yarn_fit/periodic/coarse_map.hpp"
#include "yarn_fit/periodic/tile_placement.hpp"
#include "yarn_fit/periodic/yarn_tile.hpp"

namespace yarnfit::yarn {

// The yarn energy terms a scene may list.
enum class YarnTermKind { stretch, bending, contact };
// All three, in the order the energy sums them.
[[nodiscard]] std::vector<YarnTermKind> all_yarn_terms();

class YarnSystem {
 public:
  using Triplets = numerics::Triplets;

  YarnSystem(YarnTile tile, const YarnParams& params, std::vector<YarnTermKind> terms = all_yarn_terms());
  // Copies rebuild their terms on their own tile, placements and contact list (a move is a
  // copy: the terms point into the object).
  YarnSystem(const YarnSystem& other);
  YarnSystem& operator=(const YarnSystem& other);
  ~YarnSystem();

  void set_deformation(const CoarseDeformation& chi);
  [[nodiscard]] const CoarseDeformation& deformation() const { return m_map.deformation(); }
  void set_params(const YarnParams& params);
  [[nodiscard]] const YarnParams& params() const { return m_params; }
  [[nodiscard]] const YarnTile& tile() const { return m_tile; }
  // Rest lengths and curvatures may be edited here; geometry changes go through set_tile.
  [[nodiscard]] YarnTile& mutable_tile() { return m_tile; }
  // Replaces the tile (same vertices and elements, e.g. a transformed_tile): placements,
  // constraints and contacts follow.
  void set_tile(YarnTile tile);

  // The terms assembled, in order, and the scene's effects: their names, plus "co-rotation"
  // when the current χ is curved.
  [[nodiscard]] const numerics::TermList& terms() const { return m_term_list; }
  [[nodiscard]] std::vector<std::string> effects() const;

  [[nodiscard]] int dof_count() const { return 3 * m_tile.vertex_count(); }
  [[nodiscard]] double area() const { return m_tile.area(); }
  // Deformed position of vertex v copied into `cell`.
  [[nodiscard]] Eigen::Vector3d position(const Eigen::VectorXd& g, int v, const Cell& cell) const {
    return m_placement.position(g, v, cell);
  }

  // Total energy E [J] of the tile (Ψ = E / area); +inf where a barrier is crossed.
  [[nodiscard]] double energy(const Eigen::VectorXd& g) const;
  // Energy and its gradient with respect to g (overwritten).
  double energy_gradient(const Eigen::VectorXd& g, Eigen::VectorXd& gradient) const;
  // Hessian with respect to g as triplets (appended), per-element PSD-projected on request.
  // With `lower_only`, only entries with row ≥ column (what a lower LDLT reads: half the
  // assembly and sorting work).
  void hessian(const Eigen::VectorXd& g, Triplets& out, bool project_psd, bool lower_only = false) const;

  // Energy of each term [J], by name, for reports ({"stretch", 1.2e-9}, …).
  [[nodiscard]] std::vector<std::pair<std::string, double>> energy_by_term(const Eigen::VectorXd& g) const;

  // Coarse first Piola-Kirchhoff stress P = ∂Ψ/∂F at fixed g (3.23) [N/m], in-plane 2×2.
  // Exact for κ = 0; for κ ≠ 0 it is the in-plane part of the same sum (the derivative of
  // the co-rotated map is then computed by central differences, see d_energy_density).
  [[nodiscard]] Eigen::Matrix2d coarse_stress(const Eigen::VectorXd& g) const;
  // dΨ/dq at fixed g for q = stretch or compression of the current χ [N/m]:
  // σ_s = uᵀ P u, ∂Ψ/∂c = −vᵀ P v for κ = 0; central differences of the map for κ ≠ 0.
  enum class Coordinate { stretch, compression, curvature };
  [[nodiscard]] double d_energy_density(const Eigen::VectorXd& g, Coordinate q) const;

  // Derivatives at fixed g for the fit's sensitivities (homogenise/sensitivity.hpp): with
  // respect to the parameters `wanted` (column k for wanted[k]), and, for κ = 0 only, to the
  // coarse deformation gradient F (yarn_term.hpp).
  [[nodiscard]] ParameterDerivatives parameter_derivatives(const Eigen::VectorXd& g,
                                                           std::span<const YarnParam> wanted) const;
  [[nodiscard]] AffineDerivatives affine_derivatives(const Eigen::VectorXd& g) const;

  // Constraint rows C (g-space), dense: 3 + number of pinned yarns.
  [[nodiscard]] const Eigen::MatrixXd& constraints() const { return m_constraints; }

  // The factorisation the equilibrium solves of this system keep between them (its symbolic
  // analysis and triplet slots, shifted_ldlt.hpp; after a solve it holds the last one). A
  // copy of the system starts with a fresh one, so copies can solve in parallel.
  [[nodiscard]] numerics::ShiftedLdlt& factorisation() const { return *m_factorisation; }

  // Contact candidates (Verlet list); without a contact term the list stays empty.
  void rebuild_contacts(const Eigen::VectorXd& g);
  // True when the list may miss a pair after a further move of up to `pending_step` [m].
  [[nodiscard]] bool contacts_stale(const Eigen::VectorXd& g, double pending_step) const;
  [[nodiscard]] const ContactCandidates& contacts() const { return m_candidates; }
  // Largest t ∈ (0, 1] such that moving g by t·dg keeps every candidate pair at least half
  // its current segment distance apart (the contact term's collision-free step; 1 without
  // contact). Never lets a step cross a barrier.
  [[nodiscard]] double collision_free_fraction(const Eigen::VectorXd& g, const Eigen::VectorXd& dg) const;
  // Smallest centreline distance between contact candidates [m] (+inf with no candidates).
  [[nodiscard]] double min_contact_distance(const Eigen::VectorXd& g) const;

 private:
  void build_terms();
  void build_constraints();
  [[nodiscard]] double energy_with(const Eigen::VectorXd& g, const CoarseDeformation& chi) const;
  [[nodiscard]] double contact_skin() const { return 1.5 * std::max(m_params.r1, m_params.r2); }

  YarnTile m_tile;
  YarnParams m_params;
  std::vector<YarnTermKind> m_kinds;
  CoarseMap m_map;
  TilePlacement m_placement;
  ContactCandidates m_candidates;
  Eigen::MatrixXd m_constraints;
  // The terms read m_tile, m_placement and m_candidates: they are rebuilt on copy.
  std::vector<std::unique_ptr<YarnTerm>> m_terms;
  numerics::TermList m_term_list;
  const ContactTerm* m_contact = nullptr;  // the contact term when listed
  std::unique_ptr<numerics::ShiftedLdlt> m_factorisation = std::make_unique<numerics::ShiftedLdlt>();
};

}  // namespace yarnfit::yarn
