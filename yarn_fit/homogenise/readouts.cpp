#include "yarn_fit/homogenise/readouts.hpp"

#include <nlopt.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace yarnfit::yarn {

Sample simulate_sample(YarnSystem& system, const CoarseDeformation& chi, Eigen::VectorXd& g,
                       const EquilibriumOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  Sample s;
  s.chi = chi;
  s.effects = system.effects().names(chi);
  system.set_deformation(chi);
  Eigen::VectorXd work = g;
  s.last_solve = solve_equilibrium(system, work, options);
  s.solves = 1;
  s.newton_iterations = s.last_solve.iterations;
  s.ok = s.last_solve.converged;
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
    s.message = std::string("equilibrium ") + to_string(s.last_solve.reason) + ": " + s.last_solve.message;
  }
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
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

double cobyla_objective(unsigned n, const double* x, double* grad, void* data) {
  (void)n;
  (void)grad;
  auto* search = static_cast<CompressionSearch*>(data);
  const Sample s = search->at(x[0]);
  return s.ok ? s.energy_density : std::numeric_limits<double>::max();
}

}  // namespace

Sample solve_free_compression(YarnSystem& system, CoarseDeformation chi, Eigen::VectorXd& g,
                              const CompressionOptions& co, const EquilibriumOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  CompressionSearch search{system, chi, g, g, g, options, 0, 0, false, Sample{}, Sample{},
                           std::numeric_limits<double>::infinity()};
  Sample result;
  if (co.method == CompressionMethod::cobyla) {
    nlopt::opt opt(nlopt::LN_COBYLA, 1);
    opt.set_lower_bounds(std::vector<double>{co.lower});
    opt.set_upper_bounds(std::vector<double>{co.upper});
    opt.set_min_objective(cobyla_objective, &search);
    opt.set_xtol_abs(co.tolerance);
    opt.set_maxeval(co.max_evaluations);
    opt.set_initial_step(0.05);
    std::vector<double> x{std::clamp(co.initial_guess, co.lower, co.upper)};
    double fmin = 0.0;
    try {
      opt.optimize(x, fmin);
    } catch (const std::exception&) {
      // fall through: the best point seen is kept below
    }
    result = search.best;
    result.ok = std::isfinite(search.best_psi);
    if (!result.ok) result.message = "no compression with a converged equilibrium";
  } else {
    // Root of f(c) = ∂Ψ/∂c: bracket from the initial guess outwards, then Illinois
    // (regula falsi with halving), which keeps the bracket and converges superlinearly.
    double a = std::clamp(co.initial_guess, co.lower, co.upper);
    Sample sa = search.at(a);
    if (!sa.ok) {
      result = sa;
      result.message = "compression search: " + sa.message;
    } else if (std::abs(sa.stress_c) <= co.stress_tolerance) {
      result = sa;  // already free of orthogonal stress within the tolerance
    } else {
      double fa = sa.stress_c;
      double step = co.initial_step * (fa < 0.0 ? 1.0 : -1.0);  // Ψ decreases towards larger c when f < 0
      double b = a;
      double fb = fa;
      Sample sb = sa;
      bool bracketed = false;
      while (search.evaluations < co.max_evaluations) {
        // After two evaluations on one side, aim the next one past the secant's root
        // (by 10 % of the way, so that it brackets) instead of doubling blindly: warm curve
        // points start close to c*, where the secant is accurate.
        if (b != a && fb != fa) {
          const double to_root = -fb * (b - a) / (fb - fa);
          if (to_root * step > 0.0) step = std::clamp(1.1 * to_root, 0.25 * step, 4.0 * step);
        }
        const double next = std::clamp(b + step, co.lower, co.upper);
        if (next == b) break;
        a = b;
        fa = fb;
        sa = sb;
        b = next;
        sb = search.at(b);
        if (!sb.ok) break;
        fb = sb.stress_c;
        if ((fa < 0.0) != (fb < 0.0) || std::abs(fb) <= co.stress_tolerance) {
          bracketed = true;
          break;
        }
        step *= 2.0;
      }
      if (!bracketed) {
        result = search.failed ? search.last : sb;
        result.ok = false;
        result.message = search.failed ? "compression search: " + search.last.message
                                       : "no zero of the orthogonal stress in [" + std::to_string(co.lower) +
                                             ", " + std::to_string(co.upper) + "]";
      } else {
        int side = 0;
        Sample sc = sb;
        double previous = b;
        while (search.evaluations < co.max_evaluations && std::abs(b - a) > co.tolerance &&
               std::abs(sc.stress_c) > co.stress_tolerance) {
          const double c = (a * fb - b * fa) / (fb - fa);
          // Regula falsi keeps one end of the bracket: stop once the iterate itself settles.
          if (std::abs(c - previous) <= 0.1 * co.tolerance) break;
          previous = c;
          sc = search.at(c);
          if (!sc.ok) break;
          const double fc = sc.stress_c;
          if ((fc < 0.0) == (fb < 0.0)) {
            b = c;
            fb = fc;
            if (side == -1) fa *= 0.5;
            side = -1;
          } else {
            a = c;
            fa = fc;
            if (side == 1) fb *= 0.5;
            side = 1;
          }
          if (fc == 0.0) break;
        }
        result = sc;
        if (!sc.ok) result.message = "compression search: " + sc.message;
        else if (std::abs(b - a) > co.tolerance && std::abs(sc.stress_c) > co.stress_tolerance &&
                 search.evaluations >= co.max_evaluations) {
          result.ok = false;
          result.message = "compression search: evaluation limit before the tolerance";
        }
      }
    }
  }
  if (result.ok) g = co.method == CompressionMethod::cobyla ? search.best_g : search.g;
  result.solves = search.evaluations;
  result.newton_iterations = search.iterations;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

BendingSample simulate_bending(YarnSystem& system, const CoarseDeformation& chi, Eigen::VectorXd& g,
                               double step, const EquilibriumOptions& options) {
  BendingSample out;
  const double h = step > 0.0 ? step : 1e-3 / system.tile().radius;
  CoarseDeformation plus = chi, minus = chi;
  plus.curvature += h;
  minus.curvature -= h;
  Eigen::VectorXd gc = g;
  out.centre = simulate_sample(system, chi, gc, options);
  Eigen::VectorXd gp = gc, gm = gc;
  const Sample sp = simulate_sample(system, plus, gp, options);
  const Sample sm = simulate_sample(system, minus, gm, options);
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
