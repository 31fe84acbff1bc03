// The synthetic stockinette tile; the curve and its reasons are in the header.
#include "fabrics_db/tile/synthetic_stockinette.hpp"
#include "numerics/util/error.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace yarnfit::db {

Problems StockinetteTileOptions::problems() const {
  Problems out;
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(yarn_radius)) out.add_field("yarn_radius", "must be positive");
  if (!positive(period_x)) out.add_field("period_x", "must be positive");
  if (!positive(period_y)) out.add_field("period_y", "must be positive");
  if (vertices_per_loop < 8)
    out.add_field("vertices_per_loop", "must be at least 8 (the loop has two legs, a head and a sinker), got " +
                                           std::to_string(vertices_per_loop));
  if (!positive(loop_height)) out.add_field("loop_height", "must be positive (it is h / period_y)");
  if (!std::isfinite(bulge) || bulge < 0.0) out.add_field("bulge", "must be zero or positive (it is a / period_x)");
  if (!positive(depth)) out.add_field("depth", "must be positive (it is c / yarn_radius)");
  return out;
}

PeriodicTile make_stockinette_tile(const StockinetteTileOptions& options) {
  if (const Problems problems = options.problems(); !problems.empty())
    throw Error(ErrorCategory::input, "make_stockinette_tile: " + problems.one_line());
  const int n = options.vertices_per_loop;
  const double px = options.period_x;
  const double a = options.bulge * px;
  const double h = options.loop_height * options.period_y;
  const double c = options.depth * options.yarn_radius;

  PeriodicTile tile;
  tile.period_x = px;
  tile.period_y = options.period_y;
  tile.radius = options.yarn_radius;
  for (int k = 0; k < n; ++k) {
    const double t = 2.0 * std::numbers::pi * k / n;
    tile.positions.push_back({px * t / (2.0 * std::numbers::pi) + a * std::sin(2.0 * t),
                              h * (1.0 - std::cos(t)) / 2.0, -c * std::cos(2.0 * t)});
    // x(2π) = x(0) + px: the last edge ends on vertex 0 of the next tile in x.
    tile.edges.push_back(TileEdge{k, (k + 1) % n, k + 1 == n ? 1 : 0, 0});
  }
  fill_tile_defaults(tile);
  return tile;
}

}  // namespace yarnfit::db
