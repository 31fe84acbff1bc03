#include "shell_fit/fit/bending_fit.hpp"

#include <ceres/ceres.h>

#include "numerics/roots/bisection.hpp"
#include "numerics/util/clock.hpp"
#include "numerics/util/error.hpp"
#include "numerics/util/format.hpp"
#include "results/metrics/error_metrics.hpp"
#include "shell_fit/energies/lockup_curve.hpp"
#include "shell_fit/fit/ceres_support.hpp"
#include "shell_fit/fit/curve_interpolation.hpp"
#include "numerics/util/index.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <stdexcept>

namespace yarnfit::shell {

namespace {

using numerics::idx;

// Search range of the bending length relative to the free length: from a strip that hangs
// as a hairpin (ℓ = L/100) to one that gravity hardly bends (ℓ = 10 L).
constexpr double k_min_length_ratio = 1e-2;
constexpr double k_max_length_ratio = 10.0;

double areal_density_of(const db::Fabric& fabric) {
  if (!fabric.areal_density || !(*fabric.areal_density > 0.0)) {
    throw Error(ErrorCategory::input, "fabric " + fabric.id +
                                ": bending tests need areal_density_gsm (the pear loop hangs under gravity)");
  }
  return *fabric.areal_density;
}

// A strip is thin while its bending stiffness is small against its membrane stiffness E
// times L²: B ≤ 1e-4 E L², i.e. an equivalent thickness √(12 B/E) ≤ 3.5 % of L. Stiffer
// bending stretches the membrane instead of rounding the loop (r then leaves the elastica's
// range, and Newton struggles), so the search stops there.
constexpr double k_thin_shell_ratio = 1e-4;

// The membrane stiffness the thin-shell limit compares bending with: the uniaxial secant
// stiffness at a Green strain of 5 % along the weaker material axis. For eq. 6.1 it is
// min(kxx, kyy); a stiffening law's lock-up adds its share. (The small-strain K alone would
// make the limit vanish for a knit slack at rest, kyy → 0, whose pear loops are well
// posed: the synthetic records of `synth fabric` have such laws.)
constexpr double k_thin_shell_strain = 0.05;
double membrane_stiffness(const InplaneParams& p) {
  const double e = k_thin_shell_strain;
  const double weft = p.kxx + LockupCurve{p.lxx, p.bxx}.stress(e) / e;
  const double warp = p.kyy + LockupCurve{p.lyy, p.byy}.stress(e) / e;
  return std::min(weft, warp);
}

// Bending-length range of one test: [L/100, 10 L], the top capped by the thin-shell limit.
std::pair<double, double> length_bounds(const db::BendingTest& test, const InplaneParams& inplane, double rho,
                                        double g) {
  const double L = test.swatch.length;
  double hi = k_max_length_ratio * L;
  const double E = membrane_stiffness(inplane);
  if (E > 0.0) {
    const double ktheta_thin = k_thin_shell_ratio * E * L * L / bending_stiffness_per_width(1.0);
    hi = std::min(hi, bending_length(ktheta_thin, rho, g));
  }
  return {std::min(k_min_length_ratio * L, 0.5 * hi), hi};
}

BendingParams uniform(double k) {
  BendingParams p;
  p.ktheta = {k, k, k};
  return p;
}

// Fills the slots no test measures with the geometric mean of the measured ones.
void tie_unmeasured(BendingParams& p, const std::array<bool, 3>& measured) {
  double log_sum = 0.0;
  int n = 0;
  for (int j = 0; j < 3; ++j)
    if (measured[idx(j)]) {
      log_sum += std::log(p.ktheta[idx(j)]);
      ++n;
    }
  if (n == 0) return;
  for (int j = 0; j < 3; ++j)
    if (!measured[idx(j)]) p.ktheta[idx(j)] = std::exp(log_sum / n);
}

struct Guess {
  BendingParams params;
  std::array<bool, 3> measured{false, false, false};
  std::vector<std::string> fallbacks;  // BendingFitResult::fallback_starts
};

Guess guess_from_data(const db::Fabric& fabric, const InplaneParams& inplane, const BendingFitOptions& options,
                      ProgressCallback* progress = nullptr) {
  Guess out;
  const double rho = areal_density_of(fabric);
  const double g = options.gravity;
  for (const auto& [dir, test] : fabric.bending_tests) {
    // A coarser mesh than the fit's: the start needs ~10 %, not the fit's accuracy.
    const PearLoopScene scene(pear_loop_setup(test, rho, 2.0 * options.target_edge, 0, g));
    const int slot = scene.governing_ktheta();
    out.measured[idx(slot)] = true;
    const BendingDirectionFit t = make_bending_targets(test);
    const std::size_t mid = t.clamp_distance.size() / 2;
    const double d = t.clamp_distance[mid], r_target = t.measured_aspect_ratio[mid];
    const double L = test.swatch.length;
    const auto [ell_min, ell_max] = length_bounds(test, inplane, rho, g);
    if (progress) progress->set_stage("bending start (" + std::string(db::to_string(dir)) + ")", 0, "trial");
    int trial = 0;
    // r at bending length ℓ, or NaN when the loop did not reach equilibrium.
    const auto r_at = [&](double ell) {
      ShellParams p;
      p.inplane = inplane;
      p.bending = uniform(ktheta_for_bending_length(ell, rho, g));
      const PearLoopRun run = scene.run(p, {d});
      if (progress) progress->report(++trial, std::numeric_limits<double>::infinity());
      return run.ok ? run.samples[0].aspect_ratio : std::nan("");
    };
    // ℓ lies below the crossing while its loop is rounder than the data (r above r_target);
    // the last r seen on each side is kept for the interpolation below.
    double r_lo = std::nan(""), r_hi = std::nan("");
    const auto too_soft = [&](double ell) -> std::optional<bool> {
      const double r = r_at(ell);
      if (!std::isfinite(r)) return std::nullopt;
      (r > r_target ? r_lo : r_hi) = r;
      return r > r_target;
    };
    // Bracket r_target between ℓ_lo (r above it) and ℓ_hi (r below it), doubling ℓ.
    numerics::FactorBracketOptions bo;
    bo.lower = ell_min;
    bo.upper = ell_max;
    const double ell_first = std::clamp(0.25 * L, ell_min, ell_max);
    const numerics::FactorBracket bracket = numerics::bracket_by_factor(too_soft, ell_first, bo);
    // The search stopped on a trial that did not reach equilibrium, before a bracket closed:
    // the start below is then a fallback, not the data's.
    const bool search_failed = bracket.failed_at.has_value();
    double ell_start = ell_first;  // no trial reached equilibrium
    if (bracket.bracketed()) {
      // Bisection in log ℓ to a factor 2^(1/16) (13 % in k_θ), then linear in log ℓ.
      numerics::BisectionOptions so;
      so.midpoint = numerics::Midpoint::geometric;
      so.halvings = 4;
      const numerics::BisectionResult b = numerics::bisect(too_soft, *bracket.below, *bracket.above, so);
      const double frac = (r_lo - r_target) / (r_lo - r_hi);
      ell_start = std::exp(std::log(b.lower) + std::clamp(frac, 0.0, 1.0) * (std::log(b.upper) - std::log(b.lower)));
    } else if (bracket.below) {
      ell_start = ell_max;  // r stays above the data even for the stiffest strip
    } else if (bracket.above) {
      ell_start = ell_min;  // r stays below the data even for the softest strip
    }
    out.params.ktheta[idx(slot)] = ktheta_for_bending_length(ell_start, rho, g);
    if (search_failed) {
      out.fallbacks.push_back(std::string(db::to_string(dir)) + " test (" + k_bending_names[slot] +
                              "): start search failed, the pear loop did not reach equilibrium at bending length " +
                              numerics::format_number(*bracket.failed_at * 1e3, 4) + " mm; started from " +
                              numerics::format_number(ell_start * 1e3, 4) + " mm instead of the data's match");
    }
  }
  tie_unmeasured(out.params, out.measured);
  return out;
}

class LoopResiduals : public ceres::CostFunction {
 public:
  LoopResiduals(const std::vector<PearLoopScene>& scenes, std::vector<BendingDirectionFit>& data,
                std::vector<PearLoopWarmStart>& warm, const std::vector<int>& free, const std::vector<int>& held,
                const InplaneParams& inplane, int threads, int& simulations)
      : m_scenes(scenes), m_data(data), m_warm(warm), m_free(free), m_held(held), m_inplane(inplane),
        m_threads(threads), m_simulations(simulations) {
    int n = 0;
    for (const auto& d : m_data) n += static_cast<int>(d.clamp_distance.size());
    set_num_residuals(n);
    mutable_parameter_block_sizes()->push_back(static_cast<int>(m_free.size()));
  }

