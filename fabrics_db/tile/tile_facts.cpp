// Facts about a periodic tile: its yarns, lengths and the contact radius R_est (SPEC §3).
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "fabrics_db/tile/periodic_tile.hpp"
#include "numerics/geometry/segment_distance.hpp"
#include "numerics/util/error.hpp"

namespace yarnfit::db {
namespace {

using Vec3 = std::array<double, 3>;

double distance(const Vec3& a, const Vec3& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

// One edge of the tile as a segment, with where it sits along its yarn.
struct Segment {
  Vec3 p0{};
  Vec3 p1{};
  Vec3 lo{};  // bounding box
  Vec3 hi{};
  int yarn = 0;
  double arc0 = 0.0;    // arc length along the yarn where the segment starts [m]
  double length = 0.0;  // [m]
  // Sum of the period offsets of the yarn's edges before this one: the tile's copy of the
  // segment sits at its place on the unrolled yarn shifted back by (cx, cy) periods.
  int cx = 0;
  int cy = 0;
  int next = 0;         // following edge along the yarn, reached through shift (next_dx, next_dy)
  int next_dx = 0;
  int next_dy = 0;
  int prev = 0;  // preceding edge, reached through shift (prev_dx, prev_dy)
  int prev_dx = 0;
  int prev_dy = 0;
};

void check_tile(const PeriodicTile& tile) {
  const auto fail = [](const std::string& why) {
    throw Error(ErrorCategory::input, "compute_tile_facts: " + why);
  };
  const std::size_t n = tile.positions.size();
  if (n == 0) fail("tile has no vertices");
  if (tile.edges.size() != n) {
    fail("tile has " + std::to_string(n) + " vertices but " + std::to_string(tile.edges.size()) +
         " edges; a pyp tile has one edge per vertex");
  }
  if (!tile.rest_lengths.empty() && tile.rest_lengths.size() != n) {
    fail("tile has " + std::to_string(tile.rest_lengths.size()) + " rest lengths for " +
         std::to_string(n) + " edges");
  }
  if (!(tile.period_x > 0.0) || !(tile.period_y > 0.0)) fail("periods must be positive");
  std::vector<int> out_count(n, 0);
  std::vector<int> in_count(n, 0);
  for (const auto& e : tile.edges) {
    if (e.v0 < 0 || e.v1 < 0 || static_cast<std::size_t>(e.v0) >= n ||
        static_cast<std::size_t>(e.v1) >= n) {
      fail("edge " + std::to_string(e.v0) + " -> " + std::to_string(e.v1) + " has a vertex out of range");
    }
    ++out_count[static_cast<std::size_t>(e.v0)];
    ++in_count[static_cast<std::size_t>(e.v1)];
  }
  for (std::size_t v = 0; v < n; ++v) {
    if (out_count[v] != 1 || in_count[v] != 1) {
      fail("vertex " + std::to_string(v) + " has " + std::to_string(out_count[v]) + " outgoing and " +
           std::to_string(in_count[v]) + " incoming edges; yarns must be closed loops");
    }
  }
}

// Along-yarn arc gap between segment a and the copy of segment b shifted by k yarn periods
// (both on the same yarn of length L): the length of yarn strictly between them. A yarn
// with zero net offset is a closed ring, so the gap is the shorter way round.
double arc_gap(const Segment& a, const Segment& b, int k, double yarn_length, bool ring) {
  const double a0 = a.arc0;
  const double a1 = a.arc0 + a.length;
  const double b0 = b.arc0 + k * yarn_length;
  const double b1 = b0 + b.length;
  const double straight = std::max({0.0, b0 - a1, a0 - b1});
  if (!ring) return straight;
  const double round = yarn_length - (std::max(a1, b1) - std::min(a0, b0));
  return std::min(straight, std::max(0.0, round));
}

// If (i, j) is k times the yarn's net offset (ox, oy), returns true and sets k. For segment
// a and the copy of segment b shifted by s, both of one tile yarn, (i, j) = s + c_a − c_b
// with c the offsets accumulated along the yarn before each segment: the copy then lies on
// the same infinite yarn as a, k yarn periods further along it.
bool same_infinite_yarn(int i, int j, int ox, int oy, int& k) {
  if (ox == 0 && oy == 0) {
    k = 0;
    return i == 0 && j == 0;
  }
  if (ox != 0) {
    if (i % ox != 0) return false;
    k = i / ox;
    return j == k * oy;
  }
  if (i != 0 || j % oy != 0) return false;
  k = j / oy;
  return true;
}

}  // namespace

TileFacts compute_tile_facts(const PeriodicTile& tile) {
  check_tile(tile);
  const int n = tile.edge_count();
  const auto nu = static_cast<std::size_t>(n);

  TileFacts facts;
  facts.area = tile.period_x * tile.period_y;
  facts.yarn_radius = tile.radius;

  // Yarns: follow each vertex's outgoing edge until the cycle closes.
  std::vector<int> out_edge(nu);
  std::vector<int> in_edge(nu);
  for (int e = 0; e < n; ++e) {
    out_edge[static_cast<std::size_t>(tile.edges[static_cast<std::size_t>(e)].v0)] = e;
    in_edge[static_cast<std::size_t>(tile.edges[static_cast<std::size_t>(e)].v1)] = e;
  }
  std::vector<Segment> segs(nu);
  for (int e = 0; e < n; ++e) {
    Segment& s = segs[static_cast<std::size_t>(e)];
    const TileEdge& edge = tile.edges[static_cast<std::size_t>(e)];
    s.p0 = tile.positions[static_cast<std::size_t>(edge.v0)];
    s.p1 = tile.edge_end(e);
    for (int c = 0; c < 3; ++c) {
      s.lo[static_cast<std::size_t>(c)] = std::min(s.p0[static_cast<std::size_t>(c)], s.p1[static_cast<std::size_t>(c)]);
      s.hi[static_cast<std::size_t>(c)] = std::max(s.p0[static_cast<std::size_t>(c)], s.p1[static_cast<std::size_t>(c)]);
    }
    s.length = distance(s.p0, s.p1);
    // The next edge starts at v1 itself, so its copy adjacent to e is shifted by e's offset;
    // the previous edge ends at its own offset, so its adjacent copy is shifted back by it.
    s.next = out_edge[static_cast<std::size_t>(edge.v1)];
    s.next_dx = edge.dx;
    s.next_dy = edge.dy;
    s.prev = in_edge[static_cast<std::size_t>(edge.v0)];
    s.prev_dx = -tile.edges[static_cast<std::size_t>(s.prev)].dx;
    s.prev_dy = -tile.edges[static_cast<std::size_t>(s.prev)].dy;
  }
  std::vector<bool> seen(nu, false);
  for (int first = 0; first < n; ++first) {
    if (seen[static_cast<std::size_t>(first)]) continue;
    PeriodicYarn yarn;
    const int yarn_index = static_cast<int>(facts.yarns.size());
    int e = first;
    do {
      seen[static_cast<std::size_t>(e)] = true;
      Segment& s = segs[static_cast<std::size_t>(e)];
      s.yarn = yarn_index;
      s.arc0 = yarn.length;
      s.cx = yarn.offset_x;
      s.cy = yarn.offset_y;
      yarn.edges.push_back(e);
      yarn.offset_x += tile.edges[static_cast<std::size_t>(e)].dx;
      yarn.offset_y += tile.edges[static_cast<std::size_t>(e)].dy;
      yarn.length += s.length;
      yarn.rest_length += tile.rest_lengths.empty() ? s.length : tile.rest_lengths[static_cast<std::size_t>(e)];
      e = s.next;
    } while (e != first);
    facts.total_length += yarn.length;
    facts.total_rest_length += yarn.rest_length;
    facts.yarns.push_back(std::move(yarn));
  }
  facts.mean_segment_length = facts.total_length / n;

  // R_est. For each segment a, copies of every segment b are searched in two passes: first
  // the 3 × 3 copies around the copy of b nearest to a, which gives a finite bound (among
  // them are a's own copies one period away, which lie on other yarns); then every copy
  // whose bounding box comes within that bound of a's box. The second pass is exact however
  // far from each other the tile's description puts its yarns; for the HYLC tiles it stays
  // within |i|, |j| ≤ 2.
  constexpr double inf = std::numeric_limits<double>::infinity();
  // A yarn of radius R bending back onto itself through a U-turn has at least πR of yarn
  // between the touching points at distance 2R, i.e. an arc gap g ≥ (π/2)·d. A straight or
  // gently curved yarn has g ≈ d between nearby segments, which is no contact.
  constexpr double self_contact_ratio = std::numbers::pi / 2.0;
  // A pair of segments needing more copies than this means a tile whose edges span far more
  // than a period: a broken tile, not a knit.
  constexpr double max_copies_per_pair = 1e5;

  facts.segment_contact_distances.assign(nu, inf);
  for (int ia = 0; ia < n; ++ia) {
    const Segment& a = segs[static_cast<std::size_t>(ia)];
    const PeriodicYarn& ya = facts.yarns[static_cast<std::size_t>(a.yarn)];
    const bool ring = ya.offset_x == 0 && ya.offset_y == 0;
    double best = inf;
    // Distance from a to the copy of b shifted by (i·px, j·py), if it is a contact candidate
    // closer than `best`.
    const auto visit = [&](int ib, int i, int j) {
      const Segment& b = segs[static_cast<std::size_t>(ib)];
      const double sx = i * tile.period_x;
      const double sy = j * tile.period_y;
      // Cheap box test first: the boxes' distance bounds the segments' distance.
      const double gx = std::max({0.0, b.lo[0] + sx - a.hi[0], a.lo[0] - b.hi[0] - sx});
      const double gy = std::max({0.0, b.lo[1] + sy - a.hi[1], a.lo[1] - b.hi[1] - sy});
      const double gz = std::max({0.0, b.lo[2] - a.hi[2], a.lo[2] - b.hi[2]});
      if (gx * gx + gy * gy + gz * gz >= best * best) return;
      if (ib == ia && i == 0 && j == 0) return;
      if ((ib == a.next && i == a.next_dx && j == a.next_dy) ||
          (ib == a.prev && i == a.prev_dx && j == a.prev_dy)) {
        return;  // shares a vertex with a along the yarn
      }
      const Vec3 q0 = {b.p0[0] + sx, b.p0[1] + sy, b.p0[2]};
      const Vec3 q1 = {b.p1[0] + sx, b.p1[1] + sy, b.p1[2]};
      const double d = numerics::segment_segment_distance(a.p0, a.p1, q0, q1);
      if (d >= best) return;
      int k = 0;
      if (b.yarn == a.yarn &&
          same_infinite_yarn(i + a.cx - b.cx, j + a.cy - b.cy, ya.offset_x, ya.offset_y, k)) {
        if (!(arc_gap(a, b, k, ya.length, ring) > self_contact_ratio * d)) return;
      }
      best = d;
    };
    for (int ib = 0; ib < n; ++ib) {
      const Segment& b = segs[static_cast<std::size_t>(ib)];
      const int i0 = static_cast<int>(std::lround((a.lo[0] + a.hi[0] - b.lo[0] - b.hi[0]) / (2 * tile.period_x)));
      const int j0 = static_cast<int>(std::lround((a.lo[1] + a.hi[1] - b.lo[1] - b.hi[1]) / (2 * tile.period_y)));
      for (int i = i0 - 1; i <= i0 + 1; ++i) {
        for (int j = j0 - 1; j <= j0 + 1; ++j) visit(ib, i, j);
      }
    }
    for (int ib = 0; ib < n; ++ib) {
      const Segment& b = segs[static_cast<std::size_t>(ib)];
      // Copies whose box is within `best` of a's box along x and along y.
      const double ilo = std::ceil((a.lo[0] - b.hi[0] - best) / tile.period_x);
      const double ihi = std::floor((a.hi[0] - b.lo[0] + best) / tile.period_x);
      const double jlo = std::ceil((a.lo[1] - b.hi[1] - best) / tile.period_y);
      const double jhi = std::floor((a.hi[1] - b.lo[1] + best) / tile.period_y);
      if (ihi < ilo || jhi < jlo) continue;
      if ((ihi - ilo + 1) * (jhi - jlo + 1) > max_copies_per_pair) {
        throw Error(ErrorCategory::input, 
            "compute_tile_facts: edges " + std::to_string(ia) + " and " + std::to_string(ib) +
            " would need more than " + std::to_string(static_cast<long>(max_copies_per_pair)) +
            " periodic copies checked; the tile's edges span far more than its periods (" +
            std::to_string(tile.period_x) + " m × " + std::to_string(tile.period_y) + " m)");
      }
      for (int i = static_cast<int>(ilo); i <= static_cast<int>(ihi); ++i) {
        for (int j = static_cast<int>(jlo); j <= static_cast<int>(jhi); ++j) visit(ib, i, j);
      }
    }
    facts.segment_contact_distances[static_cast<std::size_t>(ia)] = best;
  }
  facts.min_contact_distance = inf;
  for (int e = 0; e < n; ++e) {
    const double d = facts.segment_contact_distances[static_cast<std::size_t>(e)];
    facts.min_contact_distance = std::min(facts.min_contact_distance, d);
    if (d / 2.0 > facts.r_est) {
      facts.r_est = d / 2.0;
      facts.r_est_edge = e;
    }
  }
  return facts;
}

std::vector<std::array<double, 3>> yarn_polyline(const PeriodicTile& tile, const PeriodicYarn& yarn) {
  std::vector<std::array<double, 3>> points;
  if (yarn.edges.empty()) return points;
  points.push_back(tile.positions.at(static_cast<std::size_t>(tile.edges.at(static_cast<std::size_t>(yarn.edges.front())).v0)));
  int dx = 0, dy = 0;
  for (const int e : yarn.edges) {
    const TileEdge& edge = tile.edges.at(static_cast<std::size_t>(e));
    dx += edge.dx;
    dy += edge.dy;
    auto p = tile.positions.at(static_cast<std::size_t>(edge.v1));
    p[0] += dx * tile.period_x;
    p[1] += dy * tile.period_y;
    points.push_back(p);
  }
  return points;
}

}  // namespace yarnfit::db
