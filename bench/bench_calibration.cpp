// Yarn-level calibration studies (issue 5, acceptance 2, 3 and 5), printed, not asserted:
//   profile    the local step's objective at the true parameters and with each one 10 % off
//   cost       where one evaluation of the local step's objective spends its time
//   line       g along the line from 10 % off the truth to the truth, own and held rest state
//   goals      the default fit of each --cases tile:truth (truth KS1/EPS_S[/KC1] for --truth's KS1,EPS_S[,KC1])
//   recovery   the profile, then targets simulated from known parameters on a tile of ../shared
//              (stockinette unless --tile says another),
//              fitted back: true vs fitted parameters, errors, time per stage
//   ablations  the same targets fitted without the swarm, with linear stretch (ks1 = ks2,
//              ε̄s = 0) and without the rest-shape heuristic (thesis Fig. 6.11, 6.16, 6.17),
//              and with the other local step (COBYLA, the thesis's, or implicit filtering)
//   settings   error, recovered parameters and time for particles × iterations × samples
//              settings: three cheaper rows, then the default
// Usage: bench_calibration MODE [--particles N] [--iterations N] [--samples N]
//                               [--local-evaluations N] [--local-method implicit-filtering|cobyla]
//                               [--threads T] [--shared DIR]
//                               [--settings K]   (settings mode: the first K rows of its table)
//                               [--first-setting K]   (settings mode: start at row K, from 1)
//                               [--truth toe|plated|KS1,EPS_S[,KC1]]   (the known parameters:
//                               see make_problem; KS1 in ks2, KC1 in kc_base, e.g. 0.2,0.004)
//                               [--max-stretch S]   (targets over 0..S, 1 % apart; default 0.3)
//                               [--tile NAME|PATH]   (../shared/data/patterns/NAME.pyp, or a .pyp file;
//                                                   default stockinette)
#include <algorithm>
#include <random>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "yarn_fit/fit/budget.hpp"
#include "yarn_fit/fit/yarn_fit.hpp"
#include "yarn_fit/fit/objective/jacobian_check.hpp"
#include "yarn_fit/fit/synth/synthetic_yarn_fabric.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"
#include "numerics/util/clock.hpp"
#include "numerics/util/format.hpp"