  // k_θ of every slot: the free ones from q = log k, the held ones at their geometric mean.
  [[nodiscard]] BendingParams params_from(const double* q) const {
    BendingParams p;
    double mean = 0.0;
    for (std::size_t i = 0; i < m_free.size(); ++i) {
      p.ktheta[idx(m_free[i])] = std::exp(q[i]);
      mean += q[i];
    }
    mean /= static_cast<double>(m_free.size());
    for (int h : m_held) p.ktheta[idx(h)] = std::exp(mean);
    return p;
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    ShellParams sp;
    sp.inplane = m_inplane;
    sp.bending = params_from(parameters[0]);
    const bool want_jacobian = jacobians && jacobians[0];
    m_runs.assign(m_data.size(), PearLoopRun{});
#pragma omp parallel for num_threads(m_threads) schedule(dynamic)
    for (int k = 0; k < static_cast<int>(m_data.size()); ++k) {
      m_runs[idx(k)] = m_scenes[idx(k)].run(sp, m_data[idx(k)].clamp_distance, want_jacobian, &m_warm[idx(k)]);
    }
    m_simulations += static_cast<int>(m_data.size());
    const int nf = static_cast<int>(m_free.size());
    int r = 0;
    for (std::size_t k = 0; k < m_data.size(); ++k) {
      if (!m_runs[k].ok) return false;  // Ceres shrinks its step and tries again
      m_effects = m_runs[k].effects;
      auto& d = m_data[k];
      d.simulated_aspect_ratio.clear();
      d.max_curvature = 0.0;
      for (std::size_t i = 0; i < d.clamp_distance.size(); ++i) {
        const PearLoopSample& s = m_runs[k].samples[i];
        d.simulated_aspect_ratio.push_back(s.aspect_ratio);
        d.max_curvature = std::max(d.max_curvature, s.max_curvature);
        residuals[r] = s.aspect_ratio - d.measured_aspect_ratio[i];
        if (want_jacobian) {
          // d/dq_j with k_j = exp(q_j), and every held k = exp(mean q) moving by k/n_free.
          double held = 0.0;
          for (int h : m_held) held += s.daspect_dktheta[h] * sp.bending.ktheta[idx(h)];
          for (int j = 0; j < nf; ++j) {
            const int slot = m_free[idx(j)];
            jacobians[0][r * nf + j] = s.daspect_dktheta[slot] * sp.bending.ktheta[idx(slot)] + held / nf;
          }
        }
        ++r;
      }
    }
    return true;
  }

