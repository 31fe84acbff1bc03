#include "shell_fit/fit/inplane_fit.hpp"

#include <ceres/ceres.h>

#include "shell_fit/fit/ceres_support.hpp"
#include "shell_fit/fit/curve_interpolation.hpp"

#include <Eigen/QR>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "shell_fit/targets/uniform_targets.hpp"

namespace yarnfit::shell {

namespace {

using Vec6 = Eigen::Matrix<double, 6, 1>;

Vec6 to_vec(const InplaneParams& p) { return (Vec6() << p.kxx, p.kxy, p.kyy, p.kss, p.kn1, p.kn2).finished(); }
InplaneParams from_vec(const Vec6& v) { return {v[0], v[1], v[2], v[3], v[4], v[5]}; }


// Least-squares slope through the origin over the first third of the range: the small-strain
// modulus of a curve that stiffens, without being thrown by the toe's noise.
double initial_slope(const std::vector<double>& s, const std::vector<double>& y) {
  const double s_end = s.back() / 3.0;
  double num = 0.0, den = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] > s_end && den > 0.0) break;
    num += s[i] * y[i];
    den += s[i] * s[i];
  }
  return den > 0.0 ? num / den : 0.0;
}

double mean_abs(const std::vector<double>& v) {
  double sum = 0.0;
  for (double x : v) sum += std::abs(x);
  return v.empty() ? 0.0 : sum / static_cast<double>(v.size());
}

}  // namespace

ClampedStretchSetup stretch_setup(const db::StretchTest& test, double target_edge, int refinements) {
  ClampedStretchSetup s;
  s.length = test.swatch.length;
  s.width = test.swatch.width;
  // The weft axis seen from the pull: the test pulls at +φ from the weft, so the weft lies at −φ.
  s.material_angle = -db::pull_angle(test.direction);
  s.gauge_length = test.gauge.length;
  s.gauge_width = test.gauge.width;
  s.target_edge = target_edge;
  s.refinements = refinements;
  return s;
}

DirectionFit make_direction_targets(const db::StretchTest& test, double max_line_force) {
  DirectionFit d;
  d.direction = test.direction;
  const auto& c = test.curve;
  double s_max = c.stretch.back();
  if (std::isfinite(max_line_force)) {
    if (const auto s_limit = db::stretch_at_line_force(test, max_line_force)) s_max = std::min(s_max, *s_limit);
  }
  d.max_stretch = s_max;
  d.measured_max_stretch = c.stretch.back();
  for (int i = 1; i <= k_stretch_targets_per_direction; ++i) {
    const double s = s_max * i / k_stretch_targets_per_direction;
    d.stretch.push_back(s);
    d.measured_force.push_back(interpolate_linear(c.stretch, c.force, s));
    if (c.has_compression()) d.measured_compression.push_back(interpolate_linear(c.stretch, c.compression, s));
  }
  return d;
}

InplaneParams initial_inplane_guess(const db::Fabric& fabric) {
  // Line-force modulus E = d(F/W)/ds and contraction ratio ν = dc/ds at small stretch.
  double E[3] = {0, 0, 0}, nu[3] = {-1, -1, -1};
  for (const auto& [dir, t] : fabric.stretch_tests) {
    std::vector<double> line_force(t.curve.force);
    for (double& f : line_force) f /= t.swatch.width;
    const auto k = static_cast<std::size_t>(dir);
    E[k] = std::max(initial_slope(t.curve.stretch, line_force), 1e-9);
    if (t.curve.has_compression()) nu[k] = std::clamp(initial_slope(t.curve.stretch, t.curve.compression), 0.0, 0.95);
  }
  const double Ex = E[0] > 0 ? E[0] : (E[2] > 0 ? E[2] : E[1]);
  const double Ey = E[2] > 0 ? E[2] : Ex;
  // Linear orthotropic zero-lateral-stress relations: ν_x = kxy/kyy, E_x = kxx − kxy²/kyy,
  // ν_y = kxy/kxx, E_y = kyy − kxy²/kxx; a few fixed-point sweeps reconcile them.
  InplaneParams p;
  p.kxx = Ex;
  p.kyy = Ey;
  for (int it = 0; it < 20; ++it) {
    if (nu[0] >= 0.0) p.kxy = nu[0] * p.kyy;
    else if (nu[2] >= 0.0) p.kxy = nu[2] * p.kxx;
    else p.kxy = 0.0;
    p.kxx = Ex + p.kxy * p.kxy / p.kyy;
    p.kyy = Ey + p.kxy * p.kxy / p.kxx;
  }
  const double geo = std::sqrt(p.kxx * p.kyy);
  p.kss = std::max((geo - p.kxy) / 2.0, 0.05 * geo);
  if (E[1] > 0.0) {
    // Bias: choose kss so the small-stretch bias modulus of the model matches the data.
    const double s = 1e-3;
    double lo = 1e-4 * geo, hi = 1e2 * geo;
    for (int it = 0; it < 60; ++it) {
      InplaneParams q = p;
      q.kss = std::sqrt(lo * hi);
      const double Eb = uniaxial_point(q, db::pull_angle(db::Direction::bias), s).stress / s;
      (Eb < E[1] ? lo : hi) = q.kss;
    }
    p.kss = std::sqrt(lo * hi);
  }
  // Area terms start small against the axial stiffnesses: the data fixes them through the
  // compression at large stretch, which the fit reaches from here.
  p.kn1 = 0.02 * geo;
  p.kn2 = 0.02 * geo;
  return p;
}