namespace {

using namespace yarnfit;

struct Problem {
  db::PeriodicTile tile;
  yarn::ParameterScales scales;
  yarn::YarnParams truth;
  std::vector<db::DirectionTargets> targets;
};

// Known parameters inside the bounds, away from the defaults the swarm is centred on, in one
// of two regimes of the biphasic stretch (thesis 6.4.2):
//  * toe (default): a stiff soft phase ks1 = 0.05 ks2 up to ε̄s = 0.5 %. The yarns strain by
//    about 0.6 % at 30 % fabric stretch (0.5 % at 25 %; mean over the edges, the tile held at
//    its width, c = 0), so the stiff phase engages near the
//    end of the comfort range, and below that bending and contact carry the fabric. An onset
//    above the yarns' strains leaves ε̄s unidentified (at ε̄s = 6 %, the first choice here,
//    the fit moved it by +63 % with g unchanged).
//  * plated: a softer phase ks1 = 0.01 ks2 (a plated, elastane-like yarn) up to ε̄s = 1 %,
//    reached at about 20–25 % stretch in every direction (c = 0). Softer still (0.005 ks2) the tile
//    is slack across at rest and the synthetic bias targets fail at s = 0 (the compression
//    search creeps along a mechanism).
// The profile printed by `recovery` and `profile` shows how well the data pin each parameter.
// Other truths, by `profile` (g with one parameter ×0.9 / ×1.1 over g at the truth):
//  * a stiffer soft phase carrying the load, 0.2,0.004 and 0.3,0.003: ks1 1 / 1×, ε̄s 1 / 1×
//    (the yarns' stretch is in series with the far softer loops: its stiffness hardly shows);
//  * stiffer contact, 0.02,0.005,20: ks1 1 / 1×, ε̄s 1 / 1×, kc1 2 / 2×;
//  * the toe truth stretched to 50 %: ks1 2 / 3×, ε̄s 3 / 4×, kb 65 / 48×, kc1 63 / 46×.
// R1 stays at 400–19000× in all of them.
// 31 target points (1 % apart) keep the linear interpolation of the targets between
// samples well below the fit's errors.
Problem make_problem(const std::string& shared, const std::string& tile_name, const std::string& truth,
                     double max_stretch) {
  db::Problems problems;
  // A name of ../shared/data/patterns, or a path to a .pyp (e.g. from yarnfit tile make).
  const bool is_path = tile_name.find('/') != std::string::npos || tile_name.ends_with(".pyp");
  const auto tile = db::read_pyp(is_path ? tile_name : shared + "/data/patterns/" + tile_name + ".pyp", problems);
  if (!tile) throw std::runtime_error(problems.to_string());
  Problem p;
  p.tile = *tile;
  p.scales = {400.0, db::compute_tile_facts(*tile).r_est};
  p.truth = yarn::default_params(p.scales);
  double kc1_in_base = 2.0;
  if (truth == "plated") {
    p.truth.ks1 = 0.01 * p.scales.ks2;
    p.truth.eps_s = 0.01;
  } else if (truth == "toe") {
    p.truth.ks1 = 0.05 * p.scales.ks2;
    p.truth.eps_s = 0.005;
  } else {
    double ks1_fraction = 0, eps_s = 0, kc1_factor = 2.0;
    char tail = 0;
    const int read = std::sscanf(truth.c_str(), "%lf,%lf,%lf%c", &ks1_fraction, &eps_s, &kc1_factor, &tail);
    if ((read != 2 && read != 3) || !(ks1_fraction > 0) || !(eps_s >= 0) || !(kc1_factor > 0))
      throw std::invalid_argument("--truth: expected toe, plated or KS1,EPS_S[,KC1] (ks1 as a fraction of ks2 > 0, "
                                  "eps_s >= 0, kc1 in kc_base > 0, default 2), got " + truth);
    p.truth.ks1 = ks1_fraction * p.scales.ks2;
    p.truth.eps_s = eps_s;
    kc1_in_base = kc1_factor;
  }
  p.truth.kb = 0.2 * p.scales.kb_base();
  p.truth.r1 = 0.9 * p.scales.r_est;
  p.truth.kc1 = kc1_in_base * p.scales.kc_base();
  yarn::SyntheticYarnOptions so;
  so.max_stretch = max_stretch;
  so.points = static_cast<int>(std::lround(max_stretch / 0.01)) + 1;
  const auto synth = yarn::simulate_yarn_targets(p.tile, p.truth, so);
  p.targets = synth.targets;
  std::printf("targets: %s, %s truth (ks1 %.4g ks2, eps_s %.4g, kc1 %.4g kc_base), weft/bias/warp 0-%.0f %%, "
              "%d points each, simulated in %.1f s\n",
              tile_name.c_str(), truth.c_str(), p.truth.ks1 / p.scales.ks2, p.truth.eps_s, kc1_in_base,
              100.0 * max_stretch, so.points, synth.seconds);
  return p;
}

void print_fit(const char* label, const Problem& p, const yarn::YarnFitResult& r, bool compare) {
  const auto& e = r.final;
  double comfort = 0, full = 0, comp = 0;
  for (const auto& d : e.directions) {
    comfort += d.stress_comfort_pct;
    full += d.stress_full_pct;
    comp += d.compression_pct;
  }
  const double nd = e.directions.empty() ? 1.0 : static_cast<double>(e.directions.size());
  std::printf("%-22s %s  stress comfort %6.2f %%  full %6.2f %%  compression %6.2f %%  g %.4g  "
              "%d evaluations (%d failed, %d stopped at the cutoff)  swarm %.0f s  local %.0f s  total %.0f s\n",
              label, r.ok ? "ok    " : "FAILED", comfort / nd, full / nd, comp / nd, e.value, r.evaluations,
              r.swarm.failed + r.local.failed, r.swarm_stopped,
              r.seconds_swarm, r.seconds_local, r.seconds_total);
  for (const auto& d : e.directions)
    std::printf("    %-5s comfort %6.2f %%  full %6.2f %%  compression %6.2f %%\n",
                std::string(db::to_string(d.scale.direction)).c_str(), d.stress_comfort_pct, d.stress_full_pct,
                d.compression_pct);
  if (!r.swarm.history.empty()) std::printf("    swarm: %s\n", r.swarm.brief_report().c_str());
  if (r.local.ran) std::printf("    local: %s\n", r.local.report.c_str());
  for (const auto& round : r.local.alternation.rounds)
    std::printf("      round %d: g %.4g -> %.4g held, %.4g on its own rest state (%s), move %.3g, %d iterations, %d "
                "evaluations, %.0f s (%s)%s\n",
                round.round, round.g_start, round.g_end, round.g_true, round.accepted ? "accepted" : "rejected",
                round.move, round.iterations, round.evaluations, round.seconds, round.termination.c_str(),
                round.rest_derivative_measured ? "; rest state's derivative measured" : "");
  if (!r.on_bound.empty()) {
    std::printf("    on a bound:");
    for (const auto& n : r.on_bound) std::printf(" %s", n.c_str());
    std::printf("\n");
  }
  if (!compare) return;
  const auto row = [](const char* name, double fitted, double truth) {
    std::printf("    %-6s fitted %-12.5g true %-12.5g %+7.1f %%\n", name, fitted, truth, 100.0 * (fitted / truth - 1.0));
  };
  row("ks1", r.params.ks1, p.truth.ks1);
  row("eps_s", r.params.eps_s, p.truth.eps_s);
  row("kb", r.params.kb, p.truth.kb);
  row("R1", r.params.r1, p.truth.r1);
  row("kc1", r.params.kc1, p.truth.kc1);
  if (!r.profile.computed) return;
  // What the fit itself reports about each parameter (parameter_profile.hpp): how far the
  // truth lies from the fit against the range the targets leave open.
  std::printf("    identifiability at the fit (g %.4g): g at /%.2f and x%.2f; range (x/÷) before g doubles, others "
              "re-fitted / held\n",
              r.profile.g_fit, 1.0 + r.profile.step, 1.0 + r.profile.step);
  // A side whose simulation failed has g = inf and leaves that parameter's range unknown
  // (nan); an infinite range means the residuals do not pin the parameter at all.
  const auto number = [](double v, const char* if_infinite) {
    if (std::isnan(v)) return std::string("-");
    if (std::isinf(v)) return std::string(if_infinite);
    return numerics::format_number(v, 4);
  };
  for (const auto& entry : r.profile.entries)
    std::printf("    %-6s g %s / %s   range %s / %s\n", entry.name.c_str(), number(entry.g_lower, "failed").c_str(),
                number(entry.g_upper, "failed").c_str(), number(entry.range_factor, "unbounded").c_str(),
                number(entry.range_alone_factor, "unbounded").c_str());
  if (!r.profile.message.empty()) std::printf("    incomplete: %s\n", r.profile.message.c_str());
}

// The goals of issue 17 for a recovery run: the whole fit's time, and the accuracy that the
// speed work must keep (ks1, ε̄s, kb, kc1 within 10 %, R1 within 1 % of the truth, the mean
// comfort-range stress error ≤ 0.5 %).
// One recovery's figures against issue 33's bar: ks1, ε̄s, kb, kc1 within 5 %, R1 within 1 %,
// comfort-range stress error ≤ 0.5 % (and issue 49's for woven tiles: 10 %, 2 %, 1 %); and the
// time against 300 s (moonshot 120 s).
struct RecoveryRow {
  std::string label;
  bool ok = false;
  double ks1 = 0, eps_s = 0, kb = 0, r1 = 0, kc1 = 0;  // relative errors
  double comfort = 0, g = 0, seconds = 0;
  [[nodiscard]] double worst() const { return std::max({std::abs(ks1), std::abs(eps_s), std::abs(kb), std::abs(kc1)}); }
  [[nodiscard]] bool met() const { return ok && worst() <= 0.05 && std::abs(r1) <= 0.01 && comfort <= 0.5; }
  // Issue 49's bar for woven tiles: 10 %, R1 2 %, comfort ≤ 1 %.
  [[nodiscard]] bool met_woven() const { return ok && worst() <= 0.10 && std::abs(r1) <= 0.02 && comfort <= 1.0; }
};

RecoveryRow recovery_row(const std::string& label, const Problem& p, const yarn::YarnFitResult& r) {
  RecoveryRow row;
  row.label = label;
  row.ok = r.ok;
  const auto off = [](double fitted, double truth) { return fitted / truth - 1.0; };
  row.ks1 = off(r.params.ks1, p.truth.ks1);
  row.eps_s = off(r.params.eps_s, p.truth.eps_s);
  row.kb = off(r.params.kb, p.truth.kb);
  row.r1 = off(r.params.r1, p.truth.r1);
  row.kc1 = off(r.params.kc1, p.truth.kc1);
  for (const auto& d : r.final.directions) row.comfort += d.stress_comfort_pct;
  row.comfort /= static_cast<double>(std::max<std::size_t>(r.final.directions.size(), 1));
  row.g = r.final.value;
  row.seconds = r.seconds_total;
  return row;
}

void print_goal_table(const std::vector<RecoveryRow>& rows, int threads) {
  std::printf("\ngoal table: issue 33's bar (ks1, eps_s, kb, kc1 within 5 %%, R1 within 1 %%, comfort <= 0.5 %%) and "
              "issue 49's (10 %%, 2 %%, 1 %%); time <= 300 s (moonshot 120 s), %d thread(s)\n",
              threads);
  std::printf("| case | ks1 | eps_s | kb | R1 | kc1 | comfort | g | time | bar 33 | bar 49 |\n"
              "|---|---|---|---|---|---|---|---|---|---|---|\n");
  int met = 0, met_woven = 0, fast = 0;
  for (const auto& r : rows) {
    std::printf("| %s | %+.1f %% | %+.1f %% | %+.1f %% | %+.2f %% | %+.1f %% | %.2f %% | %.3g | %.0f s | %s | %s |\n",
                r.label.c_str(), 100 * r.ks1, 100 * r.eps_s, 100 * r.kb, 100 * r.r1, 100 * r.kc1, r.comfort, r.g,
                r.seconds, r.met() ? "met" : "MISSED", r.met_woven() ? "met" : "MISSED");
    met += r.met() ? 1 : 0;
    met_woven += r.met_woven() ? 1 : 0;
    fast += r.seconds <= 300.0 ? 1 : 0;
  }
  std::printf("recovered %d of %zu (issue 33's bar), %d of %zu (issue 49's); %d of %zu within 300 s\n", met, rows.size(),
              met_woven, rows.size(), fast, rows.size());
}

void print_recovery_goals(const Problem& p, const yarn::YarnFitResult& r, int threads) {
  std::printf("goals (issue 17):\n");
  std::printf("  whole yarn fit %.0f s on %d thread(s)   goal <= 300 s   %s (moonshot <= 120 s: %s)\n", r.seconds_total,
              threads, r.seconds_total <= 300.0 ? "met" : "MISSED", r.seconds_total <= 120.0 ? "met" : "missed");
  const auto off = [](double fitted, double truth) { return std::abs(fitted / truth - 1.0); };
  const double worst10 = std::max({off(r.params.ks1, p.truth.ks1), off(r.params.eps_s, p.truth.eps_s),
                                   off(r.params.kb, p.truth.kb), off(r.params.kc1, p.truth.kc1)});
  const double r1 = off(r.params.r1, p.truth.r1);
  double comfort = 0.0;
  for (const auto& d : r.final.directions) comfort += d.stress_comfort_pct;
  comfort /= std::max<std::size_t>(r.final.directions.size(), 1);
  std::printf("  ks1, eps_s, kb, kc1 worst %.1f %% off (<= 10 %%), R1 %.2f %% off (<= 1 %%), stress comfort %.2f %% "
              "(<= 0.5 %%)   %s\n",
              100.0 * worst10, 100.0 * r1, comfort,
              r.ok && worst10 <= 0.1 && r1 <= 0.01 && comfort <= 0.5 ? "met" : "MISSED");
}

yarn::YarnFitResult run(const Problem& p, yarn::YarnFitSettings s) {
  s.progress = [](const numerics::Progress& e) {
    std::fprintf(stderr, "\r  %s %d/%d  best %.4g  %.0f s      ", e.stage.c_str(), e.step, e.steps, e.best, e.seconds);
  };
  const auto r = yarn::fit_yarn_params(yarn::make_yarn_tile(p.tile), p.targets, p.scales, s);
  std::fprintf(stderr, "\n");
  return r;
}

// What a swarm candidate costs: `count` points of a Latin-hypercube-like spread over the box
// (the contact stage's: R1 and kc1 random, the rest at the middle; then all five random),
// each evaluated serially on `samples` samples: the rest state's share, the sweeps', Newton
// iterations and solves.
void print_candidate_costs(const Problem& p, const yarn::YarnFitSettings& base, int count) {
  const swarm::ParameterSpace space = yarn::yarn_parameter_space(p.scales, false);
  yarn::ObjectiveOptions o = base.objective;
  o.samples = base.swarm_samples;
  const yarn::YarnObjective objective(yarn::make_yarn_tile(p.tile), p.targets, o);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const bool contact_only : {true, false}) {
    double rest = 0.0, total = 0.0;
    long iterations = 0, rest_iterations = 0, solves = 0;
    int failed = 0;
    for (int k = 0; k < count; ++k) {
      Eigen::VectorXd u = Eigen::VectorXd::Constant(space.dimension(), 0.5);
      for (int i = 0; i < space.dimension(); ++i)
        if (!contact_only || i >= 3) u[i] = (k + unit(rng)) / count;
      const yarn::YarnParams q = yarn::params_from_point(space.from_unit(u), p.scales, false);
      const auto r = objective.evaluate(q);
      total += r.seconds;
      rest += r.rest.seconds;
      iterations += r.newton_iterations;
      rest_iterations += r.rest.newton_iterations;
      solves += r.solves;
      failed += r.ok ? 0 : 1;
    }
    std::printf("%s: %d candidates, %d samples: %.2f s each (rest shape %.2f s, %ld Newton iterations of %ld; "
                "%ld sample solves), %d failed\n",
                contact_only ? "contact stage (R1, kc1 random)" : "all five random", count, o.samples, total / count,
                rest / count, rest_iterations / count, iterations / count, solves / count, failed);
  }
}

