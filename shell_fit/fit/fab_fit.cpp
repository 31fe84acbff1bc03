#include "shell_fit/fit/fab_fit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "numerics/util/clock.hpp"
#include "shell_fit/scenes/clamped_stretch.hpp"
#include "shell_fit/scenes/loop_bend.hpp"

namespace yarnfit::shell {

namespace {

struct Sample {
  double x = 0.0;  // stretch, or clamp distance [m]
  double force = 0.0;
};

// Linear interpolation through (xs, ys), xs ascending; clamped at the ends.
double interpolate(const std::vector<double>& xs, const std::vector<double>& ys, double x) {
  if (x <= xs.front()) return ys.front();
  if (x >= xs.back()) return ys.back();
  const auto hi = static_cast<std::size_t>(std::upper_bound(xs.begin(), xs.end(), x) - xs.begin());
  const double t = (x - xs[hi - 1]) / (xs[hi] - xs[hi - 1]);
  return (1.0 - t) * ys[hi - 1] + t * ys[hi];
}

std::vector<Sample> loading_samples(const db::FabTest& test) {
  std::vector<Sample> out;
  for (const auto& b : test.branches)
    if (b.branch == db::FabBranch::loading)
      for (std::size_t i = 0; i < b.clamp_distance.size(); ++i) out.push_back({b.clamp_distance[i], b.raw_force[i]});
  return out;
}

// Σ|model − measured| / Σ|measured| and the mean |model − measured| of (x, force) samples
// against the model curve through (xs, ys), `offset` taken off the readings.
void score(const std::vector<Sample>& samples, const std::vector<double>& xs, const std::vector<double>& ys,
           double offset, FabTestError& e) {
  double diff = 0.0, size = 0.0;
  for (const auto& s : samples) {
    const double measured = s.force - offset;
    diff += std::abs(interpolate(xs, ys, s.x) - measured);
    size += std::abs(measured);
  }
  e.samples = static_cast<int>(samples.size());
  e.offset = offset;
  e.force_pct = size > 0.0 ? 100.0 * diff / size : std::numeric_limits<double>::quiet_NaN();
  e.mean_abs_error = samples.empty() ? 0.0 : diff / static_cast<double>(samples.size());
}

}  // namespace

FabTestError predict_fab_stretch(const db::FabTest& test, db::Direction dir, const InplaneParams& params,
                                 const FabStretchOptions& options) {
  FabTestError e;
  e.test = test.name;
  std::vector<Sample> samples;
  for (const auto& s : loading_samples(test))
    if (s.x >= test.clamp_distance) samples.push_back({s.x / test.clamp_distance - 1.0, s.force});
  if (samples.empty()) {
    e.message = "no loading sample past the taut length";
    return e;
  }
  double s_max = 0.0;
  for (const auto& s : samples) s_max = std::max(s_max, s.x);
  std::vector<double> xs{0.0}, ys{0.0};
  if (s_max > 0.0) {
    std::vector<double> targets;
    for (int k = 1; k <= options.points; ++k) targets.push_back(s_max * k / options.points);
    ClampedStretchSetup setup;
    setup.length = test.clamp_distance;
    setup.width = test.strip_width;
    setup.material_angle = -db::pull_angle(dir);
    setup.target_edge = std::min(options.target_edge, 0.25 * test.clamp_distance);
    const auto run = ClampedStretchScene(setup).run(params, targets);
    e.converged = run.ok;
    e.message = run.message;
    for (const auto& s : run.samples) {
      xs.push_back(s.measured_stretch);
      ys.push_back(s.force);
    }
  }
  score(samples, xs, ys, test.zero_offset.value_or(0.0), e);
  return e;
}

namespace {

// One bend test ready to simulate: its scene, distances and loading samples.
struct BendCase {
  const db::FabTest* test = nullptr;
  LoopBendScene scene;
  std::vector<double> distances;  // ascending
  std::vector<Sample> samples;
  double width_scale = 1.0;       // the strip's width over the simulated width
  mutable std::vector<Eigen::VectorXd> warm;  // the last equilibria, per distance
};

// The model's force curve of one case at k_θ (ascending distances); false when a point failed.
bool model_curve(const BendCase& c, const InplaneParams& inplane, double ktheta, std::vector<double>& forces,
                 std::string& message) {
  ShellParams p;
  p.inplane = inplane;
  p.bending.ktheta = {ktheta, ktheta, ktheta};
  const auto run = c.scene.run(p, c.distances, &c.warm);
  forces.clear();
  for (const auto& s : run.samples) forces.push_back(s.force * c.width_scale);
  if (!run.ok) message = c.test->name + ": " + run.message;
  return run.ok;
}

// The offset that best fits the readings to the model curve: their mean difference.
double best_offset(const BendCase& c, const std::vector<double>& forces) {
  double sum = 0.0;
  for (const auto& s : c.samples) sum += s.force - interpolate(c.distances, forces, s.x);
  return c.samples.empty() ? 0.0 : sum / static_cast<double>(c.samples.size());
}

}  // namespace

FabBendFit fit_fab_bends(const std::vector<db::FabTest>& tests, db::Direction dir, const InplaneParams& inplane,
                         double areal_density, const FabBendOptions& options) {
  const auto start = numerics::Clock::now();
  FabBendFit fit;
  fit.direction = dir;
  std::vector<BendCase> cases;
  for (const auto& t : tests) {
    if (t.kind == db::FabTestKind::stretch) continue;
    const double L = t.clamp_distance;
    std::vector<Sample> samples;
    for (const auto& s : loading_samples(t))
      if (s.x > 0.3 * L && s.x < 0.999 * L) samples.push_back(s);
    if (samples.empty()) continue;
    double lo = samples.front().x, hi = lo;
    for (const auto& s : samples) {
      lo = std::min(lo, s.x);
      hi = std::max(hi, s.x);
    }
    LoopBendSetup setup;
    setup.length = L;
    setup.width = options.width_over_length * L;
    setup.material_angle = -db::pull_angle(dir);
    setup.areal_density = areal_density;
    setup.direction = t.kind == db::FabTestKind::up_bend ? LoopDirection::up : LoopDirection::down;
    BendCase c{&t, LoopBendScene(setup), {}, std::move(samples), t.strip_width / setup.width, {}};
    for (int k = 0; k < options.points; ++k) c.distances.push_back(lo + (hi - lo) * k / std::max(1, options.points - 1));
    cases.push_back(std::move(c));
  }
  if (cases.empty()) {
    fit.message = "no loop-method bend with loading samples inside the strip's length";
    return fit;
  }
  // Sum of squares of the residuals after each test's best offset; infinite when a loop fails.
  std::string failure;
  const auto objective = [&](double log_k) {
    ++fit.evaluations;
    double sse = 0.0;
    std::vector<double> forces;
    for (const auto& c : cases) {
      if (!model_curve(c, inplane, std::exp(log_k), forces, failure)) return std::numeric_limits<double>::infinity();
      const double o = best_offset(c, forces);
      for (const auto& s : c.samples) {
        const double r = s.force - o - interpolate(c.distances, forces, s.x);
        sse += r * r;
      }
    }
    return sse;
  };
  // Golden-section search in log k_θ.
  const double phi = 0.5 * (std::sqrt(5.0) - 1.0);
  double a = std::log(options.ktheta_lower), b = std::log(options.ktheta_upper);
  double x1 = b - phi * (b - a), x2 = a + phi * (b - a);
  double f1 = objective(x1), f2 = objective(x2);
  while (b - a > options.tolerance) {
    if (f1 <= f2) {
      b = x2;
      x2 = x1;
      f2 = f1;
      x1 = b - phi * (b - a);
      f1 = objective(x1);
    } else {
      a = x1;
      x1 = x2;
      f1 = f2;
      x2 = a + phi * (b - a);
      f2 = objective(x2);
    }
  }
  const double best = f1 <= f2 ? x1 : x2;
  fit.ktheta = std::exp(best);
  fit.on_bound = best - std::log(options.ktheta_lower) < 2.0 * options.tolerance ||
                 std::log(options.ktheta_upper) - best < 2.0 * options.tolerance;
  fit.converged = std::isfinite(std::min(f1, f2));
  if (!fit.converged) fit.message = "no k_θ in the search range gave every loop an equilibrium: " + failure;
  // The errors at the fit.
  double diff = 0.0, size = 0.0;
  int n = 0;
  for (const auto& c : cases) {
    FabTestError e;
    e.test = c.test->name;
    std::vector<double> forces;
    e.converged = model_curve(c, inplane, fit.ktheta, forces, e.message);
    if (!e.converged) {
      fit.tests.push_back(e);
      continue;
    }
    score(c.samples, c.distances, forces, best_offset(c, forces), e);
    diff += e.mean_abs_error * e.samples;
    for (const auto& s : c.samples) size += std::abs(s.force - e.offset);
    n += e.samples;
    fit.tests.push_back(e);
  }
  fit.force_pct = size > 0.0 ? 100.0 * diff / size : std::numeric_limits<double>::quiet_NaN();
  fit.mean_abs_error = n > 0 ? diff / n : 0.0;
  fit.seconds = numerics::seconds_since(start);
  return fit;
}

}  // namespace yarnfit::shell
