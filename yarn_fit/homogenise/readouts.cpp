#include "yarn_fit/homogenise/readouts.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

#include "numerics/optim/cobyla.hpp"
#include "numerics/roots/bracketed_root.hpp"
#include "numerics/util/clock.hpp"
#include "numerics/util/error.hpp"

namespace yarnfit::yarn {

Sample simulate_sample(YarnSystem& system, const CoarseDeformation& chi, Eigen::VectorXd& g,
                       const EquilibriumOptions& options) {
  const auto start = numerics::Clock::now();
  Sample s;
  s.chi = chi;
  system.set_deformation(chi);
  s.effects = system.effects();
  Eigen::VectorXd work = g;
  s.last_solve = solve_equilibrium(system, work, options);
  s.solves = 1;
  s.newton_iterations = s.last_solve.iterations;
  s.ok = s.last_solve.converged();
  if (s.ok) {
    g = work;
    s.energy_density = s.last_solve.energy / system.area();
    if (!chi.curved()) {
      s.coarse_stress = system.coarse_stress(g);
      s.stress_s = chi.u().dot(s.coarse_stress * chi.u());
      s.stress_c = -chi.v().dot(s.coarse_stress * chi.v());
    } else {
      s.stress_s = system.d_energy_density(g, YarnSystem::Coordinate::stretch);
      s.stress_c = system.d_energy_density(g, YarnSystem::Coordinate::compression);
    }
  } else {
    s.message = std::string("equilibrium ") + to_string(s.last_solve.status) + ": " + s.last_solve.message;
  }
  s.seconds = numerics::seconds_since(start);
  return s;
}

namespace {

struct CompressionSearch {
  YarnSystem& system;
  CoarseDeformation chi;
  Eigen::VectorXd anchor;  // start state of every evaluation
  Eigen::VectorXd g;       // state of the last converged evaluation
  Eigen::VectorXd best_g;  // state of the lowest Ψ seen
  const EquilibriumOptions& options;
  int evaluations = 0;
  int iterations = 0;
  bool failed = false;
  Sample last;
  Sample best;
  double best_psi = std::numeric_limits<double>::infinity();
  // The last two converged evaluations (c, ∂Ψ/∂c), for the slope handed to the next search.
  double c_previous = 0.0, f_previous = 0.0, c_latest = 0.0, f_latest = 0.0;
  int converged_evaluations = 0;

  [[nodiscard]] double slope() const {
    if (converged_evaluations < 2 || c_latest == c_previous) return 0.0;
    const double k = (f_latest - f_previous) / (c_latest - c_previous);
    return std::isfinite(k) && k > 0.0 ? k : 0.0;
  }