// Spearman's rank correlation of two score lists (failed = worst).
double rank_correlation(const std::vector<double>& a, const std::vector<double>& b) {
  const auto ranks = [](const std::vector<double>& v) {
    std::vector<std::size_t> order(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return v[i] < v[j]; });
    std::vector<double> r(v.size());
    for (std::size_t k = 0; k < order.size(); ++k) r[order[k]] = static_cast<double>(k);
    return r;
  };
  const std::vector<double> ra = ranks(a), rb = ranks(b);
  const double n = static_cast<double>(a.size());
  double d2 = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) d2 += (ra[i] - rb[i]) * (ra[i] - rb[i]);
  return 1.0 - 6.0 * d2 / (n * (n * n - 1.0));
}

// The truth off by a factor: ks1, kb, kc1 × (1 + f), ε̄s ÷ (1 + f), R1 ÷ (1 + f/10) (its basin
// is narrow).
yarn::YarnParams off_truth(const yarn::YarnParams& truth, double f) {
  yarn::YarnParams q = truth;
  q.ks1 *= 1.0 + f;
  q.eps_s /= 1.0 + f;
  q.kb *= 1.0 + f;
  q.r1 /= 1.0 + 0.1 * f;
  q.kc1 *= 1.0 + f;
  return q;
}