namespace {

class StretchResiduals : public ceres::CostFunction {
 public:
  StretchResiduals(std::vector<ClampedStretchScene>& scenes, std::vector<DirectionFit>& data,
                   const std::vector<int>& free, const Vec6& held, int threads, int& simulations)
      : m_scenes(scenes), m_data(data), m_free(free), m_held(held), m_threads(threads), m_simulations(simulations) {
    int n = 0;
    for (const auto& d : m_data) {
      m_force_weight.push_back(1.0 / std::max(mean_abs(d.measured_force), 1e-12));
      m_comp_weight.push_back(d.measured_compression.empty() ? 0.0 : 1.0 / std::max(mean_abs(d.measured_compression), 1e-6));
      n += static_cast<int>(d.stretch.size()) * (d.measured_compression.empty() ? 1 : 2);
    }
    set_num_residuals(n);
    mutable_parameter_block_sizes()->push_back(static_cast<int>(m_free.size()));
  }

  Vec6 params_from(const double* q) const {
    Vec6 p = m_held;
    for (std::size_t i = 0; i < m_free.size(); ++i) p[m_free[i]] = std::exp(q[i]);
    return p;
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const Vec6 p = params_from(parameters[0]);
    const InplaneParams ip = from_vec(p);
    std::vector<ClampedStretchRun> runs(m_data.size());
    const bool want_jacobian = jacobians && jacobians[0];
#pragma omp parallel for num_threads(m_threads) schedule(dynamic)
    for (int k = 0; k < static_cast<int>(m_data.size()); ++k) {
      runs[static_cast<std::size_t>(k)] = m_scenes[static_cast<std::size_t>(k)].run(ip, m_data[static_cast<std::size_t>(k)].stretch, want_jacobian);
    }
    m_simulations += static_cast<int>(m_data.size());
    int r = 0;
    const int nf = static_cast<int>(m_free.size());
    for (std::size_t k = 0; k < m_data.size(); ++k) {
      if (!runs[k].ok) return false;  // Ceres shrinks its step and tries again
      auto& d = m_data[k];
      d.simulated_force.clear();
      d.simulated_compression.clear();
      for (std::size_t i = 0; i < d.stretch.size(); ++i) {
        const auto& smp = runs[k].samples[i];
        d.simulated_force.push_back(smp.force);
        d.simulated_compression.push_back(smp.compression);
        residuals[r] = m_force_weight[k] * (smp.force - d.measured_force[i]);
        if (want_jacobian)
          for (int j = 0; j < nf; ++j) jacobians[0][r * nf + j] = m_force_weight[k] * smp.dforce_dp[m_free[static_cast<std::size_t>(j)]] * p[m_free[static_cast<std::size_t>(j)]];
        ++r;
        if (d.measured_compression.empty()) continue;
        residuals[r] = m_comp_weight[k] * (smp.compression - d.measured_compression[i]);
        if (want_jacobian)
          for (int j = 0; j < nf; ++j) jacobians[0][r * nf + j] = m_comp_weight[k] * smp.dcompression_dp[m_free[static_cast<std::size_t>(j)]] * p[m_free[static_cast<std::size_t>(j)]];
        ++r;
      }
    }
    return true;
  }

 private:
  std::vector<ClampedStretchScene>& m_scenes;
  std::vector<DirectionFit>& m_data;
  std::vector<int> m_free;
  Vec6 m_held;
  int m_threads;
  int& m_simulations;
  std::vector<double> m_force_weight, m_comp_weight;
};


}  // namespace

