#include "fabrics_db/tile/woven_tile.hpp"

#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "fabrics_db/tile/chart_rows.hpp"
#include "numerics/util/error.hpp"

namespace yarnfit::db {
namespace {

constexpr std::array<std::pair<const char*, const char*>, 3> kNamedWeaves{
    {{"plain", "10/01"}, {"basket2x2", "1100/1100/0011/0011"}, {"twill2x2", "1100/0110/0011/1001"}}};

int periodic(int i, int n) { return ((i % n) + n) % n; }

std::string weave_names() {
  std::string names;
  for (const auto& n : named_weave_charts()) names += (names.empty() ? "" : ", ") + n;
  return names;
}

// Depth of a yarn along its length: `over[i]` says whether it lies on top at its crossing i
// (centred at i + ½ in units of the spacing); a half cosine between successive crossings.
double depth_along(const std::vector<bool>& over, double at, double amplitude) {
  const int n = static_cast<int>(over.size());
  const double u = at - 0.5;  // crossings at integer u
  const int i = static_cast<int>(std::floor(u));
  const double t = u - i;
  const double z0 = over[static_cast<std::size_t>(periodic(i, n))] ? amplitude : -amplitude;
  const double z1 = over[static_cast<std::size_t>(periodic(i + 1, n))] ? amplitude : -amplitude;
  return z0 + (z1 - z0) * 0.5 * (1.0 - std::cos(std::numbers::pi * t));
}

}  // namespace

bool WeaveChart::warp_on_top(int weft, int warp) const {
  const auto& row = rows[static_cast<std::size_t>(periodic(weft, wefts()))];
  return row[static_cast<std::size_t>(periodic(warp, warps()))];
}

std::string WeaveChart::text() const {
  std::string out;
  for (std::size_t j = 0; j < rows.size(); ++j) {
    if (j > 0) out += '/';
    for (const bool up : rows[j]) out += up ? '1' : '0';
  }
  return out;
}

const std::vector<std::string>& named_weave_charts() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v;
    for (const auto& [name, text] : kNamedWeaves) v.emplace_back(name);
    return v;
  }();
  return names;
}

std::optional<WeaveChart> parse_weave_chart(const std::string& given, std::string* why) {
  const auto fail = [&](std::string message) -> std::optional<WeaveChart> {
    if (why != nullptr) *why = std::move(message);
    return std::nullopt;
  };
  std::string text = given;
  for (const auto& [name, chart] : kNamedWeaves)
    if (given == name) text = chart;
  const ChartRows rows = split_chart_rows(text, "01", "weave", given, "crossings");
  if (!rows.problem.empty()) return fail(rows.problem);
  if (rows.unknown_symbol)
    return fail("unknown weave '" + given + "': expected one of " + weave_names() +
                ", or rows of 1 (warp on top) and 0 (weft on top) separated by '/', such as 10/01");
  WeaveChart out;
  out.name = given;
  for (const std::string& row : rows.rows) {
    out.rows.emplace_back();
    for (const char c : row) out.rows.back().push_back(c == '1');
  }
  // A yarn on the same side at every crossing floats free of the cloth.
  const auto floats = [&](const char* kind, int yarns, int crossings, auto warp_up_at) -> std::optional<std::string> {
    for (int y = 0; y < yarns; ++y) {
      int up = 0;
      for (int k = 0; k < crossings; ++k) up += warp_up_at(y, k) ? 1 : 0;
      if (up == 0 || up == crossings)
        return "weave '" + given + "': " + kind + " " + std::to_string(y + 1) +
               " lies on one side at every crossing (it would not be held in the cloth)";
    }
    return std::nullopt;
  };
  if (auto why_weft = floats("weft", out.wefts(), out.warps(), [&](int j, int i) { return out.warp_on_top(j, i); }))
    return fail(*why_weft);
  if (auto why_warp = floats("warp", out.warps(), out.wefts(), [&](int i, int j) { return out.warp_on_top(j, i); }))
    return fail(*why_warp);
  return out;
}

