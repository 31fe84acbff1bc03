#include "yarn_fit/fit/objective/yarn_objective.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>
#include <utility>

#include "fabrics_db/text_util.hpp"
#include "numerics/util/clock.hpp"
#include "numerics/util/error.hpp"
#include "results/metrics/error_metrics.hpp"
#include "yarn_fit/periodic/yarn_system.hpp"

namespace yarnfit::yarn {

namespace {

using numerics::Clock;

bool same_params(const yarn::YarnParams& a, const yarn::YarnParams& b) {
  return a.ks1 == b.ks1 && a.eps_s == b.eps_s && a.kb == b.kb && a.r1 == b.r1 && a.kc1 == b.kc1 && a.ks2 == b.ks2 &&
         a.kc2 == b.kc2 && a.r2 == b.r2;
}

ObjectiveResult finished(ObjectiveResult& out, std::string message, Clock::time_point start) {
  out.ok = message.empty();
  out.message = std::move(message);
  if (!out.ok) {
    out.value = std::numeric_limits<double>::infinity();
    if (!out.lower_bound) out.directions.clear();
  }
  out.seconds = numerics::seconds_since(start);
  return out;
}

// Target second Piola-Kirchhoff stress at s.
double target_pk2(const std::vector<db::UniaxialPoint>& pts, double s) {
  return pk2(interpolate_target(pts, s, &db::UniaxialPoint::stress), s);
}

DirectionScale comfort_scale(const db::DirectionTargets& t, const ObjectiveOptions& o) {
  DirectionScale sc;
  sc.direction = t.direction;
  const auto& p = t.stretch;
  // End of the comfort range: first crossing of the line force, linear in between.
  sc.comfort_stretch = p.back().stretch;
  for (std::size_t i = 1; i < p.size(); ++i) {
    if (p[i].stress >= o.comfort_line_force) {
      const double a = p[i - 1].stress, b = p[i].stress;
      const double f = b > a ? std::clamp((o.comfort_line_force - a) / (b - a), 0.0, 1.0) : 1.0;
      sc.comfort_stretch = p[i - 1].stretch + f * (p[i].stretch - p[i - 1].stretch);
      break;
    }
  }
  sc.comfort_value = target_pk2(p, sc.comfort_stretch);
  sc.stress_norm = sc.comfort_value;
  double cmax = std::abs(interpolate_target(p, sc.comfort_stretch, &db::UniaxialPoint::compression));
  for (const auto& q : p) {
    if (q.stretch > sc.comfort_stretch) break;
    sc.stress_norm = std::max(sc.stress_norm, pk2(q.stress, q.stretch));
    cmax = std::max(cmax, std::abs(q.compression));
  }
  sc.compression_norm = std::max(cmax, o.min_compression_norm);
  return sc;
}

}  // namespace

db::Problems ObjectiveOptions::problems() const {
  db::Problems out;
  if (samples < 2) out.add_field("samples", "must be at least 2 (got " + std::to_string(samples) + ")");
  if (compression_nodes < 2)
    out.add_field("compression_nodes", "must be at least 2 (got " + std::to_string(compression_nodes) + ")");
  if (!(comfort_line_force > 0.0)) out.add_field("comfort_line_force", "must be positive");
  if (!(min_compression_norm > 0.0)) out.add_field("min_compression_norm", "must be positive");
  if (!(std::isfinite(compression_weight) && compression_weight >= 0.0))
    out.add_field("compression_weight", "must be zero or positive");
  if (!(std::isfinite(bending_weight) && bending_weight >= 0.0)) out.add_field("bending_weight", "must be zero or positive");
  if (bending_samples < 1) out.add_field("bending_samples", "must be at least 1");
  if (!(compression_stress_fraction >= 0.0 && compression_stress_fraction < 0.1))
    out.add_field("compression_stress_fraction", "must be in [0, 0.1)");
  if (rest_period && !(period_stress_fraction > 0.0)) out.add_field("period_stress_fraction", "must be positive");
  return out;
}

YarnObjective::YarnObjective(yarn::YarnTile tile, std::vector<db::DirectionTargets> targets, ObjectiveOptions options)
    : m_tile(std::move(tile)), m_options(std::move(options)) {
  if (const db::Problems problems = m_options.problems(); !problems.empty())
    throw Error(ErrorCategory::input, "objective: " + problems.one_line());
  for (auto& t : targets) {
    if (t.stretch.size() < 2) continue;
    DirectionScale sc = comfort_scale(t, m_options);
    sc.compression_weight = m_options.compression_weight;
    if (!(sc.stress_norm > 0.0)) {
      throw Error(ErrorCategory::input, "objective: " + std::string(db::to_string(t.direction)) +
                                  " targets have no positive stress in the comfort range");
    }
    m_scales.push_back(sc);
    m_targets.push_back(std::move(t));
  }
  if (m_targets.empty()) throw Error(ErrorCategory::input, "objective: no direction has stretch targets");
  double smallest_norm = std::numeric_limits<double>::infinity();
  for (const auto& sc : m_scales) smallest_norm = std::min(smallest_norm, sc.stress_norm);
  // A solve that reaches its iteration limit with a residual force below 1e-3 of the
  // smallest stress norm times the shorter period changes a read-out by about 1e-3 of what
  // the objective compares it with: accept it as converged_loosely (counted in the result).
  if (m_options.solve.loose_tolerance == 0.0) {
    m_options.solve.loose_tolerance = 1e-3 * smallest_norm * m_tile.shorter_period();
  }
  // The stress read-out test stays off here unless asked for: with it the local step's stencil
  // differences see where each solve happened to stop, and a known-truth fit ended far off
  // the truth (docs/calibration.md). Solves end at the force or the loose tolerance.
  if (m_options.solve.stress_tolerance < 0.0) m_options.solve.stress_tolerance = 0.0;
  if (m_options.rest_period) {
    m_options.period.tolerance = Eigen::Vector2d::Constant(m_options.period_stress_fraction * smallest_norm);
  }
}

void YarnObjective::set_samples(int samples) {
  if (samples < 2) throw Error(ErrorCategory::input, "objective: samples must be at least 2");
  m_options.samples = samples;
}

double YarnObjective::operator()(const yarn::YarnParams& params) const {
  const ObjectiveResult r = evaluate(params);
  if (!r.ok) throw Error(ErrorCategory::solve, r.message);
  return r.value;
}

RestState YarnObjective::rest_state(const yarn::YarnParams& params) const {
  RestStateOptions o;
  o.rest_shape = m_options.rest_shape;
  o.rest = m_options.rest;
  o.rest_period = m_options.rest_period;
  o.period = m_options.period;
  return relax_rest_state(m_tile, params, o);
}

ObjectiveResult YarnObjective::evaluate(const yarn::YarnParams& params, double cutoff) const {
  const auto start = Clock::now();
  ObjectiveResult out;
  out.value = std::numeric_limits<double>::infinity();
  if (const db::Problems invalid = params.problems(); !invalid.empty())
    return finished(out, "invalid parameters: " + invalid.one_line(), start);
  const RestState rest = rest_state(params);
  out.rest = rest.rest;
  out.period = rest.period;
  out.newton_iterations += rest.newton_iterations;
  if (!rest.ok) return finished(out, rest.message, start);
  out.effects = rest.system->effects();
  AtRestOptions fresh;
  fresh.cutoff = cutoff;
  sweep_directions(rest, nullptr, fresh, out);
  return finished(out, out.message, start);
}

ObjectiveResult YarnObjective::evaluate_at_rest(const RestState& rest, const yarn::YarnParams& params,
                                                const AtRestOptions& options) const {
  const auto start = Clock::now();
  ObjectiveResult out;
  out.value = std::numeric_limits<double>::infinity();
  out.held_rest = true;
  out.derivative_params.assign(options.wanted.begin(), options.wanted.end());
  if (const db::Problems invalid = params.problems(); !invalid.empty())
    return finished(out, "invalid parameters: " + invalid.one_line(), start);
  if (!rest.ok || !rest.system) return finished(out, "no rest state to hold: " + rest.message, start);
  out.effects = rest.system->effects();
  sweep_directions(rest, &params, options, out);
  return finished(out, out.message, start);
}

SweepSettings YarnObjective::sweep_settings(std::size_t direction, const AtRestOptions& options) const {
  const DirectionScale& scale = m_scales[direction];
  SweepSettings s;
  s.samples = m_options.samples;
  s.every_sample = m_options.free_compression_every_sample;
  s.nodes = m_options.compression_nodes;
  s.compression = m_options.compression;
  s.compression.stress_tolerance = m_options.compression_stress_fraction * scale.stress_norm;
  s.solve = m_options.solve;
  s.root_correction = m_options.root_correction;
  s.flat_band = m_options.flat_band;
  s.accept_bands = m_options.accept_bands;
  s.wanted = options.wanted;
  s.cutoff = options.cutoff;
  s.record_states = options.record_states;
  if (options.warm != nullptr && options.warm->size() == m_targets.size()) s.warm = &(*options.warm)[direction];
  return s;
}

void YarnObjective::sweep_directions(const RestState& rest, const yarn::YarnParams* params,
                                     const AtRestOptions& options, ObjectiveResult& out) const {
  // Directions in parallel when not already inside a parallel region (the swarm evaluates
  // particles in parallel; the local step is serial and would leave a core idle). Each
  // direction's result does not depend on the others, so the value is the same whatever the
  // number of threads. Each direction decides on its own partial sum whether to stop at the
  // cutoff; run serially, the directions after a stopped one are skipped.
  const int nd = static_cast<int>(m_targets.size());
  std::vector<DirectionError> errors(static_cast<std::size_t>(nd));
  std::vector<std::string> failures(static_cast<std::size_t>(nd));
  std::vector<SweepCounts> counts(static_cast<std::size_t>(nd));
  std::vector<char> skipped(static_cast<std::size_t>(nd), 0);
  const bool parallel = nd > 1 && !omp_in_parallel();
  const auto stopped_before = [&](int d) {
    return std::any_of(counts.begin(), counts.begin() + d, [](const SweepCounts& c) { return c.stopped; });
  };
#pragma omp parallel for schedule(dynamic) if (parallel)
  for (int d = 0; d < nd; ++d) {
    const auto k = static_cast<std::size_t>(d);
    if (!parallel && stopped_before(d)) {
      skipped[k] = 1;
      continue;
    }
    yarn::YarnSystem copy = *rest.system;
    // The rest state's own parameters keep its contact list: the evaluation is then bitwise
    // the one evaluate() makes of them.
    if (params != nullptr && !same_params(*params, rest.params)) copy.set_params(*params);
    errors[k].scale = m_scales[k];
    failures[k] = sweep_direction(copy, rest.g, m_targets[k], sweep_settings(k, options), errors[k], counts[k]);
    if (failures[k].empty() && !counts[k].stopped)
      failures[k] = sweep_bending(copy, rest.g, m_targets[k], m_options.bending_samples, m_options.bending_weight,
                                  m_options.solve, options.wanted, errors[k], counts[k]);
  }
  out.lower_bound = std::any_of(counts.begin(), counts.end(), [](const SweepCounts& c) { return c.stopped; });
  double total = 0.0;
  for (std::size_t k = 0; k < errors.size(); ++k) {
    out.newton_iterations += counts[k].newton_iterations;
    out.loose_solves += counts[k].loose_solves;
    if (skipped[k]) continue;
    if (!failures[k].empty()) {
      if (out.lower_bound) continue;  // g is already known to reach the cutoff
      out.message = failures[k];
      return;
    }
    total += errors[k].value;
    out.solves += errors[k].solves;
    out.held_compressions += errors[k].held;
    out.flat_compressions += errors[k].flat;
    out.directions.push_back(std::move(errors[k]));
  }
  out.value = total;
}

WeightedErrors weighted_errors(const ObjectiveResult& result) {
  WeightedErrors out;
  if (!result.ok) return out;
  for (const auto& d : result.directions) {
    const double n = static_cast<double>(d.stretch.size());
    for (std::size_t i = 0; i < d.stretch.size(); ++i) {
      const double w = d.weight[i] / n;
      out.error.push_back((d.stress_sim[i] - d.stress_target[i]) / d.scale.stress_norm);
      out.weight.push_back(w);
      out.error.push_back((d.compression_sim[i] - d.compression_target[i]) / d.scale.compression_norm);
      out.weight.push_back(w * d.scale.compression_weight);
    }
    const double nb = static_cast<double>(d.bending_sim.size());
    for (std::size_t j = 0; j < d.bending_sim.size(); ++j) {
      out.error.push_back((d.bending_sim[j] - d.bending_target[j]) / d.bending_norm);
      out.weight.push_back(d.bending_weight / nb);
    }
  }
  return out;
}

Eigen::MatrixXd residual_jacobian(const ObjectiveResult& result) {
  if (!result.ok) return {};
  const auto k = static_cast<Eigen::Index>(result.derivative_params.size());
  Eigen::Index rows = 0;
  for (const auto& d : result.directions)
    rows += 2 * static_cast<Eigen::Index>(d.stretch.size()) + static_cast<Eigen::Index>(d.bending_sim.size());
  Eigen::MatrixXd out(rows, k);
  Eigen::Index row = 0;
  for (const auto& d : result.directions) {
    const double n = static_cast<double>(d.stretch.size());
    for (std::size_t i = 0; i < d.stretch.size(); ++i) {
      const double root_weight = std::sqrt(d.weight[i] / n);
      out.row(row++) = (root_weight / d.scale.stress_norm) * d.d_stress_sim[i].transpose();
      out.row(row++) = (root_weight * std::sqrt(d.scale.compression_weight) / d.scale.compression_norm) *
                       d.d_compression_sim[i].transpose();
    }
    const double nb = static_cast<double>(d.bending_sim.size());
    for (std::size_t j = 0; j < d.bending_sim.size(); ++j)
      out.row(row++) = (std::sqrt(d.bending_weight / nb) / d.bending_norm) * d.d_bending_sim[j].transpose();
  }
  return out;
}

Eigen::VectorXd residual_vector(const ObjectiveResult& result) {
  const WeightedErrors we = weighted_errors(result);
  Eigen::VectorXd out(static_cast<Eigen::Index>(we.error.size()));
  for (std::size_t i = 0; i < we.error.size(); ++i)
    out[static_cast<Eigen::Index>(i)] = std::sqrt(we.weight[i]) * we.error[i];
  return out;
}

}  // namespace yarnfit::yarn