// g along the straight line (in log θ) from the truth off by `offset` (as `recovery
// --start-offset`) to the truth: on each point's own rest state, and on the start's rest state
// held. Shows whether g itself is smooth there and how far the held rest state models it.
void print_line(const Problem& p, const yarn::YarnFitSettings& base, double offset, int points) {
  yarn::ObjectiveOptions lo = base.objective;
  lo.samples = base.local_samples;
  const yarn::YarnObjective objective(yarn::make_yarn_tile(p.tile), p.targets, lo);
  const yarn::YarnParams start = off_truth(p.truth, offset);
  const yarn::RestState held = objective.rest_state(start);
  std::printf("line from the truth off by %.0f %% (w = 0) to the truth (w = 1), log-linear; held: the start's rest state\n",
              100 * offset);
  for (int k = 0; k < points; ++k) {
    const double w = points > 1 ? static_cast<double>(k) / (points - 1) : 0.0;
    yarn::YarnParams q = p.truth;
    for (double yarn::YarnParams::*f : {&yarn::YarnParams::ks1, &yarn::YarnParams::eps_s, &yarn::YarnParams::kb,
                                        &yarn::YarnParams::r1, &yarn::YarnParams::kc1})
      q.*f = start.*f * std::pow(p.truth.*f / start.*f, w);
    const auto own = objective.evaluate(q);
    const auto at_held = objective.evaluate_at_rest(held, q, {});
    const yarn::RestState rs = objective.rest_state(q);
    std::printf("  w %.3f  g own %.5g  g held %.5g  rest: %d its, stress %.3g %.3g, E %.4g %.4g %.4g, max dL %.4g, clamped %d, "
                "energy %.6g, min distance %.5g\n",
                w, own.ok ? own.value : std::nan(""), at_held.ok ? at_held.value : std::nan(""), rs.newton_iterations,
                rs.rest.rest_stress(0, 0), rs.rest.rest_stress(1, 1), rs.rest.period_stretch(0, 0),
                rs.rest.period_stretch(1, 1), rs.rest.period_stretch(0, 1), rs.rest.max_length_change, rs.rest.clamped_edges,
                rs.system ? rs.system->energy(rs.g) : std::nan(""), rs.system ? rs.system->min_contact_distance(rs.g) : std::nan(""));
    std::fflush(stdout);
  }
}

