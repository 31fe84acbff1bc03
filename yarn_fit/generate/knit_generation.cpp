#include "yarn_fit/generate/knit_generation.hpp"

#include <map>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "numerics/util/clock.hpp"
#include "numerics/util/error.hpp"
#include "yarn_fit/periodic/yarn_tile.hpp"
#include "yarn_fit/scenes/stretch_sweep.hpp"

namespace yarnfit::yarn {
namespace {

// σ_s at 10 % stretch along `angle`, reached in four warm-started free-compression steps
// from the rest state g; NaN when a point fails.
double stress_at_ten_percent(YarnSystem& system, const Eigen::VectorXd& g, double angle,
                             const EquilibriumOptions& solve) {
  YarnSystem copy = system;
  Eigen::VectorXd state = g;
  StretchSweepOptions options;
  options.solve = solve;
  const StretchSweep sweep = sweep_stretch(copy, angle, {0.025, 0.05, 0.075, 0.1}, state, options);
  const Sample& last = sweep.points.back();
  return last.ok ? last.stress_s : std::nan("");
}

}  // namespace

db::PeriodicTile tile_at_rest(const db::PeriodicTile& source, const YarnSystem& system, const Eigen::VectorXd& g) {
  const YarnTile& tile = system.tile();
  if (std::abs(tile.lattice(0, 1)) > 0.0 || std::abs(tile.lattice(1, 0)) > 0.0)
    throw Error(ErrorCategory::input, "tile_at_rest: the pyp layout holds a rectangular period only");
  if (tile.vertex_count() != source.vertex_count() || tile.edge_count() != source.edge_count())
    throw Error(ErrorCategory::input, "tile_at_rest: the system's tile is not made from this pyp tile");
  db::PeriodicTile out = source;
  out.period_x = tile.lattice(0, 0);
  out.period_y = tile.lattice(1, 1);
  for (int v = 0; v < tile.vertex_count(); ++v) {
    const Eigen::Vector3d x = system.position(g, v, {0, 0});
    out.positions[static_cast<std::size_t>(v)] = {x.x(), x.y(), x.z()};
    out.rest_curvatures[static_cast<std::size_t>(v)] = {tile.corners[static_cast<std::size_t>(v)].rest_curvature.norm(), 0.0};
  }
  for (int e = 0; e < tile.edge_count(); ++e)
    out.rest_lengths[static_cast<std::size_t>(e)] = tile.edges[static_cast<std::size_t>(e)].rest_length;
  out.reference_directors.clear();
  db::fill_tile_defaults(out);
  return out;
}

namespace {

// A held period (a knitting gauge): the rest-shape heuristic without its period steps, so that
// the rest lengths and curvatures absorb what stress they can (thesis 6.5.2); the rest stress
// left is reported, not driven under the tolerance (only the period could do that).
void hold_period(YarnSystem& system, Eigen::VectorXd& g, const TileGenerationOptions& options, GeneratedTile& out) {
  RestShapeOptions rest;
  rest.period_chord_steps = 0;
  rest.solve = options.solve;
  const RestShapeResult relaxed = relax_rest_shape(system, g, rest);
  out.rounds = 1;
  out.relaxation.converged = relaxed.converged;
  out.relaxation.rest_stress = relaxed.rest_stress;
  out.relaxation.initial_stress = relaxed.stress_before_period;
  if (!relaxed.converged) {
    out.message = "rest shape at the held period: the last solve did not converge";
    return;
  }
  out.stress_at_10 = {stress_at_ten_percent(system, g, weft_angle(), options.solve),
                      stress_at_ten_percent(system, g, warp_angle(), options.solve)};
  if (!out.stress_at_10.allFinite()) {
    out.message = "sigma_s at 10 % stretch could not be measured at the held period";
    return;
  }
  const Eigen::Vector2d rest_stress(relaxed.rest_stress(0, 0), relaxed.rest_stress(1, 1));
  out.rest_stress_ratio = rest_stress.cwiseAbs().cwiseQuotient(out.stress_at_10.cwiseAbs()).maxCoeff();
  out.converged = true;  // the rest stress left is the gauge's: reported, not a failure
}

}  // namespace

GeneratedTile generate_knit_tile(const db::KnitChart& chart, const TileGenerationOptions& options) {
  const auto start = numerics::Clock::now();
  GeneratedTile out;
  out.initial = db::make_knit_tile(chart, options.geometry);
  const double radius = options.geometry.yarn_radius;
  out.params = options.params ? *options.params : default_params({options.default_ks2, radius});
  if (const db::Problems invalid = out.params.problems(); !invalid.empty())
    throw Error(ErrorCategory::input, "generate_knit_tile: " + invalid.one_line());

  YarnSystem system(make_yarn_tile(out.initial.tile), out.params);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(system.dof_count());
  const EquilibriumOptions& solve = options.solve;
  // The first tolerance: a guess from the stiffness of the soft phase (1e-2 of ks1 per wale
  // spacing, the line force of a 1 % strain of one yarn per wale); every later round uses the
  // measured σ_s(10 %).
  Eigen::Vector2d tolerance = Eigen::Vector2d::Constant(1e-2 * out.params.ks1 / out.initial.wale_spacing);
  if (options.geometry.wale_spacing || options.hold_period) {
    hold_period(system, g, options, out);
  } else
  for (out.rounds = 1; out.rounds <= options.rounds; ++out.rounds) {
    RestPeriodOptions relax;
    relax.tolerance = tolerance;
    relax.max_steps = options.max_period_steps;
    relax.solve = solve;
    out.relaxation = relax_rest_period(system, g, relax);
    if (!out.relaxation.converged) {
      out.message = "period relaxation: " + out.relaxation.message;
      break;
    }
    out.stress_at_10 = {stress_at_ten_percent(system, g, weft_angle(), solve),
                        stress_at_ten_percent(system, g, warp_angle(), solve)};
    if (!out.stress_at_10.allFinite() || !(out.stress_at_10.minCoeff() > 0.0)) {
      // A loose tile (thin yarn, long loops) may not resist 10 % stretch at all, or its free-
      // compression search may not settle: without a positive σ_s(10 %) there is no scale
      // for "stress-free at rest".
      const auto said = [](double v) { return std::isfinite(v) ? std::to_string(v) + " N/m" : std::string("failed"); };
      out.message = "sigma_s at 10 % stretch is weft " + said(out.stress_at_10[0]) + ", warp " +
                    said(out.stress_at_10[1]) + ": no positive scale for the rest stress (a slack tile?)";
      break;
    }
    const Eigen::Vector2d rest(out.relaxation.rest_stress(0, 0), out.relaxation.rest_stress(1, 1));
    out.rest_stress_ratio = rest.cwiseAbs().cwiseQuotient(out.stress_at_10).maxCoeff();
    tolerance = options.rest_stress_fraction * out.stress_at_10;
    if (out.rest_stress_ratio <= options.rest_stress_fraction) {
      out.converged = true;
      break;
    }
  }
  if (!out.converged && out.message.empty() && !options.geometry.wale_spacing && !options.hold_period)
    out.message = "rest stress " + std::to_string(out.rest_stress_ratio) + " of sigma_s(10 %) after " +
                  std::to_string(options.rounds) + " rounds";
  out.rounds = std::min(out.rounds, options.rounds);
  out.held_period = options.geometry.wale_spacing.has_value() || options.hold_period;
  out.tile = tile_at_rest(out.initial.tile, system, g);
  out.min_distance = system.min_contact_distance(g);
  double rest_length = 0.0;
  for (const double l : out.tile.rest_lengths) rest_length += l;
  out.stitch_length = rest_length / (chart.courses() * chart.wales());
  out.seconds = numerics::seconds_since(start);
  return out;
}

results::TileFile to_file(const GeneratedTile& t) {
  results::TileFile f;
  f.chart = t.initial.chart.name;
  f.chart_rows = t.initial.chart.text();
  f.period_mm = {1e3 * t.tile.period_x, 1e3 * t.tile.period_y};
  f.wale_spacing_mm = 1e3 * t.wale_spacing();
  f.course_spacing_mm = 1e3 * t.course_spacing();
  f.courses_per_cm = 1e-2 / t.course_spacing();
  f.wales_per_cm = 1e-2 / t.wale_spacing();
  f.stitch_length_mm = 1e3 * t.stitch_length;
  f.yarn_radius_mm = 1e3 * t.tile.radius;
  f.vertices = static_cast<long long>(t.tile.vertex_count());
  f.min_distance_mm = 1e3 * t.min_distance;
  f.rest_stress_N_per_m = {t.relaxation.rest_stress(0, 0), t.relaxation.rest_stress(1, 1)};
  f.stress_at_10pct_N_per_m = {t.stress_at_10[0], t.stress_at_10[1]};
  f.rest_stress_ratio = t.rest_stress_ratio;
  f.period_change = {t.tile.period_x / t.initial.tile.period_x - 1.0, t.tile.period_y / t.initial.tile.period_y - 1.0};
  f.converged = t.converged;
  f.message = t.message;
  f.rounds = t.rounds;
  f.seconds = t.seconds;
  f.params = to_json(t.params).get<std::map<std::string, double>>();
  return f;
}

}  // namespace yarnfit::yarn
