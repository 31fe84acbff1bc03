#include "yarn_fit/fit/objective/direction_sweep.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>

#include "fabrics_db/text_util.hpp"
#include "results/metrics/error_metrics.hpp"
#include "yarn_fit/homogenise/sensitivity.hpp"

namespace yarnfit::yarn {

double interpolate_target(const std::vector<db::UniaxialPoint>& points, double s, double db::UniaxialPoint::*field) {
  if (points.empty()) return 0.0;
  if (s <= points.front().stretch) return points.front().*field;
  if (s >= points.back().stretch) return points.back().*field;
  const auto hi = std::upper_bound(points.begin(), points.end(), s,
                                   [](double x, const db::UniaxialPoint& q) { return x < q.stretch; });
  const auto lo = hi - 1;
  const double f = (s - lo->stretch) / (hi->stretch - lo->stretch);
  return (1.0 - f) * ((*lo).*field) + f * ((*hi).*field);
}

namespace {

bool same_deformation(const yarn::CoarseDeformation& a, const yarn::CoarseDeformation& b) {
  return a.stretch == b.stretch && a.compression == b.compression && a.curvature == b.curvature && a.angle == b.angle;
}

// One direction's sweep: the samples in order, each added to the direction's error as soon as
// its c and σ_s are known.
class Sweep {
 public:
  Sweep(yarn::YarnSystem& system, const Eigen::VectorXd& g_rest, const db::DirectionTargets& targets,
        const SweepSettings& settings, DirectionError& e, SweepCounts& counts)
      : m_system(system), m_g(g_rest), m_t(targets), m_s(settings), m_e(e), m_counts(counts),
        m_name(db::to_string(targets.direction)),
        m_sensitive(settings.root_correction || !settings.wanted.empty()) {
    m_chi.angle = db::pull_angle(targets.direction);
  }

  std::string run() {
    const std::string why = m_s.every_sample ? every_sample() : at_nodes();
    if (!why.empty()) return why;
    finish();
    return {};
  }

 private:
  [[nodiscard]] double stretch_at(int i) const {
    const double s0 = m_t.stretch.front().stretch, s1 = m_t.stretch.back().stretch;
    return s0 + (s1 - s0) * static_cast<double>(i) / (m_s.samples - 1);
  }
  [[nodiscard]] double target_c(double s) const {
    return interpolate_target(m_t.stretch, s, &db::UniaxialPoint::compression);
  }
  void count(const yarn::Sample& smp) {
    if (smp.last_solve.status == yarn::Termination::converged_loosely) ++m_counts.loose_solves;
    m_e.solves += smp.solves;
    m_counts.newton_iterations += smp.newton_iterations;
  }
  std::string failed(const char* what, double s, const std::string& message) const {
    return m_name + ": " + what + " at s = " + db::format_g(s) + " failed: " + message;
  }

  // The sample's read-out: as solved, or (sensitive) with its derivatives and, at a free c,
  // the point of its band nearest the targets' c, to first order (sensitivity.hpp).
  yarn::SensitiveReadout read(const yarn::Sample& smp, bool free_compression) {
    yarn::SensitiveReadout r;
    r.compression = smp.chi.compression;
    r.stress_s = smp.stress_s;
    if (!m_sensitive) return r;
    if (!same_deformation(m_system.deformation(), smp.chi)) {
      m_system.set_deformation(smp.chi);
      m_system.rebuild_contacts(m_g);
    }
    m_sensitivity = yarn::equilibrium_sensitivity(m_system, m_g, m_s.wanted);
    return read(smp, m_sensitivity, free_compression);
  }

