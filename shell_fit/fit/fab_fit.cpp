#include "shell_fit/fit/fab_fit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "numerics/optim/brent_minimize.hpp"
#include "numerics/util/clock.hpp"
#include "shell_fit/fit/curve_interpolation.hpp"
#include "shell_fit/scenes/clamped_stretch.hpp"
#include "shell_fit/scenes/loop_bend.hpp"

namespace yarnfit::shell {

namespace {

// How far in log k_θ a loop's equilibria seed the next evaluation's (a third of e).
constexpr double k_warm_reach = 0.3;

struct Sample {
  double x = 0.0;  // stretch, or clamp distance [m]
  double force = 0.0;
};

// The loading samples of the cycles up to `last_cycle` (0: every cycle).
std::vector<Sample> loading_samples(const db::FabTest& test, int last_cycle = 0) {
  std::vector<Sample> out;
  for (const auto& b : test.branches)
    if (b.branch == db::FabBranch::loading && (last_cycle == 0 || b.cycle <= last_cycle))
      for (std::size_t i = 0; i < b.clamp_distance.size(); ++i) out.push_back({b.clamp_distance[i], b.raw_force[i]});
  return out;
}

// Σ|model − measured| / Σ|measured| and the mean |model − measured| of (x, force) samples
// against the model curve through (xs, ys), `offset` taken off the readings. The model is
// simulated at a few points and read between them by monotone cubics.
void score(const std::vector<Sample>& samples, const std::vector<double>& xs, const std::vector<double>& ys,
           double offset, FabTestError& e) {
  double diff = 0.0, size = 0.0;
  for (const auto& s : samples) {
    const double measured = s.force - offset;
    diff += std::abs(interpolate_monotone_cubic(xs, ys, s.x) - measured);
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
    e.force_pct = e.first_cycles_force_pct = e.mean_abs_error = std::numeric_limits<double>::quiet_NaN();
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
  // Over the range of the first two cycles.
  double s_first = 0.0;
  for (const auto& s : loading_samples(test, 2)) s_first = std::max(s_first, s.x / test.clamp_distance - 1.0);
  std::vector<Sample> first;
  for (const auto& s : samples)
    if (s.x <= s_first) first.push_back(s);
  FabTestError within = e;
  score(first, xs, ys, e.offset, within);
  e.first_cycles_force_pct = within.force_pct;
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
  mutable double warm_log_k = std::numeric_limits<double>::quiet_NaN();  // their log k_θ
  mutable double max_curvature = 0.0;         // of the last run
  mutable std::vector<std::string> effects;   // what the scene simulated
};

// The model's force curve of one case at k_θ (ascending distances); false when a point failed.
bool model_curve(const BendCase& c, const InplaneParams& inplane, double ktheta, std::vector<double>& forces,
                 std::string& message) {
  ShellParams p;
  p.inplane = inplane;
  p.bending.ktheta = {ktheta, ktheta, ktheta};
  // A loop has more than one equilibrium at a clamp distance. Started from the buckling mode
  // it takes the one the rig's strip takes; warm-started from a loop of a very different k_θ
  // it may stay on another. So the last equilibria seed only a nearby k_θ.
  const double log_k = std::log(ktheta);
  if (!(std::abs(log_k - c.warm_log_k) <= k_warm_reach)) c.warm.clear();
  const auto run = c.scene.run(p, c.distances, &c.warm);
  c.warm_log_k = log_k;
  forces.clear();
  for (const auto& s : run.samples) forces.push_back(s.force * c.width_scale);
  c.effects = run.effects;
  c.max_curvature = 0.0;
  for (const auto& s : run.samples) c.max_curvature = std::max(c.max_curvature, s.max_curvature);
  if (!run.ok) message = c.test->name + ": " + run.message;
  return run.ok;
}

// The offset that best fits the readings to the model curve: their mean difference.
double best_offset(const BendCase& c, const std::vector<double>& forces) {
  double sum = 0.0;
  for (const auto& s : c.samples) sum += s.force - interpolate_monotone_cubic(c.distances, forces, s.x);
  return c.samples.empty() ? 0.0 : sum / static_cast<double>(c.samples.size());
}

// The case of bend test `t`, or none when it has no loading sample inside the strip's length.
std::optional<BendCase> bend_case(const db::FabTest& t, db::Direction dir, double areal_density,
                                  const FabBendOptions& options) {
  const double L = t.clamp_distance;
  std::vector<Sample> samples;
  for (const auto& s : loading_samples(t))
    if (s.x > 0.3 * L && s.x < 0.999 * L) samples.push_back(s);
  if (samples.empty()) return std::nullopt;
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
  BendCase c{&t, LoopBendScene(setup), {}, std::move(samples), t.strip_width / setup.width, {}, std::numeric_limits<double>::quiet_NaN(), 0.0, {}};
  // Uniform in √(L − d): close together where the strip straightens and its force turns
  // sharply (a limp strip's tension grows as 1/√(L − d)), far apart in the deep loop.
  const double u_lo = std::sqrt(L - hi), u_hi = std::sqrt(L - lo);
  for (int k = options.points - 1; k >= 0; --k) {
    const double u = u_lo + (u_hi - u_lo) * k / std::max(1, options.points - 1);
    c.distances.push_back(L - u * u);
  }
  return c;
}

// The case's error at k_θ, its offset the best one.
FabTestError bend_error(const BendCase& c, const InplaneParams& inplane, double ktheta) {
  FabTestError e;
  e.test = c.test->name;
  std::vector<double> forces;
  e.converged = model_curve(c, inplane, ktheta, forces, e.message);
  e.first_cycles_force_pct = std::numeric_limits<double>::quiet_NaN();
  if (e.converged) score(c.samples, c.distances, forces, best_offset(c, forces), e);
  else e.force_pct = e.mean_abs_error = e.offset = std::numeric_limits<double>::quiet_NaN();
  e.max_curvature = c.max_curvature;
  return e;
}

// Each test's errors at the fit's k_θ, and the force error over every test whose loops settled.
void record_errors_at_fit(FabBendFit& fit, const std::vector<BendCase>& cases, const InplaneParams& inplane) {
  double diff = 0.0, size = 0.0;
  int n = 0;
  for (const auto& c : cases) {
    const FabTestError e = bend_error(c, inplane, fit.ktheta);
    fit.tests.push_back(e);
    fit.effects = c.effects;
    if (!e.converged) continue;
    diff += e.mean_abs_error * e.samples;
    for (const auto& s : c.samples) size += std::abs(s.force - e.offset);
    n += e.samples;
  }
  fit.force_pct = size > 0.0 ? 100.0 * diff / size : std::numeric_limits<double>::quiet_NaN();
  fit.mean_abs_error = n > 0 ? diff / n : 0.0;
}

}  // namespace

FabTestError predict_fab_bend(const db::FabTest& test, db::Direction dir, const ShellParams& params,
                              double areal_density, const FabBendOptions& options) {
  const auto c = bend_case(test, dir, areal_density, options);
  if (!c) {
    FabTestError e;
    e.test = test.name;
    e.force_pct = e.first_cycles_force_pct = e.mean_abs_error = e.offset = std::numeric_limits<double>::quiet_NaN();
    e.message = "no loading sample inside the strip's length";
    return e;
  }
  return bend_error(*c, params.inplane, params.bending.ktheta[static_cast<std::size_t>(dir)]);
}

FabBendFit fit_fab_bends(const std::vector<const db::FabTest*>& tests, db::Direction dir, const InplaneParams& inplane,
                         double areal_density, const FabBendOptions& options) {
  const auto start = numerics::Clock::now();
  FabBendFit fit;
  fit.direction = dir;
  std::vector<BendCase> cases;
  for (const auto* t : tests)
    if (t->kind != db::FabTestKind::stretch)
      if (auto c = bend_case(*t, dir, areal_density, options)) cases.push_back(std::move(*c));
  if (cases.empty()) {
    fit.message = "no loop-method bend with loading samples inside the strip's length";
    return fit;
  }
  // The sum of squares of every sample's residual after its test's best offset, in newtons: one
  // load cell of one noise for every test, so every sample weighs alike. Infinite when a loop
  // fails.
  std::string failure;
  const auto objective = [&](double log_k) {
    double sse = 0.0;
    std::vector<double> forces;
    for (const auto& c : cases) {
      if (!model_curve(c, inplane, std::exp(log_k), forces, failure)) return std::numeric_limits<double>::infinity();
      const double o = best_offset(c, forces);
      for (const auto& s : c.samples) {
        const double r = s.force - o - interpolate_monotone_cubic(c.distances, forces, s.x);
        sse += r * r;
      }
    }
    return sse;
  };
  // The misfit need not have one minimum over six decades: a limp strip whose loops are all
  // gravity can fit the deep loops' level about as well as the right k_θ. So a scan over the
  // decades first, then Brent's method between the best point's neighbours.
  const double lower = std::log(options.ktheta_lower), upper = std::log(options.ktheta_upper);
  const int scan = std::max(3, options.scan_points);
  std::vector<double> grid(static_cast<std::size_t>(scan)), misfit(grid.size());
  for (std::size_t i = 0; i < grid.size(); ++i) {
    grid[i] = lower + (upper - lower) * static_cast<double>(i) / (scan - 1);
    misfit[i] = objective(grid[i]);
  }
  const auto at = static_cast<std::size_t>(std::min_element(misfit.begin(), misfit.end()) - misfit.begin());
  const double from = grid[at == 0 ? 0 : at - 1], to = grid[std::min(at + 1, grid.size() - 1)];
  const auto best =
      numerics::brent_minimize(objective, from, to, options.tolerance, std::max(1, options.max_evaluations - scan));
  fit.evaluations = best.evaluations + scan;
  // Brent's method never evaluates the scan's best point itself; keep it when it stays best.
  const bool scan_best = misfit[at] < best.value;
  const double best_x = scan_best ? grid[at] : best.x, best_value = scan_best ? misfit[at] : best.value;
  // How well the bends pin k_θ: where the misfit doubles on either side of the best, from the
  // scan's points beyond it, halved three times in log k_θ. With every zero free, a strip's
  // loops may fit about as well over a decade or more: a stiffer strip's level taken up by its
  // offsets.
  const double doubled = 2.0 * best_value;
  const auto edge = [&](int step) {
    auto k = static_cast<std::ptrdiff_t>(at);
    const auto n = static_cast<std::ptrdiff_t>(grid.size());
    while (k + step >= 0 && k + step < n && misfit[static_cast<std::size_t>(k + step)] <= doubled) k += step;
    if (k + step < 0 || k + step >= n) return grid[static_cast<std::size_t>(k)];  // still under at the bound
    double inside = k == static_cast<std::ptrdiff_t>(at) ? best_x : grid[static_cast<std::size_t>(k)];
    double outside = grid[static_cast<std::size_t>(k + step)];
    for (int halving = 0; halving < 3; ++halving) {
      const double mid = 0.5 * (inside + outside);
      (objective(mid) <= doubled ? inside : outside) = mid;
      ++fit.evaluations;
    }
    return outside;
  };
  fit.ktheta_low = std::exp(edge(-1));
  fit.ktheta_high = std::exp(edge(+1));
  fit.ktheta = std::exp(best_x);
  fit.on_bound = best_x - lower < 2.0 * options.tolerance || upper - best_x < 2.0 * options.tolerance;
  fit.converged = best.converged && std::isfinite(best_value);
  if (!std::isfinite(best_value)) fit.message = "no k_θ in the search range gave every loop an equilibrium: " + failure;
  else if (scan_best) fit.message = "the local search ended above the scan's best point: k_θ is that point, to a scan step";
  else if (!fit.converged) fit.message = "k_θ not settled within " + std::to_string(options.max_evaluations) + " evaluations";
  record_errors_at_fit(fit, cases, inplane);
  fit.seconds = numerics::seconds_since(start);
  return fit;
}

}  // namespace yarnfit::shell