  // Every evaluation starts from the same state (the caller's warm start): knit tiles have
  // several equilibria close together, and chaining warm starts from one trial compression
  // to the next would make Ψ(c) depend on the order of the search (hysteresis).
  Sample at(double c) {
    CoarseDeformation x = chi;
    x.compression = c;
    Eigen::VectorXd trial = anchor;
    Sample s = simulate_sample(system, x, trial, options);
    ++evaluations;
    iterations += s.newton_iterations;
    if (s.ok) {
      g = trial;
      c_previous = c_latest;
      f_previous = f_latest;
      c_latest = c;
      f_latest = s.stress_c;
      ++converged_evaluations;
      if (s.energy_density < best_psi) {
        best_psi = s.energy_density;
        best = s;
        best_g = trial;
      }
    } else {
      failed = true;
    }
    last = s;
    return s;
  }
};

// The band of c around the root `at_root` (the search's last converged evaluation) in which
// |∂Ψ/∂c| ≤ co.band_stress. From the slope when it shows a band within ±flat_band; else each
// end by a root search of ∂Ψ/∂c ∓ band_stress outwards from the root (an end the search does
// not find inside [lower, upper] is that bound). A flat band moves the sample to the band's c
// of smallest |c|. `g_root` is the root's state; `g` returns the state of the sample kept.
Sample read_band(CompressionSearch& search, Sample at_root, const Eigen::VectorXd& g_root, const CompressionOptions& co,
                 Eigen::VectorXd& g) {
  const double c0 = at_root.chi.compression;
  const double tau = co.band_stress;
  g = g_root;
  const double slope = search.slope() > 0.0 ? search.slope() : co.initial_slope;
  if (slope > 0.0 && tau / slope <= co.flat_band) {
    at_root.band_lower = c0 - at_root.stress_c / slope - tau / slope;
    at_root.band_upper = c0 - at_root.stress_c / slope + tau / slope;
    return at_root;
  }
  const auto end = [&](double sign) -> std::optional<double> {
    numerics::RootFindOptions ro;
    ro.lower = sign < 0.0 ? co.lower : c0;
    ro.upper = sign < 0.0 ? c0 : co.upper;
    ro.initial_step = co.flat_band;
    ro.x_tolerance = std::max(co.tolerance, 1e-3 * co.flat_band);
    ro.max_evaluations = co.max_evaluations;
    const numerics::RootResult r = numerics::find_root(
        [&](double c) -> std::optional<double> {
          const Sample s = search.at(c);
          if (!s.ok) return std::nullopt;
          return s.stress_c - sign * tau;
        },
        std::clamp(c0 + sign * co.flat_band, co.lower, co.upper), ro);
    if (r.converged()) return r.x;
    if (r.status == numerics::RootStatus::not_bracketed) return sign < 0.0 ? co.lower : co.upper;
    return std::nullopt;  // the band's end is unknown: the root stands without a band
  };
  search.anchor = g_root;
  const std::optional<double> lower = end(-1.0), upper = end(1.0);
  if (!lower || !upper) return at_root;
  at_root.band_lower = *lower;
  at_root.band_upper = *upper;
  at_root.flat = *upper - *lower > 2.0 * co.flat_band;
  if (!at_root.flat) return at_root;
  const double c = std::clamp(0.0, *lower, *upper);
  Sample moved = search.at(c);
  if (!moved.ok) return at_root;  // the root is still a valid answer
  moved.band_lower = *lower;
  moved.band_upper = *upper;
  moved.flat = true;
  g = search.g;
  return moved;
}

}  // namespace

Sample solve_free_compression(YarnSystem& system, CoarseDeformation chi, Eigen::VectorXd& g,
                              const CompressionOptions& co, const EquilibriumOptions& options) {
  const auto start = numerics::Clock::now();
  CompressionSearch search{system, chi, g, g, g, options, 0, 0, false, Sample{}, Sample{},
                           std::numeric_limits<double>::infinity()};
  Sample result;
  if (co.method == CompressionMethod::cobyla) {
    // min Ψ(c) over [lower, upper], as in the thesis; a failed solve is a failed evaluation.
    numerics::CobylaSettings cs;
    cs.max_evaluations = co.max_evaluations;
    cs.initial_step = 0.05;
    cs.x_tolerance = co.tolerance;
    const numerics::Objective psi = [&](const Eigen::VectorXd& c) {
      const Sample s = search.at(c[0]);
      if (!s.ok) throw Error(ErrorCategory::solve, s.message);
      return s.energy_density;
    };
    const numerics::CobylaSummary r =
        numerics::run_cobyla(psi, Eigen::VectorXd::Constant(1, std::clamp(co.initial_guess, co.lower, co.upper)),
                             Eigen::VectorXd::Constant(1, co.lower), Eigen::VectorXd::Constant(1, co.upper), cs);
    result = search.best;
    result.ok = std::isfinite(search.best_psi);
    if (!result.ok) result.message = "no compression with a converged equilibrium (" + r.message + ")";
  } else {
    // Root of f(c) = ∂Ψ/∂c (increasing: Ψ is convex in c near its minimum), from the guess
    // outwards, then Illinois (numerics/roots/bracketed_root.hpp).
    numerics::RootFindOptions ro;
    ro.lower = co.lower;
    ro.upper = co.upper;
    ro.initial_step = co.initial_step;
    ro.initial_slope = co.initial_slope;
    ro.x_tolerance = co.tolerance;
    ro.f_tolerance = co.stress_tolerance;
    ro.max_evaluations = co.max_evaluations;
    const numerics::RootResult root = numerics::find_root(
        [&](double c) -> std::optional<double> {
          const Sample s = search.at(c);
          if (!s.ok) return std::nullopt;
          return s.stress_c;
        },
        co.initial_guess, ro);
    result = search.last;
    result.ok = root.converged();
    switch (root.status) {
      case numerics::RootStatus::converged: break;
      case numerics::RootStatus::evaluation_failed: result.message = "compression search: " + search.last.message; break;
      case numerics::RootStatus::not_bracketed:
        result.message = "no zero of the orthogonal stress in [" + std::to_string(co.lower) + ", " +
                         std::to_string(co.upper) + "]";
        break;
      case numerics::RootStatus::evaluation_limit:
        result.message = "compression search: evaluation limit (" + std::to_string(co.max_evaluations) +
                         " solves) before the tolerance";
        break;
    }
  }
  if (result.ok) g = co.method == CompressionMethod::cobyla ? search.best_g : search.g;
  if (result.ok && co.method == CompressionMethod::root_find && co.band_stress > 0.0) {
    const double slope = search.slope();
    const Eigen::VectorXd g_root = g;
    result = read_band(search, result, g_root, co, g);
    if (slope > 0.0) result.stress_c_slope = slope;  // the root's, not the band search's
    else result.stress_c_slope = search.slope();
  } else {
    result.stress_c_slope = search.slope();
  }
  result.solves = search.evaluations;
  result.newton_iterations = search.iterations;
  result.seconds = numerics::seconds_since(start);
  return result;
}

BendingSample simulate_bending(YarnSystem& system, const CoarseDeformation& chi, Eigen::VectorXd& g,
                               double step, const EquilibriumOptions& options, std::span<const YarnParam> wanted) {
  BendingSample out;
  const double h = step > 0.0 ? step : 1e-3 / system.tile().radius;
  CoarseDeformation plus = chi, minus = chi;
  plus.curvature += h;
  minus.curvature -= h;
  Eigen::VectorXd gc = g;
  out.centre = simulate_sample(system, chi, gc, options);
  Eigen::VectorXd gp = gc, gm = gc;
  const Sample sp = simulate_sample(system, plus, gp, options);
  Eigen::VectorXd d_plus;
  if (sp.ok && !wanted.empty()) d_plus = system.parameter_derivatives(gp, wanted).energy / system.area();
  const Sample sm = simulate_sample(system, minus, gm, options);
  if (sm.ok && sp.ok && !wanted.empty())
    out.d_stress_kappa = (d_plus - system.parameter_derivatives(gm, wanted).energy / system.area()) / (2.0 * h);
  out.ok = out.centre.ok && sp.ok && sm.ok;
  if (out.ok) {
    out.stress_kappa = (sp.energy_density - sm.energy_density) / (2.0 * h);
    g = gc;
  } else {
    out.message = !out.centre.ok ? out.centre.message : !sp.ok ? sp.message : sm.message;
  }
  out.centre.newton_iterations += sp.newton_iterations + sm.newton_iterations;
  out.centre.solves += 2;
  system.set_deformation(chi);
  return out;
}

}  // namespace yarnfit::yarn
