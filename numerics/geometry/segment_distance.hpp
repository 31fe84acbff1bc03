#pragma once
// Distances between points and line segments in 3-D, used to find yarn contacts.

#include <algorithm>
#include <array>
#include <cmath>

namespace yarnfit::numerics {

using Point3 = std::array<double, 3>;

// Squared distance from point p to segment [a, b]:
//   t* = clamp((p − a)·(b − a) / |b − a|², 0, 1),  d² = |p − a − t*(b − a)|²
// (a degenerate segment a == b is treated as the point a).
inline double point_segment_distance_squared(const Point3& p, const Point3& a, const Point3& b) {
  const double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
  const double len2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
  double t = 0.0;
  if (len2 > 0.0) t = std::clamp((ap[0] * ab[0] + ap[1] * ab[1] + ap[2] * ab[2]) / len2, 0.0, 1.0);
  const double w[3] = {ap[0] - t * ab[0], ap[1] - t * ab[1], ap[2] - t * ab[2]};
  return w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
}

// Exact distance between segments P(s) = p0 + s·d1 and Q(t) = q0 + t·d2, s, t ∈ [0, 1].
// |P(s) − Q(t)|² is a convex quadratic on the unit square, so its minimum is either the
// stationary point (when that lies inside the square) or on one of the four sides, each of
// which is a point–segment distance. With a = d1·d1, b = d1·d2, e = d2·d2, c = d1·r,
// f = d2·r, r = p0 − q0 and D = ae − b², the stationary point is
//   s = (bf − ce)/D,  t = (af − bc)/D.
// Parallel segments (D = 0) have a minimiser on a side, so they need no special case; nearly
// parallel ones may give an inaccurate (s, t), but the value is then evaluated at real points
// of both segments and compared with the sides, so the result never falls below the truth
// and the sides bound it from above.
inline double segment_segment_distance(const Point3& p0, const Point3& p1, const Point3& q0,
                                       const Point3& q1) {
  double best = std::min({point_segment_distance_squared(p0, q0, q1),
                          point_segment_distance_squared(p1, q0, q1),
                          point_segment_distance_squared(q0, p0, p1),
                          point_segment_distance_squared(q1, p0, p1)});
  const double d1[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
  const double d2[3] = {q1[0] - q0[0], q1[1] - q0[1], q1[2] - q0[2]};
  const double r[3] = {p0[0] - q0[0], p0[1] - q0[1], p0[2] - q0[2]};
  const double a = d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2];
  const double b = d1[0] * d2[0] + d1[1] * d2[1] + d1[2] * d2[2];
  const double e = d2[0] * d2[0] + d2[1] * d2[1] + d2[2] * d2[2];
  const double c = d1[0] * r[0] + d1[1] * r[1] + d1[2] * r[2];
  const double f = d2[0] * r[0] + d2[1] * r[1] + d2[2] * r[2];
  const double denom = a * e - b * b;
  if (denom > 0.0) {
    const double s = (b * f - c * e) / denom;
    const double t = (a * f - b * c) / denom;
    if (s > 0.0 && s < 1.0 && t > 0.0 && t < 1.0) {
      const double w[3] = {r[0] + s * d1[0] - t * d2[0], r[1] + s * d1[1] - t * d2[1],
                           r[2] + s * d1[2] - t * d2[2]};
      best = std::min(best, w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    }
  }
  return std::sqrt(best);
}

}  // namespace yarnfit::numerics
