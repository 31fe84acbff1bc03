#include "yarn_fit/fit/problem/shape_search.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "numerics/util/clock.hpp"
#include "yarn_fit/generate/knit_generation.hpp"
#include "numerics/util/non_finite.hpp"

namespace yarnfit::yarn {
namespace {

using numerics::k_inf;
using numerics::k_nan;

// A tile of the knit at aspect a and loop density K_s, held there, its crossings 2R apart.
std::optional<db::PeriodicTile> shaped_tile(const db::KnitSpec& knit, double aspect, double density, double radius,
                                            double ks2, std::string& why) {
  yarn::TileGenerationOptions o;
  o.geometry.stitch_length = knit.stitch_length;
  o.geometry.yarn_radius = radius;
  o.geometry.wale_spacing = knit.stitch_length / std::sqrt(density * aspect);
  o.geometry.course_spacing = knit.stitch_length * std::sqrt(aspect / density);
  o.default_ks2 = ks2;
  try {
    yarn::GeneratedTile t = yarn::generate_knit_tile(knit.chart, o);
    if (!t.converged) {
      why = t.message;
      return std::nullopt;
    }
    return std::move(t.tile);
  } catch (const std::invalid_argument& e) {
    why = e.what();
    return std::nullopt;
  }
}

// The parabola through three points: its vertex and the half-width where it reaches twice
// the best value (NaN when it opens downwards).
struct Parabola {
  double vertex = k_nan;
  double lower = k_nan, upper = k_nan;
};
Parabola parabola(double x0, double y0, double x1, double y1, double x2, double y2, double best) {
  const double d01 = (y1 - y0) / (x1 - x0), d12 = (y2 - y1) / (x2 - x1);
  const double a = (d12 - d01) / (x2 - x0);
  Parabola p;
  if (!(a > 0.0)) return p;
  const double b = d01 - a * (x0 + x1);
  p.vertex = -b / (2.0 * a);
  const double c = y0 - a * x0 * x0 - b * x0;
  const double at_vertex = c - b * b / (4.0 * a);
  const double rise = 2.0 * best - at_vertex;
  if (rise > 0.0) {
    const double half = std::sqrt(rise / a);
    p.lower = p.vertex - half;
    p.upper = p.vertex + half;
  }
  return p;
}

}  // namespace

std::optional<LoopShapePrior> loop_shape_prior(const db::KnitChart& chart) {
  int knits = 0, purls = 0;
  for (int j = 0; j < chart.courses(); ++j)
    for (int k = 0; k < chart.wales(); ++k) (chart.face_sign(j, k) > 0 ? knits : purls)++;
  if (knits > 0 && purls > 0) return std::nullopt;
  return LoopShapePrior{6.35, 3.60, "plain knit: loop-shape constants of the registered HYLC stockinette tiles (K_c = 6.35, K_w = 3.60)"};
}

bool shape_is_fitted(const db::Fabric& fabric, const YarnFitSettings& yarn, const ShapeSearchSettings& shape) {
  const bool thesis = yarn.global_method == GlobalMethod::swarm && yarn.local_method == LocalMethod::cobyla;
  return shape.enabled && !thesis && fabric.pattern && fabric.pattern->knit && !fabric.pattern->knit->gauge;
}

YarnFitResult fit_yarn_with_shape(YarnFitProblem& problem, const db::KnitSpec& knit, const db::PeriodicTile& generated,
                                  const YarnFitSettings& settings, const ShapeSearchSettings& shape, ShapeFit& out) {
  const auto start = numerics::Clock::now();
  const double length = knit.stitch_length;
  const double wales = knit.chart.wales(), courses = knit.chart.courses();
  // The generated tile's own period, as the mechanics relaxed it.
  const double relaxed_w = generated.period_x / wales, relaxed_p = generated.period_y / courses;
  // The prior: the registered constants, or that period.
  double aspect0 = relaxed_p / relaxed_w, density = length * length / (relaxed_p * relaxed_w);
  out.prior_source = knit.chart.name + ": the period its generated tile relaxes to (no registered constants)";
  if (const auto prior = loop_shape_prior(knit.chart)) {
    aspect0 = prior->aspect();
    density = prior->courses_constant * prior->wales_constant;
    out.prior_source = prior->source;
  }
  out.prior = aspect0;
  out.lower = shape.lower * aspect0;
  out.upper = shape.upper * aspect0;

  YarnFitResult best;
  double best_g = k_inf;
  std::optional<db::PeriodicTile> best_tile;
  const auto objective_of = [](const YarnFitResult& r) { return r.ok ? r.final.value : k_inf; };
  const auto keep = [&](ShapeTrial& t, YarnFitResult r, const db::PeriodicTile& tile) {
    t.objective = objective_of(r);
    if (!r.ok) t.message = r.message;
    if (t.objective < best_g) {
      best_g = t.objective;
      best = std::move(r);
      best_tile = tile;
    }
  };
  // Trial 0: the tile as generated, its period the mechanics' and moved by the fit's period
  // steps, fitted in full: the fit without a shape of its own is always a candidate, so the
  // search never ends above its g.
  {
    const auto t0 = numerics::Clock::now();
    ShapeTrial t;
    t.aspect = relaxed_p / relaxed_w;
    t.full_fit = true;
    t.held = false;
    t.r1 = knit.yarn_radius;
    problem.tile = yarn::make_yarn_tile(generated);
    keep(t, fit_yarn(problem, settings), generated);
    t.seconds = numerics::seconds_since(t0);
    out.trials.push_back(t);
  }
  if (!best.ok) {
    out.aspect = out.trials.front().aspect;
    out.seconds = numerics::seconds_since(start);
    return best;
  }
  // A held trial: the tile at `aspect` (its loops crossing 2R apart, R the knit's yarn radius:
  // only a differs between trials; each candidate's rest state resolves the contacts at its own
  // R1), its period held, fitted locally from the best parameters so far and, when the caller
  // gave one, from its own start too (the best fit counts). The best parameters are tried at
  // R1 = R, the radius the tile's crossings were built with, and where that fails at their own
  // R1: on a held period an R1 far from the tile's leaves contacts the rest state cannot
  // resolve (no free compression at s = 0: R1 50 % above R on a generated stockinette, the
  // acrylic stockinette's fitted R1 at 61 % of R on the other side), and which side fails
  // depends on the knit. The local step moves R1 from there. The best parameters so far alone
  // are a poor start when they come from the generated tile, whose relaxed period pushed them
  // to their bounds: the local step then stops in another basin at every aspect
  // (docs/calibration.md, "The tile's shape").
  YarnFitSettings held = settings;
  held.objective.rest.period_chord_steps = 0;
  held.checkpoint.clear();
  held.resume = false;
  const std::optional<yarn::YarnParams> given_start = problem.start;
  const auto trial = [&](double aspect) {
    const auto t0 = numerics::Clock::now();
    ShapeTrial t;
    t.aspect = aspect;
    t.r1 = knit.yarn_radius;
    std::string why;
    const auto tile = shaped_tile(knit, aspect, density, t.r1, problem.scales.ks2, why);
    if (!tile) {
      t.objective = k_inf;
      t.message = "tile: " + why;
    } else {
      problem.tile = yarn::make_yarn_tile(*tile);
      std::optional<YarnFitResult> fitted;
      const auto fit_from = [&](yarn::YarnParams from) {
        problem.start = from;
        YarnFitResult r = fit_yarn(problem, held);
        if (!fitted || objective_of(r) < objective_of(*fitted)) fitted = std::move(r);
      };
      yarn::YarnParams at_tile_radius = best.params;
      at_tile_radius.r1 = t.r1;
      fit_from(at_tile_radius);
      if (!fitted->ok && best.params.r1 != t.r1) fit_from(best.params);
      if (given_start) {
        yarn::YarnParams from = *given_start;
        from.r1 = t.r1;
        fit_from(from);
      }
      keep(t, std::move(*fitted), *tile);
    }
    t.seconds = numerics::seconds_since(t0);
    out.trials.push_back(t);
    return t.objective;
  };
  // The held prior, then steps away from it while the held trials' g falls (against the
  // previous held trial, not the generated tile's fit: the held profile is what is searched,
  // and a held tile that loses to the generated one at the prior may still win further out),
  // first upwards, then (if the first step did not help) downwards.
  const double at_prior = trial(aspect0);
  for (const double direction : {1.0, -1.0}) {
    double a = aspect0, previous = at_prior;
    bool improved_once = false;
    while (static_cast<int>(out.trials.size()) <= shape.max_trials) {
      // A step past a bound stops at the bound, so that a minimum near it is still bracketed.
      const double next = std::clamp(a * (1.0 + direction * shape.step), out.lower, out.upper);
      if (std::abs(next / a - 1.0) < 1e-9) break;  // at the bound already
      const double g = trial(next);
      if (!(g < previous)) break;
      improved_once = true;
      a = next;
      previous = g;
    }
    if (improved_once) break;  // the other side was worse at the first step
  }
  // The parabola through the best held trial and its nearest held neighbours.
  std::vector<ShapeTrial> sorted;
  for (const auto& t : out.trials)
    if (t.held) sorted.push_back(t);
  std::sort(sorted.begin(), sorted.end(), [](const ShapeTrial& x, const ShapeTrial& y) { return x.aspect < y.aspect; });
  const auto at = std::min_element(sorted.begin(), sorted.end(),
                                   [](const ShapeTrial& x, const ShapeTrial& y) { return x.objective < y.objective; });
  out.range_lower = out.range_upper = k_nan;
  if (!sorted.empty() && at != sorted.begin() && at + 1 != sorted.end() && std::isfinite((at - 1)->objective) &&
      std::isfinite((at + 1)->objective)) {
    const Parabola p = parabola((at - 1)->aspect, (at - 1)->objective, at->aspect, at->objective, (at + 1)->aspect,
                                (at + 1)->objective, at->objective);
    out.range_lower = p.lower;
    out.range_upper = p.upper;
    const bool new_point = std::isfinite(p.vertex) && std::abs(p.vertex / at->aspect - 1.0) > 0.01 &&
                           p.vertex > (at - 1)->aspect && p.vertex < (at + 1)->aspect;
    if (new_point && static_cast<int>(out.trials.size()) <= shape.max_trials) trial(p.vertex);
  }
  const auto winner = std::min_element(out.trials.begin(), out.trials.end(),
                                       [](const ShapeTrial& x, const ShapeTrial& y) { return x.objective < y.objective; });
  out.aspect = winner->aspect;
  out.held = winner->held;
  out.wale_spacing = winner->held ? length / std::sqrt(density * out.aspect) : relaxed_w;
  out.course_spacing = winner->held ? length * std::sqrt(out.aspect / density) : relaxed_p;
  problem.start = given_start;
  if (best_tile) {
    out.tile = *best_tile;
    problem.tile = yarn::make_yarn_tile(*best_tile);
  }
  out.seconds = numerics::seconds_since(start);
  return best;
}

}  // namespace yarnfit::yarn
