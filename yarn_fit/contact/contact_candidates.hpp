#pragma once
// The broad phase of yarn–yarn contact (SPEC §3: "broad phase pruned by distance"): a Verlet
// list of candidate segment pairs, each periodic pair once in its canonical placement (edge a
// in cell (0, 0) against edge b in `cell`, a < b or a == b with cell > (0, 0)), within the
// contact cutoff plus a skin. The list stays valid while every vertex moved less than half
// the skin since it was built: two vertices then approach by less than the skin, so no pair
// outside the list can have come within the cutoff.

#include <Eigen/Core>
#include <vector>

#include "yarn_fit/periodic/tile_placement.hpp"
#include "yarn_fit/periodic/yarn_tile.hpp"

namespace yarnfit::yarn {

struct ContactCandidate {
  int a = 0;  // edge in cell (0, 0)
  int b = 0;  // edge in `cell`
  Cell cell;
};

// Distance between the centrelines of the pair's two segments at state g [m].
double centreline_distance(const YarnTile& tile, const TilePlacement& placement, const Eigen::VectorXd& g,
                           const ContactCandidate& pair);

class ContactCandidates {
 public:
  // Same-yarn segment pairs closer than this many R of rest arc do not interact (nearby
  // segments of one yarn sit at about their arc distance and must not repel each other).
  static constexpr double kSelfContactArcFactor = 2.5;

  // Rebuilds the list at state g: pairs whose centrelines come within `cutoff + skin`, leaving
  // out same-yarn pairs closer than kSelfContactArcFactor · `radius` of rest arc. With
  // `find_pairs` false (a scene without contact) the list is valid and empty.
  void rebuild(const YarnTile& tile, const TilePlacement& placement, const Eigen::VectorXd& g, double cutoff,
               double skin, double radius, bool find_pairs = true);
  // Forgets the list (the tile, the map or the radii changed).
  void invalidate() { m_valid = false; }
  // True when the list may miss a pair after a further move of up to `pending_step` [m].
  [[nodiscard]] bool stale(const Eigen::VectorXd& g, double pending_step) const;

  [[nodiscard]] const std::vector<ContactCandidate>& pairs() const { return m_pairs; }
  [[nodiscard]] double skin() const { return m_skin; }
  [[nodiscard]] int generation() const { return m_generation; }

 private:
  std::vector<ContactCandidate> m_pairs;
  Eigen::VectorXd m_built_at;
  bool m_valid = false;
  double m_skin = 0.0;
  int m_generation = 0;
};

}  // namespace yarnfit::yarn
