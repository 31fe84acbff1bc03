#pragma once
// The periodic yarn system: energy (6.8), gradient and Hessian of one tile under a uniform
// coarse deformation, as functions of the free degrees of freedom g (3 per vertex, the
// co-rotated fluctuations of coarse_map.hpp). Elements are the canonical periodic elements
// of yarn_tile.hpp; their derivatives are mapped to g through x = Φ + R g.
//
// Effects (SPEC §4): stretch, bending and contact are separate pieces that a scene switches
// on; a system simulates exactly those. Twist is not modelled (thesis 6.6: negligible for
// these fits; SPEC §3: off by default), so the twist DOFs and the zero-total-twist
// constraint of 3.3.3 do not arise.
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
// Contacts use a Verlet list: candidate segment pairs within the cutoff plus a skin of 1.5 R1,
// rebuilt before any vertex could have moved by half the skin since the last build.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <string>
#include <vector>

#include "yarn_fit/energies/yarn_elements.hpp"
#include "yarn_fit/model/yarn_params.hpp"
#include "yarn_fit/periodic/coarse_map.hpp"
#include "yarn_fit/periodic/yarn_tile.hpp"

namespace yarnfit::yarn {

struct Effects {
  bool stretch = true;
  bool bending = true;
  bool contact = true;
  // Names of the simulated effects for result records, e.g. {"stretch", "bending",
  // "contact", "co-rotation"} ("co-rotation" when κ ≠ 0).
  [[nodiscard]] std::vector<std::string> names(const CoarseDeformation& chi) const;
};

struct ContactCandidate {
  int a = 0;  // edge in cell (0, 0)
  int b = 0;  // edge in `cell`
  Cell cell;
};

class YarnSystem {
 public:
  using Triplets = std::vector<Eigen::Triplet<double>>;

  // Same-yarn segment pairs closer than this many R1 of rest arc do not interact.
  static constexpr double kSelfContactArcFactor = 2.5;

  YarnSystem(YarnTile tile, const YarnParams& params, const Effects& effects = {});

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
  [[nodiscard]] const Effects& effects() const { return m_effects; }

  [[nodiscard]] int dof_count() const { return 3 * m_tile.vertex_count(); }
  [[nodiscard]] double area() const { return m_tile.area(); }
  // Deformed position of vertex v copied into `cell`.
  [[nodiscard]] Eigen::Vector3d position(const Eigen::VectorXd& g, int v, const Cell& cell) const;

  // Total energy E [J] of the tile (Ψ = E / area); +inf where a barrier is crossed.
  [[nodiscard]] double energy(const Eigen::VectorXd& g) const;
  // Energy and its gradient with respect to g (overwritten).
  double energy_gradient(const Eigen::VectorXd& g, Eigen::VectorXd& gradient) const;
  // Hessian with respect to g as triplets (appended), per-element PSD-projected on request.
  // With `lower_only`, only entries with row ≥ column (what a lower LDLT reads: half the
  // assembly and sorting work).
  void hessian(const Eigen::VectorXd& g, Triplets& out, bool project_psd, bool lower_only = false) const;

  // Per-term energies [J] for reports: stretch, bending, contact.
  struct Breakdown {
    double stretch = 0.0, bending = 0.0, contact = 0.0;
  };
  [[nodiscard]] Breakdown energy_breakdown(const Eigen::VectorXd& g) const;

  // Coarse first Piola-Kirchhoff stress P = ∂Ψ/∂F at fixed g (3.23) [N/m], in-plane 2×2.
  // Exact for κ = 0; for κ ≠ 0 it is the in-plane part of the same sum (the derivative of
  // the co-rotated map is then computed by central differences, see d_energy_density).
  [[nodiscard]] Eigen::Matrix2d coarse_stress(const Eigen::VectorXd& g) const;
  // dΨ/dq at fixed g for q = stretch or compression of the current χ [N/m]:
  // σ_s = uᵀ P u, ∂Ψ/∂c = −vᵀ P v for κ = 0; central differences of the map for κ ≠ 0.
  enum class Coordinate { stretch, compression, curvature };
  [[nodiscard]] double d_energy_density(const Eigen::VectorXd& g, Coordinate q) const;

  // Constraint rows C (g-space), dense: 3 + number of pinned yarns.
  [[nodiscard]] const Eigen::MatrixXd& constraints() const { return m_constraints; }

  // Contact candidates (Verlet list).
  void rebuild_contacts(const Eigen::VectorXd& g);
  // True when the list may miss a pair after a further move of up to `pending_step` [m]:
  // it holds while every vertex moved less than skin/2 since the build.
  [[nodiscard]] bool contacts_stale(const Eigen::VectorXd& g, double pending_step) const;
  [[nodiscard]] const std::vector<ContactCandidate>& contacts() const { return m_contacts; }
  [[nodiscard]] double contact_skin() const { return m_skin; }
  [[nodiscard]] int contact_generation() const { return m_contact_generation; }
  // Largest t ∈ (0, 1] such that moving g by t·dg keeps every candidate pair at least half
  // its current segment distance apart (conservative: distances shrink at most by the
  // relative motion of the four vertices). Never lets a step cross a barrier.
  [[nodiscard]] double collision_free_fraction(const Eigen::VectorXd& g,
                                               const Eigen::VectorXd& dg) const;
  // Smallest centreline distance between contact candidates [m] (+inf with no candidates).
  [[nodiscard]] double min_contact_distance(const Eigen::VectorXd& g) const;

 private:
  static constexpr int kCells = 3;  // placements cached for cells in [-3, 3]²

  struct Placement {
    Eigen::Vector3d base;
    Eigen::Matrix3d rotation;
  };
  [[nodiscard]] const Placement& placement(int v, const Cell& cell) const;
  void prepare_placements(const CoarseMap& map, std::vector<Placement>& out) const;
  template <class Visitor>
  void for_each_element(const Eigen::VectorXd& g, Visitor&& visit) const;
  [[nodiscard]] double energy_with(const Eigen::VectorXd& g, const CoarseDeformation& chi) const;
  void build_constraints();

  YarnTile m_tile;
  YarnParams m_params;
  Effects m_effects;
  CoarseMap m_map;
  std::vector<Placement> m_placements;
  BiphasicStretch m_stretch;
  RodBending m_bending;
  TwoBarrierContact m_contact;
  Eigen::MatrixXd m_constraints;

  std::vector<ContactCandidate> m_contacts;
  Eigen::VectorXd m_contacts_built_at;
  bool m_contacts_valid = false;
  double m_skin = 0.0;
  int m_contact_generation = 0;
};

}  // namespace yarnfit::yarn