  [[nodiscard]] const std::vector<PearLoopRun>& last_runs() const { return m_runs; }
  // The effects the scenes' last successful runs simulated (empty before any).
  [[nodiscard]] const std::vector<std::string>& effects() const { return m_effects; }

 private:
  const std::vector<PearLoopScene>& m_scenes;
  std::vector<BendingDirectionFit>& m_data;
  std::vector<PearLoopWarmStart>& m_warm;
  std::vector<int> m_free, m_held;
  InplaneParams m_inplane;
  int m_threads;
  int& m_simulations;
  mutable std::vector<PearLoopRun> m_runs;
  mutable std::vector<std::string> m_effects;
};

// "bending test D has no points" for the first direction without points, or empty.
std::string test_without_points(const std::vector<BendingDirectionFit>& directions) {
  for (const auto& d : directions)
    if (d.clamp_distance.empty()) return "bending test " + std::string(db::to_string(d.direction)) + " has no points";
  return {};
}

// The error progress shows: the root-mean-square aspect-ratio residual over the mean measured
// ratio [%], from the cost (half the sum of squares).
std::function<double(double)> displayed_error(const std::vector<BendingDirectionFit>& directions) {
  double r_sum = 0.0, n_res = 0.0;
  for (const auto& d : directions)
    for (double r : d.measured_aspect_ratio) {
      r_sum += std::abs(r);
      n_res += 1.0;
    }
  const double r_mean = std::max(r_sum / std::max(n_res, 1.0), 1e-12);
  return [n_res, r_mean](double c) { return 100.0 * std::sqrt(2.0 * c / std::max(n_res, 1.0)) / r_mean; };
}

// The search box in log k_θ per free slot, from the bending lengths the tests that measure it
// allow, and the start clamped into it.
void search_box(const db::Fabric& fabric, const InplaneParams& inplane, double rho, const BendingFitOptions& options,
                const std::vector<int>& free, const BendingParams& start, std::vector<double>& q,
                std::vector<double>& q_lo, std::vector<double>& q_hi) {
  for (int j : free) {
    double lo = 0.0, hi = 0.0;
    for (const auto& [dir, test] : fabric.bending_tests) {
      const auto [a, b] = length_bounds(test, inplane, rho, options.gravity);
      const double ka = ktheta_for_bending_length(a, rho, options.gravity);
      const double kb = ktheta_for_bending_length(b, rho, options.gravity);
      lo = lo == 0.0 ? ka : std::min(lo, ka);
      hi = std::max(hi, kb);
    }
    q_lo.push_back(std::log(lo));
    q_hi.push_back(std::log(hi));
    q.push_back(std::clamp(std::log(start.ktheta[idx(j)]), q_lo.back(), q_hi.back()));
  }
}

// What the result says of the held slots, the search box and the free slots that ended on it.
void report_held_and_bounds(BendingFitResult& result, const std::vector<int>& free, const std::vector<int>& held,
                            const std::vector<double>& q, const std::vector<double>& q_lo,
                            const std::vector<double>& q_hi) {
  for (int h : held) {
    result.not_identified.push_back(std::string(k_bending_names[h]) + ": no " +
                                    std::string(db::to_string(static_cast<db::Direction>(h))) +
                                    " bending test (held at the geometric mean of the fitted k_theta: " +
                                    numerics::format_number(result.params.ktheta[idx(h)], 4) + " N*m)");
  }
  for (std::size_t j = 0; j < free.size(); ++j)
    result.bounds[k_bending_names[free[j]]] = {std::exp(q_lo[j]), std::exp(q_hi[j])};
  for (std::size_t j = 0; j < free.size(); ++j) {
    if (q[j] - q_lo[j] < 1e-3 || q_hi[j] - q[j] < 1e-3) result.at_bounds.push_back(k_bending_names[free[j]]);
  }
  if (!result.at_bounds.empty()) {
    result.message += " (on a search bound: the measured aspect ratios lie outside what the model reaches"
                      " between a hanging hairpin and a weightless elastica)";
  }
}

// The errors at the solution when its final evaluation succeeded: the largest curvature per slot
// and the aspect-ratio error; otherwise no curves and the reason.
void record_errors(BendingFitResult& result, bool final_ok) {
  if (final_ok) {
    for (const auto& d : result.directions) {
      auto& m = result.max_curvature[d.parameter];
      m = std::max(m.value_or(0.0), d.max_curvature);
    }
    results::ShellErrorSum error;
    for (const auto& d : result.directions) error.add(d.measured_aspect_ratio, d.simulated_aspect_ratio);
    result.bending_pct = error.pct();
  } else {
    // The curves belong to the last point that simulated (some directions may be older still).
    for (auto& d : result.directions) d.simulated_aspect_ratio.clear();
    result.errors_reason = result.message;
  }
}

}  // namespace

BendingDirectionFit make_bending_targets(const db::BendingTest& test) {
  BendingDirectionFit t;
  t.direction = test.direction;
  const auto& c = test.curve;
  if (c.size() == 0) return t;
  double lo = std::max(k_bending_min_distance, c.clamp_distance.front());
  double hi = std::min(k_bending_max_distance, c.clamp_distance.back());
  if (!(hi >= lo)) {
    lo = c.clamp_distance.front();
    hi = c.clamp_distance.back();
  }
  const int n = hi > lo ? k_bending_targets_per_direction : 1;
  for (int i = 0; i < n; ++i) {
    const double d = n == 1 ? lo : lo + (hi - lo) * i / (n - 1);
    t.clamp_distance.push_back(d);
    t.measured_aspect_ratio.push_back(interpolate_linear(c.clamp_distance, c.aspect_ratio, d));
  }
  return t;
}

PearLoopSetup pear_loop_setup(const db::BendingTest& test, double areal_density, double target_edge,
                              int refinements, double gravity) {
  if (!(areal_density > 0.0)) throw Error(ErrorCategory::input, "pear loop: the areal density must be positive");
  PearLoopSetup s;
  s.length = test.swatch.length;
  s.width = test.swatch.width;
  // The strip runs along the test direction: the weft lies at −φ from it (as in the stretch test).
  s.material_angle = -db::pull_angle(test.direction);
  s.areal_density = areal_density;
  s.gravity = gravity;
  s.target_edge = target_edge;
  s.refinements = refinements;
  return s;
}

BendingParams initial_bending_guess(const db::Fabric& fabric, const InplaneParams& inplane,
                                    const BendingFitOptions& options) {
  return guess_from_data(fabric, inplane, options).params;
}

BendingFitResult fit_bending(const db::Fabric& fabric, const InplaneParams& inplane, const BendingFitOptions& options) {
  const auto start_time = numerics::Clock::now();
  BendingFitResult result;
  const auto finish = [&]() -> BendingFitResult& {
    result.seconds = numerics::seconds_since(start_time);
    return result;
  };
  if (fabric.bending_tests.empty()) {
    result.message = "the fabric has no bending test: k_theta not fitted";
    result.errors_reason = result.message;
    for (const char* name : k_bending_names) result.not_identified.push_back(std::string(name) + ": no bending test");
    return finish();
  }
  const double rho = areal_density_of(fabric);

  std::vector<PearLoopScene> scenes;
  std::array<bool, 3> measured{false, false, false};
  for (const auto& [dir, test] : fabric.bending_tests) {
    scenes.emplace_back(pear_loop_setup(test, rho, options.target_edge, options.refinements, options.gravity));
    BendingDirectionFit t = make_bending_targets(test);
    t.parameter = scenes.back().governing_ktheta();
    measured[idx(t.parameter)] = true;
    result.directions.push_back(std::move(t));
  }
  if (const std::string empty = test_without_points(result.directions); !empty.empty()) {
    result.message = result.errors_reason = empty;
    return finish();
  }

  ProgressCallback progress(options.progress, start_time, displayed_error(result.directions));
  quiet_solver_warnings();
  const Guess guess = guess_from_data(fabric, inplane, options, &progress);
  result.start = guess.params;
  result.fallback_starts = guess.fallbacks;
  std::vector<int> free, held;
  for (int j = 0; j < 3; ++j) (measured[idx(j)] ? free : held).push_back(j);
  for (int j : free) result.identified.push_back(k_bending_names[j]);

  std::vector<double> q, q_lo, q_hi;
  search_box(fabric, inplane, rho, options, free, result.start, q, q_lo, q_hi);

  std::vector<PearLoopWarmStart> warm(scenes.size());
  auto* cost = new LoopResiduals(scenes, result.directions, warm, free, held, inplane, std::max(1, options.threads),
                                 result.simulations);
  ceres::Problem problem;
  problem.AddResidualBlock(cost, nullptr, q.data());
  for (int j = 0; j < static_cast<int>(free.size()); ++j) {
    problem.SetParameterLowerBound(q.data(), j, q_lo[idx(j)]);
    problem.SetParameterUpperBound(q.data(), j, q_hi[idx(j)]);
  }
  // r is read to ~1e-6 (Newton tolerance, parabolic extremes): tighter tolerances only chase
  // that noise (with 1e-10 a 3-direction fit spent 7 of its 10 iterations there).
  std::string stage = "bending (";
  for (std::size_t k = 0; k < result.directions.size(); ++k)
    stage += (k ? ", " : "") + std::string(db::to_string(result.directions[k].direction));
  progress.set_stage(stage + ")", options.max_iterations);
  const ceres::Solver::Options so = least_squares_options(options.max_iterations, 1e-7, 1e-6, &progress);
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);

  // Re-evaluate at the solution so the reported curves belong to the final parameters.
  std::vector<double> res(static_cast<std::size_t>(cost->num_residuals()));
  const double* blocks[] = {q.data()};
  const bool final_ok = cost->Evaluate(blocks, res.data(), nullptr);
  result.params = cost->params_from(q.data());
  result.iterations = static_cast<int>(summary.iterations.size());
  result.converged = final_ok && summary.IsSolutionUsable() && summary.termination_type == ceres::CONVERGENCE;
  result.message = summary.BriefReport();
  if (!final_ok) {
    result.message = "final evaluation failed: a pear loop did not reach equilibrium";
    for (const auto& run : cost->last_runs())
      if (!run.ok && !run.message.empty()) result.message = "final evaluation failed: " + run.message;
  }
  report_held_and_bounds(result, free, held, q, q_lo, q_hi);
  if (final_ok) result.effects = cost->effects();
  record_errors(result, final_ok);
  return finish();
}

}  // namespace yarnfit::shell
