#include "reports/html/tile_drawing.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "numerics/util/error.hpp"
#include "reports/html/svg_plot.hpp"

namespace yarnfit::reports {

namespace {

using Point = std::array<double, 3>;

struct Segment {
  Point a, b;
  std::size_t yarn = 0;
  [[nodiscard]] double mid(int k) const { return 0.5 * (a[static_cast<std::size_t>(k)] + b[static_cast<std::size_t>(k)]); }
};

constexpr double k_view_px = 300.0;  // the larger side of the view from above
constexpr double k_margin_px = 22.0;  // for the caption line above each view
constexpr double k_caption_px = 250.0;

// `colour` (#rrggbb) darkened towards black by `shade` ∈ [0, 1] (1: as it is).
std::string shaded(const std::string& colour, double shade) {
  unsigned r = 0, g = 0, b = 0;
  if (std::sscanf(colour.c_str(), "#%02x%02x%02x", &r, &g, &b) != 3) return colour;
  const double f = 0.45 + 0.55 * std::clamp(shade, 0.0, 1.0);
  char out[8];
  std::snprintf(out, sizeof out, "#%02x%02x%02x", static_cast<unsigned>(r * f), static_cast<unsigned>(g * f),
                static_cast<unsigned>(b * f));
  return out;
}

// Every segment of every copy of the yarns (shifted by whole periods) that reaches into
// [0, wx] × [0, wy] (grown by `pad`) in the x-y plane; `wy` ≤ 0 keeps the copies whose
// segment midpoints lie in [0, period_y) instead (the side view's one period of depth).
std::vector<Segment> segments_in(const db::PeriodicTile& tile, const std::vector<std::vector<Point>>& yarns, double wx,
                                 double wy, double pad) {
  std::vector<Segment> out;
  const double px = tile.period_x, py = tile.period_y;
  for (std::size_t k = 0; k < yarns.size(); ++k) {
    const auto& line = yarns[k];
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (const auto& p : line) x0 = std::min(x0, p[0]), x1 = std::max(x1, p[0]), y0 = std::min(y0, p[1]), y1 = std::max(y1, p[1]);
    const double wy_range = wy > 0.0 ? wy : py;
    const int i0 = static_cast<int>(std::floor((-pad - x1) / px)), i1 = static_cast<int>(std::ceil((wx + pad - x0) / px));
    const int j0 = static_cast<int>(std::floor((-pad - y1) / py)), j1 = static_cast<int>(std::ceil((wy_range + pad - y0) / py));
    for (int i = i0; i <= i1; ++i)
      for (int j = j0; j <= j1; ++j)
        for (std::size_t s = 0; s + 1 < line.size(); ++s) {
          Segment seg{line[s], line[s + 1], k};
          seg.a[0] += i * px, seg.b[0] += i * px, seg.a[1] += j * py, seg.b[1] += j * py;
          const bool in_x = std::max(seg.a[0], seg.b[0]) >= -pad && std::min(seg.a[0], seg.b[0]) <= wx + pad;
          const bool in_y = wy > 0.0 ? std::max(seg.a[1], seg.b[1]) >= -pad && std::min(seg.a[1], seg.b[1]) <= wy + pad
                                     : seg.mid(1) >= 0.0 && seg.mid(1) < py;
          if (in_x && in_y) out.push_back(seg);
        }
  }
  return out;
}

// Draws `segments` projected on axes (h, v) of the tile (0 x, 1 y, 2 z), farthest first along
// `depth` (`near_is_high`: larger depth values lie nearer the viewer), into a view of the
// window [0, wh] × [v0, v1] at `scale` px per metre.
std::string draw_view(std::vector<Segment> segments, int h, int v, int depth, bool near_is_high, double wh, double v0,
                      double v1, double scale, double radius, const std::string& caption, const std::string& clip_id,
                      const std::string& attributes) {
  const double width = wh * scale, height = (v1 - v0) * scale;
  // At least as wide as the caption.
  svg::Canvas c(std::max(width + 2.0, k_caption_px), height + k_margin_px + 2.0, attributes);
  c.text(1.0, 14.0, caption, "start", "tick");
  const double top = k_margin_px;
  c.raw("<defs><clipPath id=\"" + clip_id + "\"><rect x=\"1\" y=\"" + std::to_string(top) + "\" width=\"" +
        std::to_string(width) + "\" height=\"" + std::to_string(height) + "\"/></clipPath></defs><g clip-path=\"url(#" +
        clip_id + ")\">");
  std::sort(segments.begin(), segments.end(), [&](const Segment& a, const Segment& b) {
    return near_is_high ? a.mid(depth) < b.mid(depth) : a.mid(depth) > b.mid(depth);
  });
  double d0 = 1e300, d1 = -1e300;
  for (const auto& s : segments) d0 = std::min(d0, s.mid(depth)), d1 = std::max(d1, s.mid(depth));
  const auto X = [&](const Point& p) { return 1.0 + p[static_cast<std::size_t>(h)] * scale; };
  const auto Y = [&](const Point& p) { return top + (v1 - p[static_cast<std::size_t>(v)]) * scale; };
  const std::string stroke_width = std::to_string(2.0 * radius * scale);
  for (const auto& s : segments) {
    double near = d1 > d0 ? (s.mid(depth) - d0) / (d1 - d0) : 1.0;
    if (!near_is_high) near = 1.0 - near;
    const std::string colour = shaded(svg::palette()[s.yarn % (svg::palette().size() - 1)], near);
    c.line(X(s.a), Y(s.a), X(s.b), Y(s.b), "stroke:" + colour + ";stroke-width:" + stroke_width + ";stroke-linecap:round");
  }
  c.raw("</g>");
  return c.str();
}

}  // namespace

TileDrawing draw_tile(const db::PeriodicTile& tile, double radius, const std::string& id, const std::string& attributes) {
  TileDrawing out;
  db::TileFacts facts;
  try {
    facts = db::compute_tile_facts(tile);
  } catch (const Error&) {
    return out;
  }
  std::vector<std::vector<Point>> yarns;
  for (const auto& y : facts.yarns) yarns.push_back(db::yarn_polyline(tile, y));
  const double px = tile.period_x, py = tile.period_y;
  const double wx = 2.0 * px, wy = 2.0 * py;
  const double scale = k_view_px / std::max(wx, wy);
  // From above: z towards the viewer.
  std::string above = draw_view(segments_in(tile, yarns, wx, wy, radius), 0, 1, 2, true, wx, 0.0, wy, scale, radius,
                                "from above, 2 × 2 periods: weft →, warp ↑", id + "-above", attributes);
  // The period outlined (a dashed rectangle at the lower left).
  const std::string frame = "<rect x=\"1\" y=\"" + std::to_string(k_margin_px + py * scale) + "\" width=\"" +
                            std::to_string(px * scale) + "\" height=\"" + std::to_string(py * scale) +
                            "\" style=\"fill:none;stroke:#222;stroke-width:1;stroke-dasharray:4 3\"/>";
  out.above = above.insert(above.size() - std::string("</svg>").size(), frame);
  // From the side: looking along +y (the warp), the nearest yarns (smallest y) over the others.
  const auto side = segments_in(tile, yarns, wx, 0.0, radius);
  double z0 = 1e300, z1 = -1e300;
  for (const auto& s : side) z0 = std::min({z0, s.a[2], s.b[2]}), z1 = std::max({z1, s.a[2], s.b[2]});
  if (side.empty()) z0 = -radius, z1 = radius;
  out.side = draw_view(side, 0, 2, 1, false, wx, z0 - 1.5 * radius, z1 + 1.5 * radius, scale, radius,
                       "from the side: weft →, depth ↑", id + "-side", attributes);
  return out;
}

}  // namespace yarnfit::reports