// Where one evaluation of the local step's objective spends its time (issue 49), at the truth
// and 10 % off it: the rest relaxation (Newton iterations, seconds), then the samples' solves
// (per sample, Newton iterations per solve, compression bands found flat, seconds).
void print_evaluation_cost(const Problem& p, const yarn::YarnFitSettings& base) {
  yarn::ObjectiveOptions lo = base.objective;
  lo.samples = base.local_samples;
  const yarn::YarnObjective objective(yarn::make_yarn_tile(p.tile), p.targets, lo);
  const yarn::YarnParams off = off_truth(p.truth, 0.1);
  for (const auto& [label, q] : {std::pair{"truth", p.truth}, std::pair{"10 % off", off}}) {
    const auto t0 = numerics::Clock::now();
    const yarn::RestState rest = objective.rest_state(q);
    const double rest_seconds = numerics::seconds_since(t0);
    const auto r = objective.evaluate_at_rest(rest, q, {});
    const int samples = lo.samples * static_cast<int>(r.directions.size());
    std::printf("%-9s rest %d Newton iterations %.2f s; samples %d: %d solves (%.1f per sample), %.1f Newton "
                "iterations per solve, %d flat bands, %.2f s; g %.4g\n",
                label, rest.newton_iterations, rest_seconds, samples, r.solves,
                samples > 0 ? static_cast<double>(r.solves) / samples : 0.0,
                r.solves > 0 ? static_cast<double>(r.newton_iterations) / r.solves : 0.0, r.flat_compressions,
                r.seconds, r.value);
  }
}

