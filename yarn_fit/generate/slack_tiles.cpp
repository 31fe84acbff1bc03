#include "yarn_fit/generate/slack_tiles.hpp"

#include <functional>
#include <utility>
#include <vector>
#include <stdexcept>

#include "fabrics_db/tile/woven_tile.hpp"
#include "fabrics_db/text_util.hpp"
#include "numerics/util/error.hpp"
#include "yarn_fit/generate/knit_generation.hpp"

namespace yarnfit::yarn {
namespace {

constexpr double kDefaultKs2 = 400.0;  // [N]
constexpr double kWovenSpacing = 1.5e-3;  // [m]
constexpr double kLooseStitch = 11.28e-3;  // [m]

SlackReproducer woven(const std::string& name, const std::string& weave, double radius) {
  std::string why;
  const auto chart = db::parse_weave_chart(weave, &why);
  if (!chart) throw std::logic_error("slack reproducer " + name + ": " + why);
  db::WovenTileOptions o;
  o.yarn_spacing = kWovenSpacing;
  o.yarn_radius = radius;
  o.weft_crimp_share = 0.5;  // balanced, as issue 37 measured them (docs/slack-tiles.md)
  SlackReproducer r;
  r.name = name;
  r.construction = weave + " weave (" + chart->text() + "), yarns " + db::format_g(1e3 * kWovenSpacing) +
                   " mm apart, R " + db::format_g(1e3 * radius) + " mm, balanced crimp";
  r.tile = db::make_woven_tile(*chart, o);
  r.params = default_params({kDefaultKs2, radius});
  return r;
}

SlackReproducer knit(const std::string& name, const std::string& chart_name, double radius) {
  std::string why;
  const auto chart = db::parse_knit_chart(chart_name, &why);
  if (!chart) throw std::logic_error("slack reproducer " + name + ": " + why);
  TileGenerationOptions o;
  o.geometry.stitch_length = kLooseStitch;
  o.geometry.yarn_radius = radius;
  o.default_ks2 = kDefaultKs2;
  GeneratedTile generated = generate_knit_tile(*chart, o);
  if (!generated.converged)
    throw Error(ErrorCategory::solve,
                "slack reproducer " + name + ": the knit generator did not relax it: " + generated.message);
  SlackReproducer r;
  r.name = name;
  r.construction = chart_name + " knitted loosely, L " + db::format_g(1e3 * kLooseStitch) + " mm, R " +
                   db::format_g(1e3 * radius) + " mm";
  r.tile = std::move(generated.tile);
  r.params = generated.params;
  return r;
}

// Name and builder of every reproducer, woven first.
const std::vector<std::pair<std::string, std::function<SlackReproducer(const std::string&)>>>& builders() {
  static const std::vector<std::pair<std::string, std::function<SlackReproducer(const std::string&)>>> all{
      {"plain_R0.25", [](const std::string& n) { return woven(n, "plain", 0.25e-3); }},
      {"plain_R0.5", [](const std::string& n) { return woven(n, "plain", 0.5e-3); }},
      {"basket_R0.25", [](const std::string& n) { return woven(n, "basket2x2", 0.25e-3); }},
      {"basket_R0.5", [](const std::string& n) { return woven(n, "basket2x2", 0.5e-3); }},
      {"loose_st_R0.35", [](const std::string& n) { return knit(n, "stockinette", 0.35e-3); }},
      {"loose_st_R0.5", [](const std::string& n) { return knit(n, "stockinette", 0.5e-3); }},
      {"open_rib_R0.35", [](const std::string& n) { return knit(n, "rib1x1", 0.35e-3); }},
      {"open_rib_R0.5", [](const std::string& n) { return knit(n, "rib1x1", 0.5e-3); }},
  };
  return all;
}

}  // namespace

const std::vector<std::string>& slack_reproducer_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v;
    for (const auto& [name, build] : builders()) v.push_back(name);
    return v;
  }();
  return names;
}

SlackReproducer make_slack_reproducer(const std::string& name) {
  for (const auto& [known, build] : builders())
    if (known == name) return build(name);
  throw Error(ErrorCategory::input, "no slack reproducer named '" + name + "'");
}

}  // namespace yarnfit::yarn
