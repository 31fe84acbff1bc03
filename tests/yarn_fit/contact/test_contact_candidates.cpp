// The Verlet list of contact candidates (yarn_fit/contact/contact_candidates.hpp): every
// segment pair within the cutoff plus the skin is a candidate and no pair beyond it is
// (against a brute-force search over the neighbouring cells), each periodic pair once, and the
// list says it is stale before a move could bring an unlisted pair within reach.

#include <gtest/gtest.h>

#include <set>
#include <tuple>

#include "numerics/geometry/segment_distance.hpp"
#include "tests/yarn_fit/energies/term_check.hpp"

namespace yarnfit::yarn {
namespace {

using namespace fixtures;

TEST_F(StockinetteSystem, EveryPairWithinReachIsACandidateOnceAndNoOtherIs) {
  YarnSystem system(make_yarn_tile(tile), params);
  const Eigen::VectorXd g = perturbed_state(system, 3);
  system.set_deformation({0.15, 0.03, 0.0, weft_angle()});
  system.rebuild_contacts(g);
  std::set<std::tuple<int, int, int, int>> listed;
  for (const auto& cc : system.contacts().pairs()) {
    EXPECT_TRUE(listed.insert({cc.a, cc.b, cc.cell.i, cc.cell.j}).second) << "pair listed twice";
    EXPECT_TRUE(cc.a < cc.b || (cc.a == cc.b && (cc.cell.i > 0 || (cc.cell.i == 0 && cc.cell.j > 0))))
        << "not in canonical placement";
  }
  const double cutoff = 2.0 * std::max(params.r1, params.r2);
  const auto point = [&](int v, const Cell& c) {
    const Eigen::Vector3d p = system.position(g, v, c);
    return numerics::Point3{p.x(), p.y(), p.z()};
  };
  const double reach = cutoff + system.contacts().skin();
  const int ne = system.tile().edge_count();
  int within = 0, within_reach = 0;
  for (int a = 0; a < ne; ++a) {
    for (int b = a; b < ne; ++b) {
      for (int ci = -2; ci <= 2; ++ci) {
        for (int cj = -2; cj <= 2; ++cj) {
          const Cell cell{ci, cj};
          if (b == a && !(ci > 0 || (ci == 0 && cj > 0))) continue;
          double gap = 0.0;
          if (system.tile().same_yarn_gap(a, b, cell, gap) &&
              gap < ContactCandidates::kSelfContactArcFactor * std::max(params.r1, params.r2))
            continue;
          const auto& ea = system.tile().edges[static_cast<std::size_t>(a)];
          const auto& eb = system.tile().edges[static_cast<std::size_t>(b)];
          const double d = numerics::segment_segment_distance(point(ea.v0, {0, 0}), point(ea.v1, ea.cell1),
                                                              point(eb.v0, cell), point(eb.v1, cell + eb.cell1));
          const bool is_listed = listed.count({a, b, ci, cj}) > 0;
          if (d < cutoff) ++within;
          if (d < reach) {
            ++within_reach;
            EXPECT_TRUE(is_listed) << "pair " << a << "-" << b << " in (" << ci << ", " << cj << ") at " << d
                                   << " m is missing";
          } else {
            EXPECT_FALSE(is_listed && d > reach * (1.0 + 1e-9))
                << "pair " << a << "-" << b << " in (" << ci << ", " << cj << ") at " << d << " m is beyond reach";
          }
        }
      }
    }
  }
  EXPECT_GT(within, 0);
  EXPECT_EQ(within_reach, static_cast<int>(listed.size())) << "the list holds exactly the pairs within reach";
}

TEST_F(StockinetteSystem, TheListIsStaleBeforeAVertexMovesHalfTheSkin) {
  YarnSystem system(make_yarn_tile(tile), params);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(system.dof_count());
  EXPECT_TRUE(system.contacts_stale(g, 0.0)) << "never built";
  system.rebuild_contacts(g);
  const double skin = system.contacts().skin();
  EXPECT_FALSE(system.contacts_stale(g, 0.4 * skin));
  EXPECT_TRUE(system.contacts_stale(g, 0.6 * skin)) << "a pending step beyond half the skin";
  g[0] = 0.3 * skin;
  EXPECT_FALSE(system.contacts_stale(g, 0.1 * skin));
  EXPECT_TRUE(system.contacts_stale(g, 0.3 * skin));
  system.set_deformation({0.01, 0.0, 0.0, weft_angle()});
  EXPECT_TRUE(system.contacts_stale(g, 0.0)) << "a new map invalidates the list";
}

}  // namespace
}  // namespace yarnfit::yarn