// How well cheaper objectives (fewer stretch samples, fewer rest-shape rounds) rank candidates
// like the local step's (20 samples, 40 rounds) does: `count` candidates spread over the box with
// R1 within ±5 % of the truth (what the staged search's second stage sees).
void print_fidelity(const Problem& p, const yarn::YarnFitSettings& base, int count) {
  const swarm::ParameterSpace space = yarn::yarn_parameter_space(p.scales, false);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<yarn::YarnParams> candidates;
  for (int k = 0; k < count; ++k) {
    Eigen::VectorXd u(space.dimension());
    for (int i = 0; i < space.dimension(); ++i) u[i] = unit(rng);
    Eigen::VectorXd x = space.from_unit(u);
    x[3] = p.truth.r1 * (0.95 + 0.1 * unit(rng));
    candidates.push_back(yarn::params_from_point(x, p.scales, false));
  }
  struct Fidelity {
    int samples, rounds;
  };
  std::vector<std::vector<double>> scores;
  std::vector<double> seconds;
  const std::vector<Fidelity> table{{20, 40}, {7, 40}, {4, 40}, {3, 40}, {4, 12}, {3, 12}, {3, 6}};
  for (const Fidelity& f : table) {
    yarn::ObjectiveOptions o = base.objective;
    o.samples = f.samples;
    o.rest.rounds = f.rounds;
    const yarn::YarnObjective objective(yarn::make_yarn_tile(p.tile), p.targets, o);
    std::vector<double> g(candidates.size());
    const auto t0 = numerics::Clock::now();
#pragma omp parallel for schedule(dynamic)
    for (int k = 0; k < count; ++k) {
      const auto r = objective.evaluate(candidates[static_cast<std::size_t>(k)]);
      g[static_cast<std::size_t>(k)] = r.ok ? r.value : std::numeric_limits<double>::infinity();
    }
    seconds.push_back(numerics::seconds_since(t0));
    scores.push_back(g);
  }
  std::printf("fidelity: %d candidates (R1 within 5 %% of the truth), rank correlation with 20 samples / 40 rest rounds\n",
              count);
  for (std::size_t f = 0; f < table.size(); ++f) {
    // Where the reference's best three land in this fidelity's ranking.
    std::vector<std::size_t> ref(candidates.size()), mine(candidates.size());
    for (std::size_t i = 0; i < ref.size(); ++i) ref[i] = mine[i] = i;
    std::stable_sort(ref.begin(), ref.end(), [&](auto i, auto j) { return scores[0][i] < scores[0][j]; });
    std::stable_sort(mine.begin(), mine.end(), [&](auto i, auto j) { return scores[f][i] < scores[f][j]; });
    int worst_rank = 0;
    for (int t = 0; t < 3 && t < count; ++t)
      worst_rank = std::max(worst_rank, static_cast<int>(std::find(mine.begin(), mine.end(), ref[t]) - mine.begin()));
    std::printf("  %2d samples, %2d rounds: %5.1f s for all (%.2f core-s each), rank correlation %.3f, the "
                "reference's best 3 within its best %d\n",
                table[f].samples, table[f].rounds, seconds[f], 2.0 * seconds[f] / count,
                rank_correlation(scores[0], scores[f]), worst_rank + 1);
  }
}