Problems WovenTileOptions::problems() const {
  Problems out;
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(yarn_radius)) out.add_field("yarn_radius", "must be positive");
  if (!positive(yarn_spacing)) out.add_field("yarn_spacing", "must be positive");
  else if (yarn_spacing < 2.0 * yarn_radius)
    out.add_field("yarn_spacing", "must be at least twice the yarn radius (neighbouring yarns would overlap)");
  if (vertices_per_crossing < 3)
    out.add_field("vertices_per_crossing", "must be at least 3, got " + std::to_string(vertices_per_crossing));
  if (!positive(depth)) out.add_field("depth", "must be positive");
  if (!(weft_crimp_share > 0.0 && weft_crimp_share < 1.0)) out.add_field("weft_crimp_share", "must be in (0, 1)");
  return out;
}

PeriodicTile make_woven_tile(const WeaveChart& chart, const WovenTileOptions& options) {
  if (const Problems problems = options.problems(); !problems.empty())
    throw Error(ErrorCategory::input, "make_woven_tile: " + problems.one_line());
  if (chart.wefts() == 0 || chart.warps() == 0) throw Error(ErrorCategory::input, "make_woven_tile: empty chart");
  const double s = options.yarn_spacing;
  const int n = options.vertices_per_crossing;
  const double half_gap = options.depth * options.yarn_radius;
  PeriodicTile tile;
  tile.period_x = chart.warps() * s;
  tile.period_y = chart.wefts() * s;
  tile.radius = options.yarn_radius;
  // One periodic yarn over `over.size()` crossings, vertex k at k/n crossings past the
  // first crossing's centre; the last edge closes over one period.
  // The gap at a crossing, 2 half_gap, is the sum of the two yarns' crimp amplitudes.
  const double weft_amplitude = 2.0 * options.weft_crimp_share * half_gap;
  const double warp_amplitude = 2.0 * (1.0 - options.weft_crimp_share) * half_gap;
  const auto add_yarn = [&](const std::vector<bool>& over, bool along_x, double across) {
    const int first = tile.vertex_count();
    const int count = static_cast<int>(over.size()) * n;
    for (int k = 0; k < count; ++k) {
      const double at = 0.5 + static_cast<double>(k) / n;  // in spacings; crossing i's centre at i + ½
      const double along = at * s, z = depth_along(over, at, along_x ? weft_amplitude : warp_amplitude);
      // Centred on the origin, as the HYLC tiles are.
      if (along_x) tile.positions.push_back({along - 0.5 * tile.period_x, across - 0.5 * tile.period_y, z});
      else tile.positions.push_back({across - 0.5 * tile.period_x, along - 0.5 * tile.period_y, z});
    }
    for (int k = 0; k < count; ++k) {
      const bool wraps = k + 1 == count;
      tile.edges.push_back({first + k, wraps ? first : first + k + 1, wraps && along_x ? 1 : 0, wraps && !along_x ? 1 : 0});
    }
  };
  for (int j = 0; j < chart.wefts(); ++j) {
    std::vector<bool> over(static_cast<std::size_t>(chart.warps()));
    for (int i = 0; i < chart.warps(); ++i) over[static_cast<std::size_t>(i)] = !chart.warp_on_top(j, i);
    add_yarn(over, true, (j + 0.5) * s);
  }
  for (int i = 0; i < chart.warps(); ++i) {
    std::vector<bool> over(static_cast<std::size_t>(chart.wefts()));
    for (int j = 0; j < chart.wefts(); ++j) over[static_cast<std::size_t>(j)] = chart.warp_on_top(j, i);
    add_yarn(over, false, (i + 0.5) * s);
  }
  for (int e = 0; e < tile.edge_count(); ++e) {
    const auto a = tile.positions[static_cast<std::size_t>(tile.edges[static_cast<std::size_t>(e)].v0)];
    const auto b = tile.edge_end(e);
    tile.rest_lengths.push_back(std::hypot(b[0] - a[0], b[1] - a[1], b[2] - a[2]));
  }
  fill_tile_defaults(tile);
  return tile;
}

}  // namespace yarnfit::db
