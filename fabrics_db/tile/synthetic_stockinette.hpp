#pragma once
// A synthetic stockinette tile: one periodic yarn per course, one loop per tile, built from
// a closed-form curve so that the project can ship an example fabric made by itself
// (SPEC §6) rather than a copy of published data.
//
// The yarn of the course at y = 0 is the curve, t ∈ [0, 2π) per loop,
//   x(t) = px·t/(2π) + a·sin 2t                 a = bulge · px
//   y(t) = h·(1 − cos t)/2                       h = loop_height · py
//   z(t) = −c·cos 2t                             c = depth · R
// sampled at t_k = 2πk/N, k = 0..N−1, closed by an edge from vertex N−1 to vertex 0 of the
// next tile in x (offset (1, 0)). t = 0 is the sinker loop at the bottom, t = π the loop
// head at the top, t = π/2 and 3π/2 the legs. With a > px/8 the head is wider than the
// neck, and with h > py the head of one course reaches over the lower legs of the course
// above (its copy shifted by (0, py)). z puts the legs in front and the head and sinker
// behind, so the head passes behind the legs of the course above and the sinker behind the
// legs of the course below: the two courses interlock as in a knitted stockinette.
//
// Rest lengths are the geometric edge lengths, rest curvatures and twists are zero and the
// reference directors are perpendicular to the edges (fill_tile_defaults).

#include <string>

#include "fabrics_db/problems.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"

namespace yarnfit::db {

// The defaults (R = 0.25 mm, px = 9.6 R, py = 5 R) give a collision-free tile whose yarns
// nearly touch: centreline distance ≥ 2.09 R everywhere and R_est ≈ 1.06 R (compute_tile_facts);
// ±5 % on any one option keeps the distance ≥ 1.75 R and R_est within 1.02–1.10 R, and
// 12 to 32 vertices per loop keep it ≥ 1.9 R with R_est within 0.96–1.16 R.
struct StockinetteTileOptions {
  double yarn_radius = 0.25e-3;  // R [m]
  double period_x = 2.4e-3;      // px: loop pitch along the course (wale spacing) [m]
  double period_y = 1.25e-3;     // py: distance between courses (course spacing) [m]
  int vertices_per_loop = 16;    // N ≥ 8
  double loop_height = 1.7;      // h / py, > 1 so that courses interlock
  double bulge = 0.25;           // a / px, > 1/8 for a head wider than the neck
  double depth = 1.4;            // c / R, front–back amplitude of the yarn centreline

  // What is wrong, under each option's name; empty if the options make a tile.
  [[nodiscard]] Problems problems() const;
};

// Throws an input Error with `options.problems()` if there are any.
PeriodicTile make_stockinette_tile(const StockinetteTileOptions& options = {});

}  // namespace yarnfit::db