// The residual Jacobian of the local objective at the truth's rest state against central
// differences (issue 33: ≤ 1e-4 relative in smooth cases): tight solves and a narrow band.
void print_jacobian_check(const Problem& p, const yarn::YarnFitSettings& base) {
  yarn::ObjectiveOptions o = base.objective;
  o.samples = base.local_samples;
  o.compression_stress_fraction = 1e-8;
  o.compression.tolerance = 1e-10;
  o.solve.force_tolerance = 1e-12 * p.scales.ks2;
  o.solve.stress_tolerance = 0.0;
  o.solve.max_iterations = 1000;
  o.solve.loose_tolerance = 1e-300;  // (0 would mean the objective's default: loose solves after 60 iterations)
  const yarn::YarnObjective objective(yarn::make_yarn_tile(p.tile), p.targets, o);
  const yarn::RestState rest = objective.rest_state(p.truth);
  if (!rest.ok) throw std::runtime_error("rest state: " + rest.message);
  const std::vector<yarn::YarnParam> wanted{yarn::YarnParam::ks1, yarn::YarnParam::eps_s, yarn::YarnParam::kb,
                                            yarn::YarnParam::r1, yarn::YarnParam::kc1};
  yarn::AtRestOptions with_jacobian;
  with_jacobian.wanted = wanted;
  with_jacobian.record_states = true;
  const yarn::ObjectiveResult timed = objective.evaluate_at_rest(rest, p.truth, with_jacobian);
  const yarn::ObjectiveResult plain = objective.evaluate_at_rest(rest, p.truth);
  std::printf("jacobian check at the truth (%d samples per direction, tight solves): one evaluation %.2f s with the "
              "Jacobian, %.2f s without; %d compressions held\n",
              o.samples, timed.seconds, plain.seconds, timed.held_compressions);
  const yarn::JacobianCheck c = yarn::check_residual_jacobian(objective, rest, p.truth, wanted);
  if (!c.ok) throw std::runtime_error("jacobian check: " + c.message);
  std::printf("  %-6s %14s %12s %10s\n", "param", "|dr/dlog p|", "rel. error", "best step");
  for (const auto& col : c.columns)
    std::printf("  %-6s %14.4g %12.3g %10.0e\n", yarn::to_string(col.param), col.column_norm, col.relative_error,
                col.step);
  std::printf("  worst %.3g (goal <= 1e-4: %s), %d evaluations, %.0f s\n", c.worst, c.worst <= 1e-4 ? "met" : "MISSED",
              c.evaluations, c.seconds);
}

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> out;
  std::string item;
  for (const char ch : text) {
    if (ch == separator) {
      out.push_back(item);
      item.clear();
    } else {
      item += ch;
    }
  }
  out.push_back(item);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_calibration profile|recovery|jacobian|ablations|settings [options]\n");
    return 2;
  }
  const std::string mode = argv[1];
  std::string shared = YARNFIT_SHARED_DIR;
  yarn::YarnFitSettings base;
  int setting_count = 4;  // `settings` mode: how many rows of the table to run
  int first_setting = 1;  // and from which (1-based)
  std::string truth = "toe";
  std::string tile = "stockinette";
  double max_stretch = 0.3;
  double start_offset = 0.0;  // > 0: no swarm; the local step starts off the truth by this factor
  int candidate_count = 16;   // `candidates` mode
  std::string cases = "stockinette:toe,stockinette:plated";  // `goals` mode
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string key = argv[i];
    const char* value = argv[i + 1];
    if (key == "--particles") base.particles = std::atoi(value);
    else if (key == "--iterations") base.iterations = std::atoi(value);
    else if (key == "--samples") base.swarm_samples = std::atoi(value);
    else if (key == "--local-evaluations") base.local_evaluations = std::atoi(value);
    else if (key == "--local-samples") base.local_samples = std::atoi(value);
    else if (key == "--start-offset") start_offset = std::atof(value);
    else if (key == "--candidates") candidate_count = std::atoi(value);
    else if (key == "--cases") cases = value;
    else if (key == "--budget") {
      const auto b = yarn::budget_from_string(value);
      if (!b) {
        std::fprintf(stderr, "bench_calibration: --budget: expected quick, default or thorough, got %s\n", value);
        return 2;
      }
      yarn::apply_budget(*b, base);
    } else if (key == "--global") {
      const auto g = yarn::global_method_from_string(value);
      if (!g) {
        std::fprintf(stderr, "bench_calibration: --global: expected staged or swarm, got %s\n", value);
        return 2;
      }
      base.global_method = *g;
    }
    else if (key == "--accept-bands") base.objective.accept_bands = std::atof(value);
    else if (key == "--rest-rounds") base.objective.rest.rounds = std::atoi(value);
    else if (key == "--rounds") base.alternation.max_rounds = std::atoi(value);
    else if (key == "--rest-difference-step") base.alternation.rest_difference_step = std::atof(value);
    else if (key == "--r1-window") base.staged.r1_window = std::atof(value);
    else if (key == "--root-correction") base.objective.root_correction = std::atoi(value) != 0;
    else if (key == "--local-method" || key == "--local") {
      const auto m = yarn::local_method_from_string(value);
      if (!m) {
        std::fprintf(stderr, "bench_calibration: --local-method: expected implicit-filtering or cobyla, got %s\n", value);
        return 2;
      }
      base.local_method = *m;
    }
    else if (key == "--threads") base.threads = std::atoi(value);
    else if (key == "--shared") shared = value;
    else if (key == "--settings") setting_count = std::atoi(value);
    else if (key == "--first-setting") first_setting = std::atoi(value);
    else if (key == "--truth") truth = value;
    else if (key == "--tile") tile = value;
    else if (key == "--max-stretch") max_stretch = std::atof(value);
    else {
      std::fprintf(stderr, "bench_calibration: unknown option %s\n", key.c_str());
      return 2;
    }
  }
  try {
    if (mode == "goals") {
      // Every case of issue 33's table, one fit each; --cases names a subset (tile:truth[:seed], comma
      // separated); tiles by name of ../shared/data/patterns or a .pyp path.
      std::vector<RecoveryRow> rows;
      for (const std::string& item : split(cases, ',')) {
        const std::vector<std::string> f = split(item, ':');
        if (f.size() < 2) throw std::invalid_argument("--cases: expected tile:truth[:seed], got " + item);
        std::string case_truth = f[1];  // KS1/EPS_S[/KC1]: '/' for the ',' of --truth
        std::replace(case_truth.begin(), case_truth.end(), '/', ',');
        const Problem q = make_problem(shared, f[0], case_truth, max_stretch);
        yarn::YarnFitSettings s = base;
        if (f.size() > 2) s.seed = std::stoull(f[2]);
        const yarn::YarnFitResult r = run(q, s);
        print_fit(item.c_str(), q, r, true);
        rows.push_back(recovery_row(item, q, r));
        std::fflush(stdout);
      }
      print_goal_table(rows, base.threads);
      return 0;
    }
    const Problem p = make_problem(shared, tile, truth, max_stretch);
    if (mode == "recovery" || mode == "profile") {
      std::printf("settings: %d particles x %d iterations, %d samples (swarm), %d (local), local step %s, at most %d "
                  "evaluations\n",
                  base.particles, base.iterations, base.swarm_samples, base.local_samples,
                  yarn::to_string(base.local_method), base.local_evaluations);
      // The local step's objective at the true parameters: what a perfect optimiser reaches.
      yarn::ObjectiveOptions lo = base.objective;
      lo.samples = base.local_samples;
      const yarn::YarnObjective local(yarn::make_yarn_tile(p.tile), p.targets, lo);
      const auto at_truth = local.evaluate(p.truth);
      yarn::YarnFitResult truth_row;
      truth_row.ok = at_truth.ok;
      truth_row.params = p.truth;
      truth_row.final = at_truth;
      print_fit("true parameters", p, truth_row, false);
      if (std::getenv("BENCH_PRINT_SAMPLES") != nullptr)
        for (const auto& d : at_truth.directions)
          for (std::size_t i = 0; i < d.stretch.size(); ++i)
            std::printf("      sample %zu s %.4f S %.5g / %.5g  c %.5g / %.5g\n", i, d.stretch[i], d.stress_sim[i],
                        d.stress_target[i], d.compression_sim[i], d.compression_target[i]);
      // Identifiability from stretch data alone: g of the local step's objective with one
      // parameter 10 % off the truth, the others true. A parameter the data pin raises g well
      // above g(truth); one they do not leave it near g(truth).
      std::printf("profile at the true parameters: g = %.4g; with one parameter x0.9 / x1.1:\n", at_truth.value);
      for (double yarn::YarnParams::*field : {&yarn::YarnParams::ks1, &yarn::YarnParams::eps_s, &yarn::YarnParams::kb,
                                              &yarn::YarnParams::r1, &yarn::YarnParams::kc1}) {
        double g[2];
        for (int k = 0; k < 2; ++k) {
          yarn::YarnParams q = p.truth;
          q.*field *= k == 0 ? 0.9 : 1.1;
          const auto r = local.evaluate(q);
          g[k] = r.ok ? r.value : std::nan("");
        }
        const char* name = field == &yarn::YarnParams::ks1     ? "ks1"
                           : field == &yarn::YarnParams::eps_s ? "eps_s"
                           : field == &yarn::YarnParams::kb    ? "kb"
                           : field == &yarn::YarnParams::r1    ? "R1"
                                                               : "kc1";
        std::printf("    %-6s g %.4g / %.4g  (%.0fx / %.0fx g at the truth)\n", name, g[0], g[1], g[0] / at_truth.value,
                    g[1] / at_truth.value);
      }
      std::fflush(stdout);
      if (mode == "recovery") {
        yarn::YarnFitSettings s = base;
        if (start_offset > 0.0) {
          s.swarm = false;
          s.start = off_truth(p.truth, start_offset);
          std::printf("local step alone from the truth off by %.0f %% (R1 by %.1f %%)\n", 100 * start_offset,
                      10 * start_offset);
        }
        const yarn::YarnFitResult r = run(p, s);
        print_fit("recovery", p, r, true);
        print_recovery_goals(p, r, base.threads);
      }
    } else if (mode == "cost") {
      print_evaluation_cost(p, base);
    } else if (mode == "line") {
      print_line(p, base, start_offset > 0 ? start_offset : 0.1, candidate_count + 5);
    } else if (mode == "fidelity") {
      print_fidelity(p, base, candidate_count);
    } else if (mode == "candidates") {
      print_candidate_costs(p, base, candidate_count);
    } else if (mode == "jacobian") {
      print_jacobian_check(p, base);
    } else if (mode == "ablations") {
      print_fit("full method", p, run(p, base), true);
      yarn::YarnFitSettings s = base;
      s.swarm = false;
      print_fit("no swarm", p, run(p, s), true);
      s = base;
      s.linear_stretch = true;
      print_fit("linear stretch", p, run(p, s), true);
      s = base;
      s.rest_shape = false;
      print_fit("no rest shape", p, run(p, s), true);
      s = base;
      s.local_method = base.local_method == yarn::LocalMethod::cobyla ? yarn::LocalMethod::implicit_filtering
                                                                             : yarn::LocalMethod::cobyla;
      const std::string other = std::string("local step ") + yarn::to_string(s.local_method);
      print_fit(other.c_str(), p, run(p, s), true);
    } else if (mode == "settings") {
      struct Setting {
        int particles, iterations, samples;
      };
      // Cheapest first, the default last; the third row has half the default's iterations
      // (its inertia decays over 5, so it is not the default stopped halfway). On the toe
      // truth it reached the truth's basin; 16 x 4 and 32 x 6 did not.
      const std::vector<Setting> table{{16, 4, 4}, {32, 6, 5}, {64, 5, 7}, {64, 10, 7}};
      std::printf("settings table: particles x iterations x samples (swarm); local step %s, %d samples, at most %d "
                  "evaluations\n",
                  yarn::to_string(base.local_method), base.local_samples, base.local_evaluations);
      for (int row = std::max(first_setting, 1) - 1; row < std::min<int>(setting_count, static_cast<int>(table.size()));
           ++row) {
        const Setting& st = table[static_cast<std::size_t>(row)];
        yarn::YarnFitSettings s = base;
        s.particles = st.particles;
        s.iterations = st.iterations;
        s.swarm_samples = st.samples;
        const std::string label =
            std::to_string(st.particles) + "x" + std::to_string(st.iterations) + "x" + std::to_string(st.samples);
        print_fit(label.c_str(), p, run(p, s), true);
        std::fflush(stdout);
      }
    } else {
      std::fprintf(stderr, "bench_calibration: unknown mode %s\n", mode.c_str());
      return 2;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_calibration: %s\n", e.what());
    return 1;
  }
  return 0;
}