  yarn::SensitiveReadout read(const yarn::Sample& smp, const yarn::EquilibriumSensitivity& sens, bool free_compression) {
    yarn::SensitiveReadout r;
    r.compression = smp.chi.compression;
    r.stress_s = smp.stress_s;
    if (!sens.ok) {  // an unstable state: keep the read-out as solved, without derivatives
      ++m_e.held;
      r.held = true;
      r.d_compression = r.d_stress = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(m_s.wanted.size()));
      return r;
    }
    if (!free_compression) return yarn::fixed_compression_readout(smp, sens);
    yarn::BandOptions band;
    band.tolerance = m_s.compression.stress_tolerance;
    band.reference = target_c(smp.chi.stretch);
    band.flat_band = m_s.flat_band;
    const yarn::SensitiveReadout c = yarn::free_compression_readout(smp, sens, band);
    if (c.held) ++m_e.held;
    if (c.flat) ++m_e.flat;
    return c;
  }

  // Adds sample (s, read-out) to the direction's error; true once the cutoff is reached.
  bool add(double s, const yarn::SensitiveReadout& r, double accepted_c = 0.0, double slope = 0.0) {
    if (m_s.record_states) {
      m_e.states.g.push_back(m_g);
      m_e.states.compression.push_back(accepted_c);
      m_e.states.slope.push_back(slope);
    }
    const double s_sim = pk2(r.stress_s, s);
    const double s_tgt = pk2(interpolate_target(m_t.stretch, s, &db::UniaxialPoint::stress), s);
    const double c_tgt = target_c(s);
    const double w = m_e.scale.comfort_value / std::max(m_e.scale.comfort_value, s_tgt);
    const double ds = (s_sim - s_tgt) / m_e.scale.stress_norm;
    const double dc = (r.compression - c_tgt) / m_e.scale.compression_norm;
    m_sum_sq += w * (ds * ds + m_e.scale.compression_weight * dc * dc);
    m_e.stretch.push_back(s);
    m_e.stress_sim.push_back(s_sim);
    m_e.stress_target.push_back(s_tgt);
    m_e.compression_sim.push_back(r.compression);
    m_e.compression_target.push_back(c_tgt);
    m_e.weight.push_back(w);
    if (!m_s.wanted.empty()) {
      m_e.d_stress_sim.push_back(r.d_stress / (1.0 + s));
      m_e.d_compression_sim.push_back(r.d_compression);
    }
    m_counts.stopped = m_sum_sq / m_s.samples >= m_s.cutoff && m_s.cutoff > 0.0;
    return m_counts.stopped;
  }

  yarn::Sample solve_free(double s, const yarn::CompressionOptions& options) {
    m_chi.stretch = s;
    yarn::Sample smp = yarn::solve_free_compression(m_system, m_chi, m_g, options, m_s.solve);
    count(smp);
    return smp;
  }

  // Sensitive: Newton on ∂Ψ/∂c with the exact d²Ψ/dc² (sensitivity.hpp), from the state moved to
  // (s, guess) along the last sample's tangent when there is one; the accepted state's
  // sensitivity is kept for the read-out.
  yarn::Sample solve_free_newton(double s, const yarn::CompressionOptions& options, bool predict) {
    if (predict && m_sensitivity.ok) {
      const Eigen::Vector4d step = (s - m_chi.stretch) * yarn::stretch_weights(m_chi) +
                                   (options.initial_guess - m_chi.compression) * yarn::compression_weights(m_chi);
      m_g += m_sensitivity.state_tangent * step;
    }
    m_chi.stretch = s;
    yarn::SensitiveSample ss = yarn::solve_free_compression_newton(m_system, m_chi, m_g, options, m_s.solve, m_s.wanted);
    count(ss.sample);
    m_sensitivity = std::move(ss.sensitivity);
    if (ss.sample.ok) m_chi = ss.sample.chi;
    return ss.sample;
  }

