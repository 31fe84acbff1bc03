// Tile facts (yarns, lengths, R_est) on the real HYLC tiles, on tiles with a known answer,
// under changes that must not change them, and on the synthetic stockinette tile.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <numbers>
#include <numeric>
#include <string>
#include <vector>

#include "fabrics_db/tile/periodic_tile.hpp"
#include "fabrics_db/tile/synthetic_stockinette.hpp"
#include "numerics/util/clock.hpp"
#include "tests/test_support.hpp"
#include "tests/expect_error.hpp"

namespace yarnfit::db {
namespace {

namespace fs = std::filesystem;
using namespace yarnfit::testing;


PeriodicTile load(const fs::path& file) {
  Problems problems;
  auto tile = read_pyp(file, problems);
  if (!tile) throw std::runtime_error(problems.to_string());
  return *tile;
}

void print_facts(const std::string& name, const PeriodicTile& tile, const TileFacts& f) {
  std::cout << name << ": yarns " << f.yarns.size() << " (offsets";
  for (const auto& y : f.yarns) std::cout << " (" << y.offset_x << "," << y.offset_y << ")";
  std::cout << "), total length " << f.total_length << " m, rest " << f.total_rest_length
            << " m, radius " << tile.radius << " m, R_est " << f.r_est << " m, R_est/radius "
            << f.r_est / tile.radius << ", area " << f.area << " m^2, min contact distance "
            << f.min_contact_distance << " m (" << f.min_contact_distance / tile.radius
            << " radii)\n";
}

// The facts that must not change when the tile is only described differently.
void expect_same_facts(const TileFacts& a, const TileFacts& b, double length_scale) {
  const double tol = 1e-9 * length_scale;
  ASSERT_EQ(a.yarns.size(), b.yarns.size());
  std::vector<double> la;
  std::vector<double> lb;
  for (std::size_t y = 0; y < a.yarns.size(); ++y) {
    la.push_back(a.yarns[y].length);
    lb.push_back(b.yarns[y].length);
  }
  std::sort(la.begin(), la.end());
  std::sort(lb.begin(), lb.end());
  for (std::size_t y = 0; y < la.size(); ++y) EXPECT_NEAR(la[y], lb[y], tol);
  EXPECT_NEAR(a.total_length, b.total_length, tol);
  EXPECT_NEAR(a.total_rest_length, b.total_rest_length, tol);
  EXPECT_NEAR(a.area, b.area, 1e-12 * a.area);
  EXPECT_NEAR(a.r_est, b.r_est, tol);
  EXPECT_NEAR(a.min_contact_distance, b.min_contact_distance, tol);
}

// ---------------------------------------------------------------------------------------------
// The real tiles.

struct RealTile {
  const char* name;
  int yarns;
  double r_est_ratio;  // R_est / radius from this implementation (see the report in the test)
};

class TileFactsReal : public ::testing::TestWithParam<RealTile> {};

TEST_P(TileFactsReal, LoadsWithSaneFacts) {
  const RealTile& c = GetParam();
  const fs::path file = shared_pattern(std::string(c.name) + ".pyp");
  YARNFIT_REQUIRE_SHARED(file);
  const PeriodicTile tile = load(file);
  const TileFacts f = compute_tile_facts(tile);
  print_facts(c.name, tile, f);

  EXPECT_DOUBLE_EQ(f.area, tile.period_x * tile.period_y);
  EXPECT_GT(f.area, 0.0);
  ASSERT_EQ(static_cast<int>(f.yarns.size()), c.yarns);
  std::size_t edges = 0;
  double length = 0.0;
  for (const auto& y : f.yarns) {
    edges += y.edges.size();
    length += y.length;
    // Every yarn of these knits runs along the courses, one period per trip.
    EXPECT_EQ(std::abs(y.offset_x), 1);
    EXPECT_EQ(y.offset_y, 0);
    // Rest and geometric lengths of a relaxed tile agree within a few percent.
    EXPECT_NEAR(y.rest_length / y.length, 1.0, 0.05);
    // The edges of a yarn follow each other.
    for (std::size_t k = 0; k < y.edges.size(); ++k) {
      const auto& e = tile.edges[static_cast<std::size_t>(y.edges[k])];
      const auto& next = tile.edges[static_cast<std::size_t>(y.edges[(k + 1) % y.edges.size()])];
      EXPECT_EQ(e.v1, next.v0);
    }
  }
  EXPECT_EQ(edges, tile.edges.size());
  EXPECT_NEAR(f.total_length, length, 1e-15);
  EXPECT_NEAR(f.mean_segment_length, f.total_length / tile.edge_count(), 1e-15);

  const double ratio = f.r_est / tile.radius;
  EXPECT_GT(ratio, 0.5);
  EXPECT_LT(ratio, 3.0);
  EXPECT_NEAR(ratio, c.r_est_ratio, 1e-3 * c.r_est_ratio);
  // Published tiles are relaxed: no yarn passes through another, none is far from touching.
  EXPECT_GT(f.min_contact_distance, 1.5 * tile.radius);
  EXPECT_LE(f.min_contact_distance, 2.0 * f.r_est);
  ASSERT_EQ(f.segment_contact_distances.size(), tile.edges.size());
  EXPECT_DOUBLE_EQ(f.segment_contact_distances[static_cast<std::size_t>(f.r_est_edge)], 2.0 * f.r_est);
}

// R_est / radius. A first prototype of the rule reported 0.937, 0.926, 1.013 and 1.113: it
// compared copies of one yarn by their shift alone, ignoring the offsets accumulated along the
// yarn before each segment, and did not exclude the neighbour reached across the tile
// boundary (so its minimum contact distance was 0 on every tile). With both fixed the tiny
// tiles and the rib give the values below; the tile-shift test guards the fix.
INSTANTIATE_TEST_SUITE_P(TileFacts, TileFactsReal,
                         ::testing::Values(RealTile{"stocktiniest", 1, 0.994656},
                                           RealTile{"stocktiny", 1, 0.977223},
                                           RealTile{"stockinette", 2, 1.013498},
                                           RealTile{"cartridge_belt_rib", 4, 1.123291}),
                         [](const ::testing::TestParamInfo<RealTile>& p) { return std::string(p.param.name); });

// ---------------------------------------------------------------------------------------------
// Invariances.

std::vector<PeriodicTile> invariance_tiles() {
  std::vector<PeriodicTile> tiles;
  for (const char* name : {"stocktiniest", "stockinette", "cartridge_belt_rib"}) {
    const fs::path file = shared_pattern(std::string(name) + ".pyp");
    if (fs::exists(file)) tiles.push_back(load(file));
  }
  tiles.push_back(make_stockinette_tile());
  return tiles;
}

TEST(TileFactsInvariance, TranslatingTheWholeTile) {
  YARNFIT_REQUIRE_SHARED(shared_pattern("stockinette.pyp"));
  for (const PeriodicTile& tile : invariance_tiles()) {
    PeriodicTile moved = tile;
    for (auto& p : moved.positions) {
      p[0] += 0.37 * tile.period_x;
      p[1] -= 1.71 * tile.period_y;
      p[2] += 0.5 * tile.radius;
    }
    expect_same_facts(compute_tile_facts(tile), compute_tile_facts(moved), tile.period_x);
  }
}

// Moves vertex v by a whole period along x (sx = ±1) or y (sy = ±1) and changes the offsets of
// its two edges so that every edge keeps its end points: the yarns are the same set of
// curves, described from another copy. Returns false if an offset would leave {-1, 0, 1}.
bool shift_vertex(PeriodicTile& tile, int v, int sx, int sy) {
  PeriodicTile out = tile;
  out.positions[static_cast<std::size_t>(v)][0] += sx * tile.period_x;
  out.positions[static_cast<std::size_t>(v)][1] += sy * tile.period_y;
  for (auto& e : out.edges) {
    if (e.v1 == v) {
      e.dx -= sx;
      e.dy -= sy;
    }
    if (e.v0 == v) {
      e.dx += sx;
      e.dy += sy;
    }
    if (std::abs(e.dx) > 1 || std::abs(e.dy) > 1) return false;
  }
  tile = out;
  return true;
}

TEST(TileFactsInvariance, ShiftingVerticesByAWholePeriod) {
  YARNFIT_REQUIRE_SHARED(shared_pattern("stockinette.pyp"));
  for (const PeriodicTile& tile : invariance_tiles()) {
    PeriodicTile shifted = tile;
    int moved = 0;
    for (int v = 0; v < tile.vertex_count(); v += 3) {
      const int sx = (v / 3) % 2 == 0 ? 1 : -1;
      if (v % 2 == 0 ? shift_vertex(shifted, v, sx, 0) : shift_vertex(shifted, v, 0, sx)) ++moved;
    }
    ASSERT_GT(moved, tile.vertex_count() / 6);
    const TileFacts before = compute_tile_facts(tile);
    const TileFacts after = compute_tile_facts(shifted);
    expect_same_facts(before, after, tile.period_x);
    for (std::size_t y = 0; y < before.yarns.size(); ++y) {
      EXPECT_EQ(before.yarns[y].offset_x, after.yarns[y].offset_x);
      EXPECT_EQ(before.yarns[y].offset_y, after.yarns[y].offset_y);
    }
    for (std::size_t e = 0; e < tile.edges.size(); ++e) {
      EXPECT_NEAR(before.segment_contact_distances[e], after.segment_contact_distances[e],
                  1e-9 * tile.period_x);
    }
  }
}

TEST(TileFactsInvariance, MovingAWholeYarnByWholePeriods) {
  // The same fabric, described with one yarn several periods away from the others: contacts
  // must still be found between the right copies.
  YARNFIT_REQUIRE_SHARED(shared_pattern("stockinette.pyp"));
  int tested = 0;
  for (const PeriodicTile& tile : invariance_tiles()) {
    const TileFacts before = compute_tile_facts(tile);
    if (before.yarns.size() < 2) continue;
    PeriodicTile moved = tile;
    for (int e : before.yarns[0].edges) {
      auto& p = moved.positions[static_cast<std::size_t>(tile.edges[static_cast<std::size_t>(e)].v0)];
      p[0] += 3 * tile.period_x;
      p[1] -= 4 * tile.period_y;
    }
    const TileFacts after = compute_tile_facts(moved);
    expect_same_facts(before, after, tile.period_x);
    ++tested;
  }
  EXPECT_GT(tested, 0);
}

TEST(TileFactsInvariance, RenumberingVerticesAndEdges) {
  YARNFIT_REQUIRE_SHARED(shared_pattern("stockinette.pyp"));
  for (const PeriodicTile& tile : invariance_tiles()) {
    const int n = tile.vertex_count();
    // New vertex index of old vertex v: a fixed scramble; edges listed in reverse.
    std::vector<int> perm(static_cast<std::size_t>(n));
    std::iota(perm.begin(), perm.end(), 0);
    std::reverse(perm.begin(), perm.end());
    std::rotate(perm.begin(), perm.begin() + n / 3, perm.end());
    PeriodicTile renumbered = tile;
    for (int v = 0; v < n; ++v) {
      renumbered.positions[static_cast<std::size_t>(perm[static_cast<std::size_t>(v)])] =
          tile.positions[static_cast<std::size_t>(v)];
    }
    for (int e = 0; e < n; ++e) {
      TileEdge edge = tile.edges[static_cast<std::size_t>(e)];
      edge.v0 = perm[static_cast<std::size_t>(edge.v0)];
      edge.v1 = perm[static_cast<std::size_t>(edge.v1)];
      renumbered.edges[static_cast<std::size_t>(n - 1 - e)] = edge;
      renumbered.rest_lengths[static_cast<std::size_t>(n - 1 - e)] = tile.rest_lengths[static_cast<std::size_t>(e)];
    }
    expect_same_facts(compute_tile_facts(tile), compute_tile_facts(renumbered), tile.period_x);
  }
}

// ---------------------------------------------------------------------------------------------
// Tiles with a known answer.

// Adds a straight yarn along x at height y through the given fractions of the period.
void add_straight_yarn(PeriodicTile& tile, double y, const std::vector<double>& fractions) {
  const int first = tile.vertex_count();
  const int count = static_cast<int>(fractions.size());
  for (int k = 0; k < count; ++k) {
    tile.positions.push_back({fractions[static_cast<std::size_t>(k)] * tile.period_x, y, 0.0});
    tile.edges.push_back(TileEdge{first + k, first + (k + 1) % count, k + 1 == count ? 1 : 0, 0});
  }
}

TEST(TileFactsAnalytic, TwoStraightParallelYarnsGiveHalfTheirSeparation) {
  PeriodicTile tile;
  tile.period_x = 1e-3;
  tile.period_y = 4e-3;
  tile.radius = 0.5e-3;
  const double d = 1.2e-3;
  add_straight_yarn(tile, 0.0, {0.0, 0.15, 0.4, 0.6, 0.85});
  add_straight_yarn(tile, d, {0.1, 0.3, 0.45, 0.7, 0.95});
  fill_tile_defaults(tile);
  const TileFacts f = compute_tile_facts(tile);
  ASSERT_EQ(f.yarns.size(), 2u);
  EXPECT_DOUBLE_EQ(f.yarns[0].length, tile.period_x);
  EXPECT_DOUBLE_EQ(f.yarns[1].length, tile.period_x);
  // Every segment is d from the other yarn; its own yarn's segments, however close, are not
  // contacts (their arc gap equals their distance).
  EXPECT_DOUBLE_EQ(f.r_est, d / 2.0);
  EXPECT_DOUBLE_EQ(f.min_contact_distance, d);
  for (double dist : f.segment_contact_distances) EXPECT_DOUBLE_EQ(dist, d);
}

TEST(TileFactsAnalytic, OneStraightYarnTouchesOnlyItsCopiesInY) {
  PeriodicTile tile;
  tile.period_x = 1e-3;
  tile.period_y = 2e-3;  // py/2 = px: larger than any segment, so a self contact would show
  tile.radius = 0.5e-3;
  add_straight_yarn(tile, 0.3e-3, {0.0, 0.2, 0.3, 0.55, 0.75});
  fill_tile_defaults(tile);
  const TileFacts f = compute_tile_facts(tile);
  ASSERT_EQ(f.yarns.size(), 1u);
  EXPECT_DOUBLE_EQ(f.r_est, tile.period_y / 2.0);
  EXPECT_DOUBLE_EQ(f.min_contact_distance, tile.period_y);
}

TEST(TileFactsAnalytic, DiagonalYarnTouchesTheNeighbouringCopies) {
  // One straight yarn advancing (1, 1) per trip: the copies shifted by (1, 0) are other yarns
  // on parallel lines px·py/√(px² + py²) away; the copies shifted by (k, k) are itself.
  PeriodicTile tile;
  tile.period_x = 3e-3;
  tile.period_y = 2e-3;
  tile.radius = 0.5e-3;
  for (double s : {0.0, 0.3, 0.7}) tile.positions.push_back({s * tile.period_x, s * tile.period_y, 0.0});
  tile.edges = {{0, 1, 0, 0}, {1, 2, 0, 0}, {2, 0, 1, 1}};
  fill_tile_defaults(tile);
  const TileFacts f = compute_tile_facts(tile);
  ASSERT_EQ(f.yarns.size(), 1u);
  EXPECT_EQ(f.yarns[0].offset_x, 1);
  EXPECT_EQ(f.yarns[0].offset_y, 1);
  const double gap = tile.period_x * tile.period_y / std::hypot(tile.period_x, tile.period_y);
  EXPECT_NEAR(f.r_est, gap / 2.0, 1e-15);
  EXPECT_NEAR(f.min_contact_distance, gap, 1e-15);
}

TEST(TileFactsAnalytic, ClosedRingTouchesItselfAcrossAUTurnOnly) {
  // A stadium-shaped ring (net offset 0): two straight runs of length 4d at distance d, joined
  // by half circles. Opposite runs are a contact (the yarn between them is longer than
  // (π/2)·d); consecutive segments of one run are not.
  const double d = 1e-3;
  PeriodicTile tile;
  tile.period_x = 20 * d;
  tile.period_y = 20 * d;
  tile.radius = d / 2;
  const auto add = [&](double x, double y) { tile.positions.push_back({x, y, 0.0}); };
  add(0, 0);
  add(2 * d, 0);
  add(4 * d, 0);  // bottom run: edges 0, 1
  for (int k = 1; k < 6; ++k) {
    const double a = -std::numbers::pi / 2 + k * std::numbers::pi / 6;
    add(4 * d + 0.5 * d * std::cos(a), 0.5 * d + 0.5 * d * std::sin(a));
  }
  add(4 * d, d);
  add(2 * d, d);
  add(0, d);  // top run: edges 8, 9
  for (int k = 1; k < 6; ++k) {
    const double a = std::numbers::pi / 2 + k * std::numbers::pi / 6;
    add(0.5 * d * std::cos(a), 0.5 * d + 0.5 * d * std::sin(a));
  }
  const int n = tile.vertex_count();
  for (int v = 0; v < n; ++v) tile.edges.push_back(TileEdge{v, (v + 1) % n, 0, 0});
  fill_tile_defaults(tile);
  const TileFacts f = compute_tile_facts(tile);
  ASSERT_EQ(f.yarns.size(), 1u);
  EXPECT_EQ(f.yarns[0].offset_x, 0);
  EXPECT_EQ(f.yarns[0].offset_y, 0);
  for (int e : {0, 1, 8, 9}) EXPECT_DOUBLE_EQ(f.segment_contact_distances[static_cast<std::size_t>(e)], d) << e;
}

TEST(TileFactsAnalytic, RejectsATileThatIsNotClosedLoops) {
  PeriodicTile tile = make_stockinette_tile();
  tile.edges[3].v1 = tile.edges[5].v1;
  EXPECT_ERROR((void)compute_tile_facts(tile), yarnfit::ErrorCategory::input);
}

TEST(TileFacts, RibIsQuick) {
  // Timing is printed, not asserted (SPEC §7); the goal is well under a second in Release.
  const fs::path file = shared_pattern("cartridge_belt_rib.pyp");
  YARNFIT_REQUIRE_SHARED(file);
  const PeriodicTile tile = load(file);
  const auto start = numerics::Clock::now();
  const TileFacts f = compute_tile_facts(tile);
  const double seconds = numerics::seconds_since(start);
  std::cout << "compute_tile_facts on cartridge_belt_rib (" << tile.edge_count() << " segments): "
            << seconds << " s\n";
  EXPECT_GT(f.r_est, 0.0);
}

// ---------------------------------------------------------------------------------------------
// The synthetic stockinette tile.

// The synthetic stockinette's promise: no yarn closer than 1.6 radii to another, and an
// R_est between 0.8 and 1.6 radii.
void expect_collision_free_with_sane_r_est(const StockinetteTileOptions& options) {
  const PeriodicTile tile = make_stockinette_tile(options);
  const TileFacts f = compute_tile_facts(tile);
  EXPECT_GE(f.min_contact_distance, 1.6 * tile.radius);
  EXPECT_GE(f.r_est, 0.8 * tile.radius);
  EXPECT_LE(f.r_est, 1.6 * tile.radius);
}

TEST(StockinetteTile, DefaultTileIsCollisionFreeAndNearlyTouching) {
  const StockinetteTileOptions options;
  const PeriodicTile tile = make_stockinette_tile(options);
  const TileFacts f = compute_tile_facts(tile);
  print_facts("synthetic stockinette", tile, f);
  EXPECT_EQ(tile.vertex_count(), options.vertices_per_loop);
  EXPECT_EQ(tile.radius, options.yarn_radius);
  ASSERT_EQ(f.yarns.size(), 1u);
  EXPECT_EQ(f.yarns[0].offset_x, 1);
  EXPECT_EQ(f.yarns[0].offset_y, 0);
  EXPECT_GE(f.min_contact_distance, 1.6 * tile.radius);
  EXPECT_GE(f.r_est, 0.8 * tile.radius);
  EXPECT_LE(f.r_est, 1.6 * tile.radius);
}

TEST(StockinetteTile, OtherSamplingsStayCollisionFree) {
  for (int n : {12, 24, 32}) {
    SCOPED_TRACE(n);
    StockinetteTileOptions options;
    options.vertices_per_loop = n;
    expect_collision_free_with_sane_r_est(options);
  }
}

TEST(StockinetteTile, SmallChangesOfTheShapeStayCollisionFree) {
  // ±5 % on each option in turn: the defaults are not balanced on an edge.
  for (int option = 0; option < 5; ++option) {
    for (double factor : {0.95, 1.05}) {
      StockinetteTileOptions options;
      double* values[] = {&options.period_x, &options.period_y, &options.loop_height, &options.bulge,
                          &options.depth};
      *values[option] *= factor;
      SCOPED_TRACE(::testing::Message() << "option " << option << " x " << factor);
      expect_collision_free_with_sane_r_est(options);
    }
  }
}

TEST(StockinetteTile, ScalesWithTheYarn) {
  StockinetteTileOptions small;
  const double scale = 0.4;
  small.yarn_radius *= scale;
  small.period_x *= scale;
  small.period_y *= scale;
  const TileFacts a = compute_tile_facts(make_stockinette_tile());
  const TileFacts b = compute_tile_facts(make_stockinette_tile(small));
  EXPECT_NEAR(b.r_est / small.yarn_radius, a.r_est / StockinetteTileOptions{}.yarn_radius, 1e-12);
}

// Crossings, seen from the front (along z), of the yarn with its copy one course above.
struct Crossing {
  double phase = 0.0;  // loop parameter t ∈ [0, 2π) of the lower course at the crossing
  double z_lower = 0.0;
  double z_upper = 0.0;
};

std::vector<Crossing> crossings_with_course_above(const PeriodicTile& tile) {
  std::vector<Crossing> out;
  const int n = tile.edge_count();
  for (int a = 0; a < n; ++a) {
    const auto p0 = tile.positions[static_cast<std::size_t>(tile.edges[static_cast<std::size_t>(a)].v0)];
    const auto p1 = tile.edge_end(a);
    for (int i = -1; i <= 1; ++i) {
      for (int b = 0; b < n; ++b) {
        auto q0 = tile.positions[static_cast<std::size_t>(tile.edges[static_cast<std::size_t>(b)].v0)];
        auto q1 = tile.edge_end(b);
        for (auto* q : {&q0, &q1}) {
          (*q)[0] += i * tile.period_x;
          (*q)[1] += tile.period_y;
        }
        // p0 + s·(p1 − p0) = q0 + u·(q1 − q0) in x-y.
        const double ax = p1[0] - p0[0], ay = p1[1] - p0[1];
        const double bx = q1[0] - q0[0], by = q1[1] - q0[1];
        const double den = ax * by - ay * bx;
        if (den == 0.0) continue;
        const double rx = q0[0] - p0[0], ry = q0[1] - p0[1];
        const double s = (rx * by - ry * bx) / den;
        const double u = (rx * ay - ry * ax) / den;
        if (s < 0.0 || s >= 1.0 || u < 0.0 || u >= 1.0) continue;
        out.push_back({2.0 * std::numbers::pi * (a + s) / n, p0[2] + s * (p1[2] - p0[2]),
                       q0[2] + u * (q1[2] - q0[2])});
      }
    }
  }
  return out;
}

TEST(StockinetteTile, HeadPassesBehindTheLegsOfTheCourseAbove) {
  const PeriodicTile tile = make_stockinette_tile();
  const auto crossings = crossings_with_course_above(tile);
  int head_behind = 0;
  int leg_in_front = 0;
  for (const Crossing& c : crossings) {
    // The head is the top of the loop (t near π); elsewhere the lower course's upper legs
    // cross the sinker loops of the course above.
    const bool head = std::cos(c.phase) < -std::cos(std::numbers::pi / 4);
    if (head) {
      EXPECT_LT(c.z_lower, c.z_upper) << "head in front of the course above at t = " << c.phase;
      ++head_behind;
    } else {
      EXPECT_GT(c.z_lower, c.z_upper) << "leg behind the sinker above at t = " << c.phase;
      ++leg_in_front;
    }
    EXPECT_GE(std::abs(c.z_lower - c.z_upper), 1.6 * tile.radius);
  }
  // The course above threads through the loop: it passes under one strand and over another,
  // on both sides of the loop.
  EXPECT_EQ(head_behind, 2);
  EXPECT_EQ(leg_in_front, 2);
}

TEST(StockinetteTile, RestStateIsTheGeneratedGeometry) {
  const PeriodicTile tile = make_stockinette_tile();
  for (int e = 0; e < tile.edge_count(); ++e) {
    const auto& p = tile.positions[static_cast<std::size_t>(tile.edges[static_cast<std::size_t>(e)].v0)];
    const auto q = tile.edge_end(e);
    const double t[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
    EXPECT_DOUBLE_EQ(tile.rest_lengths[static_cast<std::size_t>(e)], std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]));
    const auto& d = tile.reference_directors[static_cast<std::size_t>(e)];
    EXPECT_NEAR(d[0] * d[0] + d[1] * d[1] + d[2] * d[2], 1.0, 1e-14);
    EXPECT_NEAR(d[0] * t[0] + d[1] * t[1] + d[2] * t[2], 0.0, 1e-18);
  }
  for (std::size_t v = 0; v < tile.positions.size(); ++v) {
    EXPECT_EQ(tile.rest_curvatures[v][0], 0.0);
    EXPECT_EQ(tile.rest_curvatures[v][1], 0.0);
    EXPECT_EQ(tile.rest_twists[v], 0.0);
    EXPECT_EQ(tile.reference_twists[v], 0.0);
    EXPECT_EQ(tile.twists[v], 0.0);
  }
}

TEST(StockinetteTile, RejectsOptionsThatMakeNoTile) {
  StockinetteTileOptions bad;
  bad.vertices_per_loop = 6;
  EXPECT_ERROR((void)make_stockinette_tile(bad), yarnfit::ErrorCategory::input);
  bad = {};
  bad.period_y = 0.0;
  try {
    (void)make_stockinette_tile(bad);
    FAIL() << "expected an input Error";
  } catch (const yarnfit::Error& e) {
    EXPECT_NE(std::string(e.what()).find("period_y"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace yarnfit::db
