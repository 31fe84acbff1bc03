// The knitted tile's initial geometry; the curve, its depths and its scale are in the header.
#include "fabrics_db/tile/knit_tile.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <stdexcept>

#include "numerics/roots/bisection.hpp"
#include "numerics/util/error.hpp"

namespace yarnfit::db {
namespace {

constexpr double pi = std::numbers::pi;
using Point = std::array<double, 3>;
// The key parameters of a loop's depth profile: the sinker at t = 0, where the sinker crosses
// the leg of the loop below (π/8), the legs (π/2, 3π/2), the head (π), and the mirror points.
constexpr std::array<double, 7> kKeyT{0.0, pi / 8.0, pi / 2.0, pi, 3.0 * pi / 2.0, 15.0 * pi / 8.0, 2.0 * pi};
using Depths = std::array<double, 7>;  // z at kKeyT

struct LoopShape {
  double w = 0.0, p = 0.0, h = 0.0, a = 0.0;
  Depths z{};
};

// z(t): between successive keys a half cosine (zero slope at every key).
double depth_at(const Depths& z, double t) {
  std::size_t i = 0;
  while (i + 2 < kKeyT.size() && t > kKeyT[i + 1]) ++i;
  const double u = std::clamp((t - kKeyT[i]) / (kKeyT[i + 1] - kKeyT[i]), 0.0, 1.0);
  return z[i] + (z[i + 1] - z[i]) * 0.5 * (1.0 - std::cos(pi * u));
}

// The point at t of the loop in course j, wale k.
Point loop_point(const LoopShape& s, int j, int k, double t) {
  return {s.w * (k + t / (2.0 * pi)) + s.a * std::sin(2.0 * t), j * s.p + 0.5 * s.h * (1.0 - std::cos(t)),
          depth_at(s.z, t)};
}

// Length of the loop's polyline through t_i = 2πi/n, i = 0..n (its last edge ends on the next
// loop's first vertex, which is this loop's t = 2π point).
double loop_length(const LoopShape& s, int n) {
  double length = 0.0;
  Point previous = loop_point(s, 0, 0, 0.0);
  for (int i = 1; i <= n; ++i) {
    const Point next = loop_point(s, 0, 0, 2.0 * pi * i / n);
    length += std::hypot(next[0] - previous[0], next[1] - previous[1], next[2] - previous[2]);
    previous = next;
  }
  return length;
}

// The x in [lo, hi] where the increasing function f crosses `target`, to a relative 1e-12.
template <class F>
double solve_increasing(F f, double lo, double hi, double target) {
  numerics::BisectionOptions o;
  o.halvings = 200;
  o.relative_width = 1e-12;
  return numerics::bisect([&](double x) -> std::optional<bool> { return f(x) < target; }, lo, hi, o).x;
}

// The depths of loop (j, k) for crossings `gap` apart (the header's rules).
Depths depths_of(const KnitChart& chart, int j, int k, double gap) {
  const auto s = [&](int jj, int kk) { return static_cast<double>(chart.face_sign(jj, kk)); };
  // Legs: half a gap to the face side when the loops above and below are of the same kind,
  // in the middle plane when both differ (garter, seed), a quarter gap when one does.
  const auto legs = [&](int jj, int kk) {
    const double same = (s(jj - 1, kk) == s(jj, kk) ? 0.5 : 0.0) + (s(jj + 1, kk) == s(jj, kk) ? 0.5 : 0.0);
    return 0.5 * gap * s(jj, kk) * same;
  };
  // The sinker of loop (j, kk) where it crosses the leg of the loop below, (j − 1, kk).
  const auto sinker = [&](int kk) { return legs(j - 1, kk) - s(j, kk) * gap; };
  const double head = legs(j + 1, k) - s(j + 1, k) * gap;
  return {0.5 * (sinker(k - 1) + sinker(k)), sinker(k), legs(j, k), head, legs(j, k), sinker(k),
          0.5 * (sinker(k) + sinker(k + 1))};
}

}  // namespace

Problems KnitTileOptions::problems() const {
  Problems out;
  const auto must_be_positive = [&](const char* field, double v) {
    if (!(std::isfinite(v) && v > 0.0)) out.add_field(field, "must be positive");
  };
  must_be_positive("stitch_length", stitch_length);
  must_be_positive("yarn_radius", yarn_radius);
  if (vertices_per_stitch < 8)
    out.add_field("vertices_per_stitch",
                  "must be at least 8 (two legs, a head and a sinker), got " + std::to_string(vertices_per_stitch));
  must_be_positive("depth", depth);
  must_be_positive("course_ratio", course_ratio);
  must_be_positive("overlap_ratio", overlap_ratio);
  if (wale_spacing.has_value() != course_spacing.has_value())
    out.add_field("course_spacing", "give both spacings of a held period, or neither");
  if (wale_spacing) must_be_positive("wale_spacing", *wale_spacing);
  if (course_spacing) must_be_positive("course_spacing", *course_spacing);
  if (!std::isfinite(bulge_ratio) || bulge_ratio < 0.0) out.add_field("bulge_ratio", "must be zero or positive");
  return out;
}

KnitTile make_knit_tile(const KnitChart& chart, const KnitTileOptions& options) {
  if (const Problems problems = options.problems(); !problems.empty())
    throw Error(ErrorCategory::input, "make_knit_tile: " + problems.one_line());
  if (chart.courses() == 0 || chart.wales() == 0) throw Error(ErrorCategory::input, "make_knit_tile: empty chart");
  const int n = options.vertices_per_stitch;
  const double length = options.stitch_length;
  double gap = 2.0 * options.depth * options.yarn_radius;

  // The wale spacing at which the chart's loops are L long on average; the shortest loop
  // possible (w → 0) is the depth profile's travel alone.
  const auto shape = [&](double w, const Depths& z) {
    const double p = options.course_ratio * w;
    return LoopShape{w, p, options.overlap_ratio * p, options.bulge_ratio * w, z};
  };
  const auto mean_length_of = [&](const auto& shape_at) {
    double sum = 0.0;
    for (int j = 0; j < chart.courses(); ++j)
      for (int k = 0; k < chart.wales(); ++k) sum += loop_length(shape_at(depths_of(chart, j, k, gap)), n);
    return sum / (chart.courses() * chart.wales());
  };
  const auto mean_length = [&](double w) { return mean_length_of([&](const Depths& z) { return shape(w, z); }); };
  // A stitch too short for crossings a full gap apart (a tightly knitted, thick yarn) gets a
  // smaller gap, so that the depth travel takes at most two thirds of L, down to R/2: such
  // yarns start pressed into each other's soft contact layer, never past the inner one.
  double shortest = mean_length(1e-9 * length);
  if (shortest > length / 1.5 && length / 1.5 / shortest * gap >= 0.5 * options.yarn_radius) {
    gap *= length / 1.5 / shortest;
    shortest = mean_length(1e-9 * length);
  }
  if (!(length > shortest * (1.0 + 1e-6)))
    throw Error(ErrorCategory::input, "make_knit_tile: a stitch length of " + std::to_string(length * 1e3) +
                                " mm is too short for loops whose crossings are " + std::to_string(gap * 1e3) +
                                " mm apart (2 x yarn radius x depth): it needs more than " +
                                std::to_string(shortest * 1e3) + " mm");
  // The loop proportions: from L alone, or fitted into a held period.
  double w = 0.0, p = 0.0, h = 0.0, bulge = 0.0;
  if (options.wale_spacing) {
    w = *options.wale_spacing;
    p = *options.course_spacing;
    const auto held = [&](double height, double a) {
      return mean_length_of([&](const Depths& z) { return LoopShape{w, p, height, a, z}; });
    };
    h = options.overlap_ratio * p;
    const double shortest_here = held(0.5 * p, 0.0), longest_here = held(3.0 * p, 0.5 * w);
    if (!(length > shortest_here) || !(length < longest_here))
      throw Error(ErrorCategory::input,
                  "make_knit_tile: loops " + std::to_string(length * 1e3) + " mm long do not fit a period of " +
                      std::to_string(w * 1e3) + " x " + std::to_string(p * 1e3) + " mm per stitch (they can be " +
                      std::to_string(shortest_here * 1e3) + " to " + std::to_string(longest_here * 1e3) +
                      " mm): check the gauge against the stitch length");
    if (held(h, 0.0) > length) {
      h = solve_increasing([&](double height) { return held(height, 0.0); }, 0.5 * p, h, length);
    } else if (held(h, 0.5 * w) >= length) {
      bulge = solve_increasing([&](double a) { return held(h, a); }, 0.0, 0.5 * w, length);
    } else {
      bulge = 0.5 * w;
      h = solve_increasing([&](double height) { return held(height, bulge); }, h, 3.0 * p, length);
    }
  } else {
    w = solve_increasing(mean_length, 1e-9 * length, length, length);
    const LoopShape s = shape(w, {});
    p = s.p, h = s.h, bulge = s.a;
  }

  KnitTile out;
  out.chart = chart;
  out.wale_spacing = w;
  out.crossing_gap = gap;
  out.course_spacing = p;
  PeriodicTile& tile = out.tile;
  const int courses = chart.courses();
  const int wales = chart.wales();
  tile.period_x = wales * w;
  tile.period_y = courses * out.course_spacing;
  tile.radius = options.yarn_radius;
  for (int j = 0; j < courses; ++j) {
    for (int k = 0; k < wales; ++k) {
      LoopShape s{w, p, h, bulge, depths_of(chart, j, k, gap)};
      // A depth profile that travels less (or more) than the chart's mean: widen (or narrow)
      // the head until this loop is L long.
      const double a0 = s.a;
      const auto length_at = [&](double a) {
        LoopShape t = s;
        t.a = a;
        return loop_length(t, n);
      };
      if (length_at(a0) < length) s.a = solve_increasing(length_at, a0, 4.0 * a0 + 0.1 * w, length);
      else if (length_at(a0) > length && length_at(0.0) < length) s.a = solve_increasing(length_at, 0.0, a0, length);
      out.stitch_lengths.push_back(loop_length(s, n));
      for (int i = 0; i < n; ++i) {
        const int v = (j * wales + k) * n + i;
        tile.positions.push_back(loop_point(s, j, k, 2.0 * pi * i / n));
        const bool last_of_course = k + 1 == wales && i + 1 == n;
        tile.edges.push_back(TileEdge{v, last_of_course ? j * wales * n : v + 1, last_of_course ? 1 : 0, 0});
      }
    }
  }
  // The course's last vertex joins the first vertex of the same course one period on in x:
  // positions of wale k are w (k + t/2π) + …, so that vertex sits at x = period_x + x(0).
  fill_tile_defaults(tile);
  out.min_distance = compute_tile_facts(tile).min_contact_distance;
  return out;
}

}  // namespace yarnfit::db