  // c* at every sample, by continuation along s: each search starts from the previous
  // sample's equilibrium, at its c* moved by the targets' change of c, with a first
  // bracketing step of the size of the last change of c* (or, sensitive, the Newton step on
  // the exact d²Ψ/dc² of the previous sample).
  std::string every_sample() {
    if (m_s.warm != nullptr && m_s.warm->size() == static_cast<std::size_t>(m_s.samples)) return from_warm_states();
    if (m_sensitive) return every_sample_newton();
    const double s0 = stretch_at(0);
    yarn::CompressionOptions comp = m_s.compression;
    comp.initial_guess = target_c(s0);
    const yarn::Sample first = solve_free(s0, comp);
    if (!first.ok) return failed("free compression", s0, first.message);
    yarn::SensitiveReadout r = read(first, true);
    if (add(s0, r, r.compression, r.stress_cc)) return {};
    double c_prev = m_sensitive ? r.compression : first.chi.compression, dc_prev = 0.0;
    double slope_prev = m_sensitive && r.stress_cc > 0.0 ? r.stress_cc : first.stress_c_slope;
    for (int i = 1; i < m_s.samples; ++i) {
      const double s = stretch_at(i);
      yarn::CompressionOptions cs = comp;
      cs.initial_guess = c_prev + target_c(s) - target_c(stretch_at(i - 1));
      cs.initial_step = std::clamp(2.0 * std::abs(dc_prev), 0.002, std::min(cs.initial_step, 0.02));
      cs.initial_slope = slope_prev;
      const yarn::Sample smp = solve_free(s, cs);
      if (!smp.ok) return failed("free compression", s, smp.message);
      r = read(smp, true);
      const double c_now = m_sensitive ? r.compression : smp.chi.compression;
      dc_prev = c_now - c_prev;
      c_prev = c_now;
      if (m_sensitive && r.stress_cc > 0.0) slope_prev = r.stress_cc;
      else if (smp.stress_c_slope > 0.0) slope_prev = smp.stress_c_slope;
      if (add(s, r, r.compression, r.stress_cc)) break;
    }
    return {};
  }

  // The same, sensitive: each sample's search by Newton on c from the previous sample's state moved
  // along its tangent to the new stretch and the guess (the previous c* plus the targets' change).
  std::string every_sample_newton() {
    yarn::CompressionOptions comp = m_s.compression;
    comp.stress_tolerance *= m_s.accept_bands;
    comp.initial_guess = target_c(stretch_at(0));
    comp.initial_step = std::min(comp.initial_step, 0.05);
    for (int i = 0; i < m_s.samples; ++i) {
      const double s = stretch_at(i);
      if (i > 0) comp.initial_guess = m_chi.compression + target_c(s) - target_c(stretch_at(i - 1));
      const yarn::Sample smp = solve_free_newton(s, comp, i > 0);
      if (!smp.ok) return failed("free compression", s, smp.message);
      const yarn::SensitiveReadout r = read(smp, m_sensitivity, true);
      if (add(s, r, r.compression, r.stress_cc)) break;
    }
    return {};
  }

  // Every sample from where the previous evaluation left it: its state, its accepted c as the
  // guess and its d²Ψ/dc² for the first (Newton) step.
  std::string from_warm_states() {
    const SweepStates& warm = *m_s.warm;
    for (int i = 0; i < m_s.samples; ++i) {
      const auto k = static_cast<std::size_t>(i);
      const double s = stretch_at(i);
      m_g = warm.g[k];
      yarn::CompressionOptions cs = m_s.compression;
      cs.stress_tolerance *= m_s.accept_bands;
      cs.initial_guess = warm.compression[k];
      cs.initial_step = 0.002;
      cs.initial_slope = warm.slope[k] > 0.0 && std::isfinite(warm.slope[k]) ? warm.slope[k] : 0.0;
      const yarn::Sample smp = solve_free_newton(s, cs, false);
      if (!smp.ok) return failed("free compression", s, smp.message);
      const yarn::SensitiveReadout r = read(smp, m_sensitivity, true);
      if (add(s, r, r.compression, r.stress_cc)) break;
    }
    return {};
  }

