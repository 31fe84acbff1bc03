#pragma once
// The initial geometry of a periodic knitted tile from its chart, stitch length and yarn
// radius (issue 20): one yarn per course running along x, one loop per stitch, courses
// stacked along y and interlocked, every loop of the chart in one tile.
//
// Each loop is Crane's plain-knit curve ("A simple parametric model of plain-knit yarns",
// 2023, keenancrane/plain-knit-yarn), per loop t ∈ [0, 2π), wale spacing w, course spacing p:
//   x(t) = w (k + t/2π) + a sin 2t          a = 0.239 w (a head wider than its neck)
//   y(t) = j p + h (1 − cos t)/2             h = 1.273 w, p = 0.716 w (Crane's 3/2, 4 and
//                                            4.5 with w = 2π: rows that just interlock)
//   z(t) through seven key depths at t = 0, π/8, π/2, π, 3π/2, 15π/8, 2π, a half cosine
//        between successive keys.
// t = 0 and 2π are the sinkers between loops, π/8 and 15π/8 where the sinker crosses the leg
// of the loop below (same wale), π/2 and 3π/2 the legs, π the head, which crosses the legs
// of the loop above. A loop is interlocked with the one below when it passes on one side of
// that loop's head and on the other side of its legs. With s = +1 for a knit and −1 for a
// purl (KnitChart::face_sign; a knit is pulled through from the back, so its legs lie in
// front of the head below) and crossings δ = 2 · depth · R apart:
//   legs      ℓ(j, k) = s(j, k) δ/2 × (1 if the loops above and below are of the same kind,
//                       ½ if one is, 0 if neither: garter and seed loops tilt instead)
//   head      ℓ(j+1, k) − s(j+1, k) δ      the other side of the next loop's legs
//   sinker    ℓ(j−1, k) − s(j, k) δ        the other side of the lower loop's legs than this
//                                          loop's legs are of the lower head
//   t = 0     the mean of the two loops' sinkers that meet there (0 where a knit and a purl
//             wale meet: the yarn passes through the middle plane, as in a rib).
// Stockinette is then Crane's loop with a flat sinker; a purl course is the knit course
// mirrored in z, as stitch-by-stitch models purls (sabetta/stitch-by-stitch,
// code/fabric_simulations). Every crossing of two loops is δ apart in depth.
//
// Scale: w is found by bisection so that the chart's loops have the mean polyline length L
// (p = course_ratio · w, h = overlap_ratio · p, a = bulge_ratio · w);
// then each loop's bulge a is adjusted (bisection) so that its own length is L: a loop whose
// depth profile travels less than the mean takes a wider head. Rest lengths are the
// edge lengths, rest curvatures zero (a straight yarn at rest), reference directors default.
//
// A held period (issue 48: the record's knitting gauge, or the yarn fit's shape): w and p are
// given, and the loops take the length L by their shape instead: the bulge a (0 to w/2), then
// the loop height h (down to p/2 for a short stitch, up to 3p for a long one).

#include <optional>
#include <string>
#include <vector>

#include "fabrics_db/tile/knit_chart.hpp"
#include "fabrics_db/problems.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"

namespace yarnfit::db {

struct KnitTileOptions {
  double stitch_length = 0.0;  // L: yarn length per stitch [m]
  double yarn_radius = 0.0;    // R [m]
  int vertices_per_stitch = 16;
  double depth = 1.0;          // δ / 2R: crossing yarns start δ = 2R apart, just touching
  // Proportions (Crane 2023: p/w = 0.716, h/w = 1.273, a/w = 0.239).
  double course_ratio = 0.716;   // p / w: the tile's aspect (courses against wales)
  double overlap_ratio = 1.273 / 0.716;  // h / p: how far a loop reaches into the course above
  double bulge_ratio = 0.239;    // a / w
  // The period to hold [m]: both set, or neither (then w follows from L and course_ratio).
  std::optional<double> wale_spacing, course_spacing;

  // What is wrong, under each option's name; empty if usable.
  [[nodiscard]] Problems problems() const;
};

struct KnitTile {
  PeriodicTile tile;
  KnitChart chart;
  double wale_spacing = 0.0;    // w [m]
  double course_spacing = 0.0;  // p [m]
  double crossing_gap = 0.0;    // δ used [m]: 2 · depth · R, or less for a stitch too short for it
  std::vector<double> stitch_lengths;  // polyline length of each loop, course-major [m]
  double min_distance = 0.0;    // smallest centreline distance between contact candidates [m]
};

// Throws an input Error for bad options, or when L is too short to form loops even with
// crossings R/2 apart (the message gives the shortest L).
KnitTile make_knit_tile(const KnitChart& chart, const KnitTileOptions& options);

}  // namespace yarnfit::db
