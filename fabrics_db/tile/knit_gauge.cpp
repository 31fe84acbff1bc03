#include "fabrics_db/tile/knit_gauge.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <vector>

namespace yarnfit::db {

namespace {

// Maxima of a closed sequence counted with hysteresis `h`: a maximum counts once the values
// have risen at least h above the last minimum and fallen at least h below it again.
int loop_heads(const std::vector<double>& warp, double h) {
  const std::size_t n = warp.size();
  if (n < 3) return 0;
  // Start at the lowest point, so the walk begins falling-side done.
  const std::size_t start = static_cast<std::size_t>(std::min_element(warp.begin(), warp.end()) - warp.begin());
  int heads = 0;
  bool rising = true;
  double low = warp[start], high = warp[start];
  for (std::size_t k = 1; k <= n; ++k) {
    const double v = warp[(start + k) % n];
    if (rising) {
      high = std::max(high, v);
      if (high - v >= h && high - low >= h) {
        ++heads;
        rising = false;
        low = v;
      }
    } else {
      low = std::min(low, v);
      if (v - low >= h) {
        rising = true;
        high = v;
      }
    }
  }
  return heads;
}

}  // namespace

TileGauge gauge_of_counts(const PeriodicTile& tile, Axis weft_axis, int wales, int courses) {
  const double weft = weft_axis == Axis::x ? tile.period_x : tile.period_y;
  const double warp = weft_axis == Axis::x ? tile.period_y : tile.period_x;
  return {wales, courses, weft / wales, warp / courses};
}

std::optional<TileGauge> count_knit_gauge(const PeriodicTile& tile, const TileFacts& facts, Axis weft_axis) {
  const int warp_index = weft_axis == Axis::x ? 1 : 0;
  int courses = 0, wales = 0;
  std::vector<const PeriodicYarn*> course_yarns;
  for (const PeriodicYarn& y : facts.yarns) {
    const int along = weft_axis == Axis::x ? y.offset_x : y.offset_y;
    const int across = weft_axis == Axis::x ? y.offset_y : y.offset_x;
    if (across != 0 || along == 0) return std::nullopt;  // a yarn along the warp: not a weft knit
    course_yarns.push_back(&y);
    courses += 1;
  }
  if (courses == 0) return std::nullopt;
  const double warp_period = weft_axis == Axis::x ? tile.period_y : tile.period_x;
  const double h = 0.5 * warp_period / courses;
  for (const PeriodicYarn* y : course_yarns) {
    auto points = yarn_polyline(tile, *y);
    points.pop_back();  // the closing point repeats the first one's warp coordinate
    std::vector<double> warp;
    for (const auto& p : points) warp.push_back(p[static_cast<std::size_t>(warp_index)]);
    const int along = std::abs(weft_axis == Axis::x ? y->offset_x : y->offset_y);
    const int heads = loop_heads(warp, h);
    if (heads == 0 || heads % along != 0) return std::nullopt;
    if (wales != 0 && heads / along != wales) return std::nullopt;  // courses disagree
    wales = heads / along;
  }
  return gauge_of_counts(tile, weft_axis, wales, courses);
}

}  // namespace yarnfit::db