  // c* at the nodes only (6.5.3: both ends), linear in between. The far nodes are reached by
  // marching the sample stretches first, at the compression the targets' shape suggests (c*(s0)
  // plus the targets' change of c), each solve warm from the last: a node's search then starts
  // from a nearby equilibrium instead of from the rest state.
  std::string at_nodes() {
    const int n = m_s.samples;
    const double s0 = stretch_at(0);
    yarn::CompressionOptions comp = m_s.compression;
    comp.initial_guess = target_c(s0);
    const yarn::Sample first = solve_free(s0, comp);
    if (!first.ok) return failed("free compression", s0, first.message);
    const int nodes = std::clamp(m_s.nodes, 2, n);
    std::vector<int> node_index;
    for (int k = 0; k < nodes; ++k)
      node_index.push_back(static_cast<int>(std::lround(static_cast<double>(k) * (n - 1) / (nodes - 1))));
    std::vector<yarn::SensitiveReadout> node_read{read(first, true)};
    std::vector<Eigen::VectorXd> march(static_cast<std::size_t>(n));
    march[0] = m_g;
    const double c0 = first.chi.compression;
    std::vector<double> c_march(static_cast<std::size_t>(n), c0);
    for (int i = 1; i < n; ++i) {
      yarn::CoarseDeformation x = m_chi;
      x.stretch = stretch_at(i);
      x.compression = c0 + target_c(x.stretch) - target_c(s0);
      const yarn::Sample smp = yarn::simulate_sample(m_system, x, m_g, m_s.solve);
      count(smp);
      if (!smp.ok) return failed("sample", x.stretch, smp.message);
      march[static_cast<std::size_t>(i)] = m_g;
      c_march[static_cast<std::size_t>(i)] = x.compression;
    }
    for (int k = 1; k < nodes; ++k) {
      const int i = node_index[static_cast<std::size_t>(k)];
      m_g = march[static_cast<std::size_t>(i)];
      yarn::CompressionOptions cs = comp;
      cs.initial_guess = c_march[static_cast<std::size_t>(i)];
      cs.initial_step = std::min(cs.initial_step, 0.02);
      const yarn::Sample smp = solve_free(stretch_at(i), cs);
      if (!smp.ok) return failed("free compression", stretch_at(i), smp.message);
      node_read.push_back(read(smp, true));
    }
    // Samples at the interpolated compression, each warm-started from the march's state at
    // the same stretch (a nearby compression); nodes reuse their free-compression read-outs.
    std::size_t k = 0;  // node at or before sample i
    for (int i = 0; i < n; ++i) {
      const double s = stretch_at(i);
      while (k + 1 < node_index.size() && node_index[k + 1] <= i) ++k;
      if (node_index[k] == i) {
        if (add(s, node_read[k], node_read[k].compression)) break;
        continue;
      }
      const double sa = stretch_at(node_index[k]), sb = stretch_at(node_index[k + 1]);
      const double f = (s - sa) / (sb - sa);
      yarn::CoarseDeformation x = m_chi;
      x.stretch = s;
      x.compression = (1.0 - f) * node_read[k].compression + f * node_read[k + 1].compression;
      m_g = march[static_cast<std::size_t>(i)];
      const yarn::Sample smp = yarn::simulate_sample(m_system, x, m_g, m_s.solve);
      count(smp);
      if (!smp.ok) return failed("sample", s, smp.message);
      yarn::SensitiveReadout r = read(smp, false);
      if (!m_s.wanted.empty()) {  // c follows the nodes: σ_s moves with it
        r.d_compression = (1.0 - f) * node_read[k].d_compression + f * node_read[k + 1].d_compression;
        r.d_stress += r.stress_sc * r.d_compression;
      }
      if (add(s, r, x.compression)) break;
    }
    return {};
  }

  // The reported errors (SPEC §3, Fig. 6.15) over the samples run; the stretches increase, so
  // the comfort range is a leading run of them.
  void finish() {
    m_e.value = m_sum_sq / m_s.samples;
    std::size_t n_comfort = 0;
    while (n_comfort < m_e.stretch.size() && m_e.stretch[n_comfort] <= m_e.scale.comfort_stretch + 1e-12) ++n_comfort;
    const std::span<const double> sim(m_e.stress_sim), tgt(m_e.stress_target);
    m_e.stress_full_pct = results::yarn_error_pct(sim, tgt, m_e.scale.stress_norm);
    m_e.stress_comfort_pct = n_comfort > 0
                                 ? results::yarn_error_pct(sim.first(n_comfort), tgt.first(n_comfort), m_e.scale.stress_norm)
                                 : m_e.stress_full_pct;
    m_e.compression_pct = results::yarn_error_pct(m_e.compression_sim, m_e.compression_target, m_e.scale.compression_norm);
  }