InplaneFitResult fit_inplane(const db::Fabric& fabric, const InplaneFitOptions& options) {
  const auto start_time = std::chrono::steady_clock::now();
  InplaneFitResult result;
  if (fabric.stretch_tests.empty()) {
    result.message = "the fabric has no stretch test";
    return result;
  }
  const bool has[3] = {fabric.stretch_tests.count(db::Direction::weft) > 0,
                       fabric.stretch_tests.count(db::Direction::bias) > 0,
                       fabric.stretch_tests.count(db::Direction::warp) > 0};
  for (const auto& [dir, t] : fabric.stretch_tests) result.compression_measured |= t.curve.has_compression();

  result.start = initial_inplane_guess(fabric);
  Vec6 held = to_vec(result.start);
  // Which parameters the tests determine (indices into kxx kxy kyy kss kn1 kn2).
  std::vector<int> free;
  auto note = [&](int i, const std::string& why) {
    result.not_identified.push_back(std::string(k_inplane_names[i]) + ": " + why);
  };
  if (has[0]) free.push_back(0);
  else note(0, "no weft test (held equal to kyy, isotropic prior)");
  if (result.compression_measured) free.push_back(1);
  else note(1, "no compression measured (held at 0)");
  if (has[2]) free.push_back(2);
  else note(2, "no warp test (held equal to kxx, isotropic prior)");
  if (has[1]) free.push_back(3);
  else note(3, "no bias test (prior (sqrt(kxx*kyy) - kxy)/2 from the start values: " + std::to_string(held[3]) + " N/m)");
  if (result.compression_measured) {
    free.push_back(4);
    free.push_back(5);
  } else {
    held[1] = 0.0;
    held[4] = 0.0;
    held[5] = 1e-3 * std::sqrt(held[0] * held[2]);
    note(4, "no compression measured (held at 0)");
    note(5, "no compression measured (weak barrier 1e-3*sqrt(kxx*kyy))");
  }
  for (int i : free) result.identified.push_back(k_inplane_names[i]);

  std::vector<ClampedStretchScene> scenes;
  for (const auto& [dir, t] : fabric.stretch_tests) {
    scenes.emplace_back(stretch_setup(t, options.target_edge, options.refinements));
    result.directions.push_back(make_direction_targets(t, options.max_line_force));
  }

  std::vector<double> q;
  for (int i : free) q.push_back(std::log(held[i]));
  // Bounds keep the search physical: 1e-4…1e4 times the data-based axial scale.
  const double scale = std::sqrt(held[0] * held[2]);
  auto* cost = new StretchResiduals(scenes, result.directions, free, held, std::max(1, options.threads), result.simulations);
  ceres::Problem problem;
  problem.AddResidualBlock(cost, nullptr, q.data());
  for (int j = 0; j < static_cast<int>(free.size()); ++j) {
    problem.SetParameterLowerBound(q.data(), j, std::log(1e-4 * scale));
    problem.SetParameterUpperBound(q.data(), j, std::log(1e4 * scale));
  }
  // The residuals carry the inner solves' noise (Newton 1e-9 of the force scale, secant 1e-10 in
  // stretch); asking for less change than 1e-9 only burns iterations, and 1e-9 keeps
  // noise-free synthetic data recoverable to 1e-4.
  ProgressCallback progress(options.progress);
  const ceres::Solver::Options so =
      least_squares_options(options.max_iterations, 1e-9, 1e-9, &progress, static_cast<bool>(options.progress));
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);

  // Re-evaluate at the solution so the reported curves belong to the final parameters.
  const Vec6 p = cost->params_from(q.data());
  std::vector<double> res(static_cast<std::size_t>(cost->num_residuals()));
  const double* blocks[] = {q.data()};
  std::vector<double> jac(res.size() * free.size());
  double* jac_blocks[] = {jac.data()};
  const bool final_ok = cost->Evaluate(blocks, res.data(), jac_blocks);
  if (final_ok && !free.empty()) {
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> J(
        jac.data(), static_cast<Eigen::Index>(res.size()), static_cast<Eigen::Index>(free.size()));
    const Eigen::MatrixXd JtJ = J.transpose() * J;
    const Eigen::MatrixXd cov = JtJ.completeOrthogonalDecomposition().pseudoInverse();
    for (std::size_t j = 0; j < free.size(); ++j) {
      const double pct = 100.0 * 0.01 * std::sqrt(std::max(cov(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(j)), 0.0));
      result.sensitivity_pct[free[j]] = pct;
      if (!(pct <= k_weak_identification_pct)) result.weakly_identified.push_back(k_inplane_names[free[j]]);
    }
  }
  result.params = from_vec(p);
  result.iterations = static_cast<int>(summary.iterations.size());
  result.converged = summary.IsSolutionUsable() && final_ok &&
                     summary.termination_type == ceres::CONVERGENCE;
  result.message = final_ok ? summary.BriefReport() : "final evaluation failed: a scene did not reach equilibrium";
  for (int j = 0; j < static_cast<int>(free.size()); ++j) {
    const double lo = std::log(1e-4 * scale), hi = std::log(1e4 * scale);
    if (q[static_cast<std::size_t>(j)] - lo < 1e-3 || hi - q[static_cast<std::size_t>(j)] < 1e-3)
      result.at_bounds.push_back(k_inplane_names[free[static_cast<std::size_t>(j)]]);
  }

  double ferr = 0, fmeas = 0, cerr = 0, cmeas = 0;
  for (const auto& d : result.directions) {
    for (std::size_t i = 0; i < d.stretch.size() && i < d.simulated_force.size(); ++i) {
      ferr += std::abs(d.simulated_force[i] - d.measured_force[i]);
      fmeas += std::abs(d.measured_force[i]);
      if (!d.measured_compression.empty()) {
        cerr += std::abs(d.simulated_compression[i] - d.measured_compression[i]);
        cmeas += std::abs(d.measured_compression[i]);
      }
    }
  }
  result.stretch_force_pct = fmeas > 0 ? 100.0 * ferr / fmeas : 0.0;
  result.compression_pct = cmeas > 0 ? 100.0 * cerr / cmeas : 0.0;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
  return result;
}

}  // namespace yarnfit::shell
