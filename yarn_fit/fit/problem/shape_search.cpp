#include "yarn_fit/fit/problem/shape_search.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "numerics/util/clock.hpp"
#include "numerics/util/error.hpp"
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
  } catch (const Error& e) {
    if (e.category() != ErrorCategory::input) throw;  // a refused geometry fails the trial, nothing else
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

namespace {

double objective_of(const YarnFitResult& r) { return r.ok ? r.final.value : k_inf; }

// One search over a generated knit tile's course/wale aspect (fit_yarn_with_shape): the state
// the trials share, and the steps in the order `run` takes them.
class ShapeSearch {
 public:
  ShapeSearch(YarnFitProblem& problem, const db::KnitSpec& knit, const db::PeriodicTile& generated,
              const YarnFitSettings& settings, const ShapeSearchSettings& shape, ShapeFit& out)
      : m_start(numerics::Clock::now()),
        m_problem(problem),
        m_knit(knit),
        m_generated(generated),
        m_settings(settings),
        m_shape(shape),
        m_out(out),
        m_length(knit.stitch_length),
        // The generated tile's own period, as the mechanics relaxed it.
        m_relaxed_w(generated.period_x / knit.chart.wales()),
        m_relaxed_p(generated.period_y / knit.chart.courses()) {}

  YarnFitResult run() {
    set_prior();
    fit_as_generated();
    if (!m_best.ok) {
      m_out.aspect = m_out.trials.front().aspect;
      m_out.seconds = numerics::seconds_since(m_start);
      return std::move(m_best);
    }
    prepare_held_trials();
    walk_from_prior(held_trial(m_aspect0));
    refine_by_parabola();
    finish();
    return std::move(m_best);
  }

 private:
  // The prior: the registered constants, or the generated tile's relaxed period.
  void set_prior() {
    m_aspect0 = m_relaxed_p / m_relaxed_w;
    m_density = m_length * m_length / (m_relaxed_p * m_relaxed_w);
    m_out.prior_source = m_knit.chart.name + ": the period its generated tile relaxes to (no registered constants)";
    if (const auto prior = loop_shape_prior(m_knit.chart)) {
      m_aspect0 = prior->aspect();
      m_density = prior->courses_constant * prior->wales_constant;
      m_out.prior_source = prior->source;
    }
    m_out.prior = m_aspect0;
    m_out.lower = m_shape.lower * m_aspect0;
    m_out.upper = m_shape.upper * m_aspect0;
  }

  void keep(ShapeTrial& t, YarnFitResult r, const db::PeriodicTile& tile) {
    t.objective = objective_of(r);
    if (!r.ok) t.message = r.message;
    if (t.objective < m_best_g) {
      m_best_g = t.objective;
      m_best = std::move(r);
      m_best_tile = tile;
    }
  }

  // Trial 0: the tile as generated, its period the mechanics' and moved by the fit's period
  // steps, fitted in full: the fit without a shape of its own is always a candidate, so the
  // search never ends above its g.
  void fit_as_generated() {
    const auto t0 = numerics::Clock::now();
    ShapeTrial t;
    t.aspect = m_relaxed_p / m_relaxed_w;
    t.full_fit = true;
    t.held = false;
    t.r1 = m_knit.yarn_radius;
    m_problem.tile = yarn::make_yarn_tile(m_generated);
    keep(t, fit_yarn(m_problem, m_settings), m_generated);
    t.seconds = numerics::seconds_since(t0);
    m_out.trials.push_back(t);
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
  void prepare_held_trials() {
    m_held = m_settings;
    m_held.objective.rest.period_chord_steps = 0;
    m_held.checkpoint.clear();
    m_held.resume = false;
    m_given_start = m_problem.start;
  }

  double held_trial(double aspect) {
    const auto t0 = numerics::Clock::now();
    ShapeTrial t;
    t.aspect = aspect;
    t.r1 = m_knit.yarn_radius;
    std::string why;
    const auto tile = shaped_tile(m_knit, aspect, m_density, t.r1, m_problem.scales.ks2, why);
    if (!tile) {
      t.objective = k_inf;
      t.message = "tile: " + why;
    } else {
      m_problem.tile = yarn::make_yarn_tile(*tile);
      keep(t, held_fit(t.r1), *tile);
    }
    t.seconds = numerics::seconds_since(t0);
    m_out.trials.push_back(t);
    return t.objective;
  }

  // The best of the local fits on the problem's (held) tile from the starts held_trial names.
  YarnFitResult held_fit(double r1) {
    std::optional<YarnFitResult> fitted;
    const auto fit_from = [&](yarn::YarnParams from) {
      m_problem.start = from;
      YarnFitResult r = fit_yarn(m_problem, m_held);
      if (!fitted || objective_of(r) < objective_of(*fitted)) fitted = std::move(r);
    };
    yarn::YarnParams at_tile_radius = m_best.params;
    at_tile_radius.r1 = r1;
    fit_from(at_tile_radius);
    if (!fitted->ok && m_best.params.r1 != r1) fit_from(m_best.params);
    if (m_given_start) {
      yarn::YarnParams from = *m_given_start;
      from.r1 = r1;
      fit_from(from);
    }
    return std::move(*fitted);
  }

  // Steps away from the held prior while the held trials' g falls (against the previous held
  // trial, not the generated tile's fit: the held profile is what is searched, and a held tile
  // that loses to the generated one at the prior may still win further out), first upwards,
  // then (if the first step did not help) downwards.
  void walk_from_prior(double at_prior) {
    for (const double direction : {1.0, -1.0}) {
      double a = m_aspect0, previous = at_prior;
      bool improved_once = false;
      while (static_cast<int>(m_out.trials.size()) <= m_shape.max_trials) {
        // A step past a bound stops at the bound, so that a minimum near it is still bracketed.
        const double next = std::clamp(a * (1.0 + direction * m_shape.step), m_out.lower, m_out.upper);
        if (std::abs(next / a - 1.0) < 1e-9) break;  // at the bound already
        const double g = held_trial(next);
        if (!(g < previous)) break;
        improved_once = true;
        a = next;
        previous = g;
      }
      if (improved_once) break;  // the other side was worse at the first step
    }
  }

  // The parabola through the best held trial and its nearest held neighbours: the range where
  // g stays within twice the best's, and one more trial at its vertex when that is new.
  void refine_by_parabola() {
    std::vector<ShapeTrial> sorted;
    for (const auto& t : m_out.trials)
      if (t.held) sorted.push_back(t);
    std::sort(sorted.begin(), sorted.end(), [](const ShapeTrial& x, const ShapeTrial& y) { return x.aspect < y.aspect; });
    const auto at = std::min_element(sorted.begin(), sorted.end(),
                                     [](const ShapeTrial& x, const ShapeTrial& y) { return x.objective < y.objective; });
    m_out.range_lower = m_out.range_upper = k_nan;
    if (sorted.empty() || at == sorted.begin() || at + 1 == sorted.end() || !std::isfinite((at - 1)->objective) ||
        !std::isfinite((at + 1)->objective))
      return;
    const Parabola p = parabola((at - 1)->aspect, (at - 1)->objective, at->aspect, at->objective, (at + 1)->aspect,
                                (at + 1)->objective, at->objective);
    m_out.range_lower = p.lower;
    m_out.range_upper = p.upper;
    const bool new_point = std::isfinite(p.vertex) && std::abs(p.vertex / at->aspect - 1.0) > 0.01 &&
                           p.vertex > (at - 1)->aspect && p.vertex < (at + 1)->aspect;
    if (new_point && static_cast<int>(m_out.trials.size()) <= m_shape.max_trials) held_trial(p.vertex);
  }

  // The winner's shape in the answer, and the problem left with its tile and the caller's start.
  void finish() {
    const auto winner = std::min_element(m_out.trials.begin(), m_out.trials.end(),
                                         [](const ShapeTrial& x, const ShapeTrial& y) { return x.objective < y.objective; });
    m_out.aspect = winner->aspect;
    m_out.held = winner->held;
    m_out.wale_spacing = winner->held ? m_length / std::sqrt(m_density * m_out.aspect) : m_relaxed_w;
    m_out.course_spacing = winner->held ? m_length * std::sqrt(m_out.aspect / m_density) : m_relaxed_p;
    m_problem.start = m_given_start;
    if (m_best_tile) {
      m_out.tile = *m_best_tile;
      m_problem.tile = yarn::make_yarn_tile(*m_best_tile);
    }
    m_out.seconds = numerics::seconds_since(m_start);
  }

  const numerics::Clock::time_point m_start;
  YarnFitProblem& m_problem;
  const db::KnitSpec& m_knit;
  const db::PeriodicTile& m_generated;
  const YarnFitSettings& m_settings;
  const ShapeSearchSettings& m_shape;
  ShapeFit& m_out;
  const double m_length, m_relaxed_w, m_relaxed_p;
  double m_aspect0 = 0.0, m_density = 0.0;
  YarnFitResult m_best;
  double m_best_g = k_inf;
  std::optional<db::PeriodicTile> m_best_tile;
  YarnFitSettings m_held;
  std::optional<yarn::YarnParams> m_given_start;
};

}  // namespace

YarnFitResult fit_yarn_with_shape(YarnFitProblem& problem, const db::KnitSpec& knit, const db::PeriodicTile& generated,
                                  const YarnFitSettings& settings, const ShapeSearchSettings& shape, ShapeFit& out) {
  return ShapeSearch(problem, knit, generated, settings, shape, out).run();
}

}  // namespace yarnfit::yarn