  yarn::YarnSystem& m_system;
  Eigen::VectorXd m_g;
  const db::DirectionTargets& m_t;
  const SweepSettings& m_s;
  DirectionError& m_e;
  SweepCounts& m_counts;
  std::string m_name;
  bool m_sensitive;
  yarn::CoarseDeformation m_chi;
  yarn::EquilibriumSensitivity m_sensitivity;  // of the last sensitive solve
  double m_sum_sq = 0.0;
};

}  // namespace

std::string sweep_direction(yarn::YarnSystem& system, const Eigen::VectorXd& g_rest, const db::DirectionTargets& targets,
                            const SweepSettings& settings, DirectionError& e, SweepCounts& counts) {
  Sweep sweep(system, g_rest, targets, settings, e, counts);
  return sweep.run();
}

std::string sweep_bending(yarn::YarnSystem& system, const Eigen::VectorXd& g_rest, const db::DirectionTargets& targets,
                          int samples, double weight, const yarn::EquilibriumOptions& solve,
                          std::span<const yarn::YarnParam> wanted, DirectionError& e, SweepCounts& counts) {
  const auto& points = targets.bending;
  if (points.size() < 2 || samples < 1 || !(weight > 0.0)) return {};
  double largest = 0.0;
  for (const auto& p : points) largest = std::max(largest, std::abs(p.stress));
  if (!(largest > 0.0)) return {};
  const std::string name(db::to_string(targets.direction));
  Eigen::VectorXd g = g_rest;
  yarn::CoarseDeformation chi;
  chi.angle = db::pull_angle(targets.direction);
  // A knitted tile curls at rest: the response is σ_κ(κ) − σ_κ(0) (bending_check.hpp).
  const yarn::BendingSample flat = yarn::simulate_bending(system, chi, g, 0.0, solve, wanted);
  counts.newton_iterations += flat.centre.newton_iterations;
  e.solves += flat.centre.solves;
  if (!flat.ok) return name + ": bending at κ = 0 failed: " + flat.message;
  e.bending_norm = largest;
  e.bending_weight = weight;
  const double kappa_max = points.back().curvature;
  double sum_sq = 0.0;
  for (int j = 1; j <= samples; ++j) {
    chi.curvature = kappa_max * j / samples;
    const yarn::BendingSample b = yarn::simulate_bending(system, chi, g, 0.0, solve, wanted);
    counts.newton_iterations += b.centre.newton_iterations;
    e.solves += b.centre.solves;
    if (!b.ok) return name + ": bending at κ = " + db::format_g(chi.curvature) + " 1/m failed: " + b.message;
    // The targets are 2 k_θ κ: linear, read at κ by interpolation all the same.
    double target = points.back().stress;
    for (std::size_t i = 1; i < points.size(); ++i)
      if (chi.curvature <= points[i].curvature) {
        const double t = (chi.curvature - points[i - 1].curvature) / (points[i].curvature - points[i - 1].curvature);
        target = points[i - 1].stress + t * (points[i].stress - points[i - 1].stress);
        break;
      }
    const double sim = b.stress_kappa - flat.stress_kappa;
    e.bending_curvature.push_back(chi.curvature);
    e.bending_sim.push_back(sim);
    e.bending_target.push_back(target);
    if (!wanted.empty()) e.d_bending_sim.push_back(b.d_stress_kappa - flat.d_stress_kappa);
    const double r = (sim - target) / largest;
    sum_sq += r * r;
  }
  system.set_deformation(yarn::CoarseDeformation{0.0, 0.0, 0.0, chi.angle});
  e.value += weight * sum_sq / samples;
  return {};
}

}  // namespace yarnfit::yarn
