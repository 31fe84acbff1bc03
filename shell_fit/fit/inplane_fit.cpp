#include "shell_fit/fit/inplane_fit.hpp"

#include <ceres/ceres.h>

#include "numerics/roots/bisection.hpp"
#include "numerics/util/clock.hpp"
#include "shell_fit/fit/ceres_support.hpp"
#include "shell_fit/fit/curve_interpolation.hpp"
#include "shell_fit/fit/search_map.hpp"
#include "shell_fit/energies/lockup_curve.hpp"

#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>

#include "results/metrics/error_metrics.hpp"
#include "shell_fit/targets/uniform_targets.hpp"

namespace yarnfit::shell {

namespace {

using VecP = Eigen::Matrix<double, k_inplane_param_count, 1>;

VecP to_vec(const InplaneParams& p) {
  const auto a = to_array(p);
  return Eigen::Map<const VecP>(a.data());
}
InplaneParams from_vec(const VecP& v) {
  std::array<double, k_inplane_param_count> a{};
  Eigen::Map<VecP>(a.data()) = v;
  return inplane_from_array(a);
}

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

namespace {

// The small-strain stiffnesses K' = K + 2 kn [[1, 1], [1, 1]] and kss from the data.
struct SmallStrain {
  double kxx = 0, kxy = 0, kyy = 0, kss = 0;
};

SmallStrain small_strain_stiffness(const db::Fabric& fabric) {
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
  SmallStrain p;
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
    // The bias modulus grows with kss: 60 halvings in log kss over 1e-4…1e2 of the geometric mean.
    const double s = 1e-3;
    const auto too_soft = [&](double kss) -> std::optional<bool> {
      const InplaneParams q{p.kxx, p.kxy, p.kyy, kss, 0.0, 0.0};
      return uniaxial_point(q, db::pull_angle(db::Direction::bias), s).stress / s < E[1];
    };
    numerics::BisectionOptions o;
    o.midpoint = numerics::Midpoint::geometric;
    o.halvings = 60;
    p.kss = numerics::bisect(too_soft, 1e-4 * geo, 1e2 * geo, o).x;
  }
  return p;
}

// Share of the small-strain coupling k'xy carried by the area terms in each start.
constexpr double k_area_shares[3] = {0.5, 0.1, 0.9};
const char* const k_start_names[3] = {"balanced (half of the coupling from the area terms)",
                                      "coupling mostly from kxy (10 % from the area terms)",
                                      "coupling mostly from the area terms (90 %)"};

InplaneParams split_coupling(const SmallStrain& k, double area_share) {
  const double geo = std::sqrt(k.kxx * k.kyy);
  // A coupling too small to split (ν ≈ 0) still leaves the area terms a small role.
  const double coupling = std::max(k.kxy, 0.02 * geo);
  const double kn = std::min(0.5 * area_share * coupling, 0.45 * std::min(k.kxx, k.kyy));
  InplaneParams p;
  p.kxx = k.kxx - 2.0 * kn;
  p.kyy = k.kyy - 2.0 * kn;
  p.kxy = std::max(coupling - 2.0 * kn, 0.01 * coupling);
  p.kss = k.kss;
  p.kn1 = 0.5 * kn;
  p.kn2 = 0.5 * kn;
  return p;
}

}  // namespace

InplaneParams initial_inplane_guess(const db::Fabric& fabric) {
  return split_coupling(small_strain_stiffness(fabric), k_area_shares[0]);
}

std::vector<InplaneStart> inplane_starts(const db::Fabric& fabric) {
  const SmallStrain k = small_strain_stiffness(fabric);
  std::vector<InplaneStart> out;
  for (int i = 0; i < 3; ++i) {
    InplaneStart s;
    s.name = k_start_names[i];
    s.params = split_coupling(k, k_area_shares[i]);
    out.push_back(s);
  }
  return out;
}

namespace {

class StretchResiduals : public ceres::CostFunction {
 public:
  StretchResiduals(std::vector<ClampedStretchScene>& scenes, std::vector<DirectionFit>& data, const SearchMap& map,
                   int threads, int& simulations)
      : m_scenes(scenes), m_data(data), m_map(map), m_threads(threads), m_simulations(simulations),
        m_warm(scenes.size()) {
    int n = 0;
    for (const auto& d : m_data) {
      m_force_weight.push_back(1.0 / std::max(mean_abs(d.measured_force), 1e-12));
      m_comp_weight.push_back(d.measured_compression.empty() ? 0.0 : 1.0 / std::max(mean_abs(d.measured_compression), 1e-6));
      n += static_cast<int>(d.stretch.size()) * (d.measured_compression.empty() ? 1 : 2);
    }
    set_num_residuals(n);
    mutable_parameter_block_sizes()->push_back(static_cast<int>(m_map.size()));
  }

  VecP params_from(const double* q) const { return m_map.params(q); }

  // Every evaluation computes the Jacobian too (the sensitivities cost a fraction of the
  // equilibrium solves) and keeps it: Ceres evaluates a trial point's residuals and, when it
  // accepts the step, asks for the Jacobian at the same point again, which then costs nothing.
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const int nf = static_cast<int>(m_map.size());
    const int nr = num_residuals();
    const std::vector<double> q(parameters[0], parameters[0] + nf);
    if (!(m_cached && q == m_cached_q)) {
      m_cached = false;
      m_cached_q = q;
      m_cached_ok = simulate(q);
      m_cached = true;
      m_failures_in_a_row = m_cached_ok ? 0 : m_failures_in_a_row + 1;
    }
    if (!m_cached_ok) return false;  // Ceres shrinks its step and tries again
    std::copy(m_res.begin(), m_res.end(), residuals);
    if (jacobians && jacobians[0]) std::copy(m_jac.begin(), m_jac.begin() + nr * nf, jacobians[0]);
    return true;
  }

  // Evaluations that failed (a scene did not reach equilibrium) since the last that worked.
  [[nodiscard]] int failures_in_a_row() const { return m_failures_in_a_row; }

  // Before a new Ceres run: forgets the failures (the cache and the warm starts stay valid).
  void new_run() const { m_failures_in_a_row = 0; }

  // The effects the scenes' last successful runs simulated (empty before any).
  [[nodiscard]] const std::vector<std::string>& effects() const { return m_effects; }

 private:
  bool simulate(const std::vector<double>& q) const {
    const VecP p = params_from(q.data());
    const InplaneParams ip = from_vec(p);
    const Eigen::MatrixXd dp_dq = m_map.jacobian(q.data());
    std::vector<ClampedStretchRun> runs(m_data.size());
#pragma omp parallel for num_threads(m_threads) schedule(dynamic)
    for (int k = 0; k < static_cast<int>(m_data.size()); ++k) {
      const auto kk = static_cast<std::size_t>(k);
      runs[kk] = m_scenes[kk].run(ip, m_data[kk].stretch, true, &m_warm[kk]);
    }
    m_simulations += static_cast<int>(m_data.size());
    const auto nf = static_cast<std::size_t>(m_map.size());
    m_res.assign(static_cast<std::size_t>(num_residuals()), 0.0);
    m_jac.assign(m_res.size() * nf, 0.0);
    // One residual's row of the Jacobian in q: (∂r/∂p)ᵀ ∂p/∂q.
    const auto put_row = [&](std::size_t row, double weight, const Eigen::VectorXd& dr_dp) {
      const Eigen::RowVectorXd dr_dq = weight * dr_dp.transpose() * dp_dq;
      for (std::size_t j = 0; j < nf; ++j) m_jac[row * nf + j] = dr_dq[static_cast<Eigen::Index>(j)];
    };
    int r = 0;
    for (std::size_t k = 0; k < m_data.size(); ++k) {
      if (!runs[k].ok) {
        m_warm[k] = ClampedStretchWarmStart{};  // its states may be far from any good point
        return false;
      }
    }
    if (!runs.empty()) m_effects = runs.front().effects;
    for (std::size_t k = 0; k < m_data.size(); ++k) {
      auto& d = m_data[k];
      d.simulated_force.clear();
      d.simulated_compression.clear();
      for (std::size_t i = 0; i < d.stretch.size(); ++i) {
        const auto& smp = runs[k].samples[i];
        d.simulated_force.push_back(smp.force);
        d.simulated_compression.push_back(smp.compression);
        const auto ur = static_cast<std::size_t>(r);
        m_res[ur] = m_force_weight[k] * (smp.force - d.measured_force[i]);
        put_row(ur, m_force_weight[k], smp.dforce_dp);
        ++r;
        if (d.measured_compression.empty()) continue;
        const auto uc = static_cast<std::size_t>(r);
        m_res[uc] = m_comp_weight[k] * (smp.compression - d.measured_compression[i]);
        put_row(uc, m_comp_weight[k], smp.dcompression_dp);
        ++r;
      }
    }
    return true;
  }

  std::vector<ClampedStretchScene>& m_scenes;
  std::vector<DirectionFit>& m_data;
  const SearchMap& m_map;
  int m_threads;
  int& m_simulations;
  std::vector<double> m_force_weight, m_comp_weight;
  mutable std::vector<ClampedStretchWarmStart> m_warm;
  mutable bool m_cached = false, m_cached_ok = false;
  mutable int m_failures_in_a_row = 0;
  mutable std::vector<double> m_cached_q, m_res, m_jac;
  mutable std::vector<std::string> m_effects;
};


}  // namespace

namespace {
// Restarts of a Ceres run that stalled on failed trial points (see solve below).
constexpr int k_max_restarts = 3;
}  // namespace

namespace {

// One fit of options.model from the thesis-model starts (inplane_starts), or, for the
// stiffening model, from `lockup_starts` when given.
// `law` names the fit's phase in the progress stage: "" for a thesis-law fit alone, e.g.
// ", eq. 6.1 first" and ", stiffening" for the two phases of a stiffening fit.
InplaneFitResult fit_inplane_from(const db::Fabric& fabric, const InplaneFitOptions& options,
                                  std::vector<InplaneStart> lockup_starts, const std::string& law);

// The lock-up pair (l, b) of a test direction: indices into k_inplane_param_names.
int lockup_index(db::Direction d) {
  switch (d) {
    case db::Direction::weft: return 6;
    case db::Direction::warp: return 8;
    default: return 10;
  }
}

// Lock-up starting values from a measured curve: the rate b = 2/ε_max puts e² of growth at
// the end of the fitted range, and l makes the term's tangent there carry the stiffening the
// curve shows beyond its small-strain slope (d(line force)/ds ≈ λ² φ''(ε) for the pull).
std::pair<double, double> lockup_guess(const db::StretchTest& t, double max_line_force) {
  const DirectionFit d = make_direction_targets(t, max_line_force);
  std::vector<double> line_force(t.curve.force);
  for (double& f : line_force) f /= t.swatch.width;
  const double E0 = std::max(initial_slope(t.curve.stretch, line_force), 1e-9);
  const double s1 = d.max_stretch, s0 = s1 * 5.0 / 6.0;
  const double E_end = (interpolate_linear(t.curve.stretch, line_force, s1) -
                        interpolate_linear(t.curve.stretch, line_force, s0)) / std::max(s1 - s0, 1e-12);
  const double lambda = 1.0 + s1;
  const double eps = 0.5 * (lambda * lambda - 1.0);
  const double tangent = std::max(E_end - E0, 0.1 * E0) / (lambda * lambda);
  const double b = std::clamp(2.0 / std::max(eps, 1e-6), 0.1, 20.0);
  const double l = tangent / (std::max(eps, 1e-6) * lockup_h(1, b * eps));
  return {l, b};
}

}  // namespace

InplaneFitResult fit_inplane(const db::Fabric& fabric, const InplaneFitOptions& options) {
  if (options.model == InplaneModel::thesis) return fit_inplane_from(fabric, options, {}, "");
  // The stiffening model starts from the thesis model's fit (with lock-up added): its
  // optimum is a point of the larger model, so the larger model never ends worse than it
  // from that start; and from the balanced small-strain split with lock-up from the curves.
  InplaneFitOptions thesis_options = options;
  thesis_options.model = InplaneModel::thesis;
  const InplaneFitResult thesis = fit_inplane_from(fabric, thesis_options, {}, ", eq. 6.1 first");
  std::vector<InplaneStart> starts;
  const auto with_lockup = [&](InplaneParams p, double l_factor, bool from_data, double share) {
    auto v = to_array(p);
    for (const auto& [dir, t] : fabric.stretch_tests) {
      const auto [l, b] = lockup_guess(t, options.max_line_force);
      const auto i = static_cast<std::size_t>(lockup_index(dir));
      v[i] = from_data ? l : l_factor * l;
      v[i + 1] = from_data ? b : 1.0;
    }
    // Both shares; held at 0 below where no test pins them.
    v[k_first_share_param] = v[k_first_share_param + 1] = share;
    return inplane_from_array(v);
  };
  const auto add = [&](const std::string& name, const InplaneParams& p) {
    InplaneStart st;
    st.name = name;
    st.params = p;
    starts.push_back(st);
  };
  if (!std::isnan(thesis.stretch_force_pct)) {  // the thesis fit reached an evaluated point
    add("thesis-model fit with lock-up from the curves' ends", with_lockup(thesis.params, 1.0, true, 0.0));
    // Shares make the lock-up pull the width in, so they start with less small-strain coupling.
    const auto less_coupling = [&](double f) {
      InplaneParams p = thesis.params;
      p.kxy *= f;
      p.kn1 *= f;
      p.kn2 *= f;
      return p;
    };
    add("thesis-model fit with half its coupling, lock-up from the curves' ends, lateral shares 0.5",
        with_lockup(less_coupling(0.5), 1.0, true, 0.5));
    add("thesis-model fit with a quarter of its coupling, lock-up from the curves' ends, lateral shares 1",
        with_lockup(less_coupling(0.25), 1.0, true, 1.0));
    // The thesis optimum itself (no lock-up): the continued start is the best after a few
    // iterations, so the stiffening fit never ends with a higher cost than the thesis fit.
    add("thesis-model fit without lock-up", with_lockup(thesis.params, 0.0, false, 0.0));
  }
  add("balanced small-strain split with lock-up from the curves' ends",
      with_lockup(initial_inplane_guess(fabric), 1.0, true, 0.0));
  InplaneFitResult r = fit_inplane_from(fabric, options, starts, ", stiffening");
  r.thesis_stretch_force_pct = thesis.stretch_force_pct;
  r.thesis_compression_pct = thesis.compression_pct;
  r.thesis_params = thesis.params;
  r.seconds += thesis.seconds;
  r.simulations += thesis.simulations;
  r.iterations += thesis.iterations;
  return r;
}

namespace {

void note_not_identified(InplaneFitResult& result, int i, const std::string& why) {
  result.not_identified.push_back(std::string(k_inplane_param_names[i]) + ": " + why);
}

// Which parameters a fit searches (indices into k_inplane_param_names, sorted) and the values
// of the others (held).
struct Identification {
  std::vector<int> free;
  VecP held;
};

// The thesis law's six (kxx kxy kyy kss kn1 kn2): free where a test pins them. Without
// compression the coupling cannot be split: one start, with the small-strain stiffnesses as
// they are. Sets result.starts and result.start; returns the held values.
VecP identify_thesis_params(const db::Fabric& fabric, std::vector<int>& free, InplaneFitResult& result) {
  const bool has[3] = {fabric.stretch_tests.count(db::Direction::weft) > 0,
                       fabric.stretch_tests.count(db::Direction::bias) > 0,
                       fabric.stretch_tests.count(db::Direction::warp) > 0};
  result.starts = inplane_starts(fabric);
  result.start = result.starts[0].params;
  VecP held = to_vec(result.start);
  if (has[0]) free.push_back(0);
  else note_not_identified(result, 0, "no weft test (held equal to kyy, isotropic prior)");
  if (result.compression_measured) free.push_back(1);
  else note_not_identified(result, 1, "no compression measured (held at 0)");
  if (has[2]) free.push_back(2);
  else note_not_identified(result, 2, "no warp test (held equal to kxx, isotropic prior)");
  if (has[1]) free.push_back(3);
  else note_not_identified(result, 3, "no bias test (prior (sqrt(k'xx*k'yy) - k'xy)/2 from the small-strain slopes: " +
                                          std::to_string(held[3]) + " N/m)");
  if (result.compression_measured) {
    free.push_back(4);
    free.push_back(5);
  } else {
    result.starts.resize(1);
    result.starts[0].name = "small-strain slopes";
    const SmallStrain k = small_strain_stiffness(fabric);
    result.starts[0].params = {k.kxx, 0.0, k.kyy, k.kss, 0.0, 1e-3 * std::sqrt(k.kxx * k.kyy)};
    result.start = result.starts[0].params;
    held = to_vec(result.start);
    note_not_identified(result, 4, "no compression measured (held at 0)");
    note_not_identified(result, 5, "no compression measured (weak barrier 1e-3*sqrt(kxx*kyy))");
  }
  return held;
}

// The stiffening law's lock-up of every tested direction (an untested one has none: held at
// 0) and the lateral shares of the weft and warp lock-up, which the width response of a test
// pins. `lockup_starts`, when given, replace the thesis starts, their held parameters set to
// the thesis model's priors whatever the start says.
void identify_lockup_params(const db::Fabric& fabric, std::vector<InplaneStart> lockup_starts, Identification& id,
                            InplaneFitResult& result) {
  for (const db::Direction d : {db::Direction::weft, db::Direction::warp, db::Direction::bias}) {
    const int i = lockup_index(d);
    if (fabric.stretch_tests.count(d)) {
      id.free.push_back(i);
      id.free.push_back(i + 1);
    } else {
      note_not_identified(result, i, "no " + std::string(db::to_string(d)) + " test (no lock-up: held at 0)");
      note_not_identified(result, i + 1, "no " + std::string(db::to_string(d)) + " test (no lock-up)");
    }
  }
  for (const db::Direction d : {db::Direction::weft, db::Direction::warp}) {
    const int share = k_first_share_param + (d == db::Direction::weft ? 0 : 1);
    if (fabric.stretch_tests.count(d) && result.compression_measured) id.free.push_back(share);
    else note_not_identified(result, share, fabric.stretch_tests.count(d)
                                                ? "no compression measured (held at 0)"
                                                : "no " + std::string(db::to_string(d)) + " test (held at 0)");
  }
  if (lockup_starts.empty()) return;
  for (auto& st : lockup_starts) {
    VecP v = to_vec(st.params);
    for (int k = 0; k < k_inplane_param_count; ++k)
      if (std::find(id.free.begin(), id.free.end(), k) == id.free.end())
        v[k] = k >= k_first_lockup_param ? 0.0 : id.held[k];
    st.params = from_vec(v);
  }
  result.starts = lockup_starts;
  result.start = result.starts[0].params;
}

// The clamped-stretch scene and the targets (result.directions) of every test.
std::vector<ClampedStretchScene> stretch_scenes(const db::Fabric& fabric, const InplaneFitOptions& options,
                                                InplaneFitResult& result) {
  std::vector<ClampedStretchScene> scenes;
  for (const auto& [dir, t] : fabric.stretch_tests) {
    ClampedStretchSetup setup = stretch_setup(t, options.target_edge, options.refinements);
    setup.max_newton_iterations = options.newton_budget_per_target * k_stretch_targets_per_direction;
    scenes.emplace_back(setup);
    result.directions.push_back(make_direction_targets(t, options.max_line_force));
  }
  return scenes;
}

// The search space: the map from the slots q to the parameters, and the bounds that keep
// the search physical, relative to the data-based axial stiffness scale.
struct SearchSpace {
  SearchMap map;
  double scale;

  SearchSpace(const Identification& id, InplaneModel model, const std::vector<DirectionFit>& directions)
      : map(id.free, id.held, model, reference_strains(directions)), scale(std::sqrt(id.held[0] * id.held[2])) {}

  // Reference strain of each lock-up curve (weft, warp, shear): the Green strain at the end of
  // its test's fitted range (a bias pull of Green strain e has |ε3| = e).
  static std::array<double, 3> reference_strains(const std::vector<DirectionFit>& directions) {
    std::array<double, 3> x_ref{1.0, 1.0, 1.0};
    for (const auto& d : directions) {
      const double e = 0.5 * ((1.0 + d.max_stretch) * (1.0 + d.max_stretch) - 1.0);
      x_ref[static_cast<std::size_t>(lockup_index(d.direction) - k_first_lockup_param) / 2] = std::max(e, 1e-3);
    }
    return x_ref;
  }

  // Bounds of slot j: stiffnesses 1e-4…1e4 of the scale (log); the stiffening law's kxy and a
  // lock-up stress (or an l searched alone) from 0, which is no coupling or no lock-up, to 1e4
  // of it; rates 0…k_max_lockup_rate; shares k_min_lockup_share…k_max_lockup_share.
  [[nodiscard]] std::pair<double, double> q_bounds(std::size_t j) const {
    const int k = map.free()[j];
    if (is_lockup_rate(k)) return {0.0, k_max_lockup_rate};
    if (is_lockup_share(k)) return {k_min_lockup_share, k_max_lockup_share};
    if (!map.log_slot(j)) return {0.0, 1e4 * scale};
    return {std::log(1e-4 * scale), std::log(1e4 * scale)};
  }
  // The same in the parameters, for the JSON (a lock-up stress slot bounds l by σ_max/g(0)).
  [[nodiscard]] std::pair<double, double> p_bounds(std::size_t j) const {
    const auto [lo, hi] = q_bounds(j);
    if (const int c = map.stress_curve(j); c >= 0) return {lo, hi / map.stress_factor(c, 0.0)};
    return map.log_slot(j) ? std::pair{std::exp(lo), std::exp(hi)} : std::pair{lo, hi};
  }
  [[nodiscard]] std::vector<double> start_q(const InplaneParams& params) const {
    std::vector<double> q = map.q_of(to_vec(params));
    for (std::size_t j = 0; j < q.size(); ++j) {
      const auto [lo, hi] = q_bounds(j);
      q[j] = std::clamp(q[j], lo, hi);
    }
    return q;
  }
};

// Ceres runs of one fit within its search space.
struct CeresRuns {
  const SearchSpace& space;
  const InplaneFitOptions& options;
  ProgressCallback& progress;
  InplaneFitResult& result;  // counts iterations and restarts

  // Ceres treats a trial point whose scenes fail as a step of infinite cost and shrinks its
  // trust region faster with every failure in a row; a few in a row make the next step so
  // short that Ceres reports convergence by parameter tolerance where the fit has merely
  // stalled. Such a stop is restarted from the point reached with a fresh trust region.
  // The residuals carry the inner solves' noise (Newton 1e-9 of the force scale, secant 1e-10 in
  // stretch); asking for less change than 1e-9 only burns iterations, and 1e-9 keeps
  // noise-free synthetic data recoverable to 1e-4.
  void solve(StretchResiduals& cost, std::vector<double>& q, int max_iterations,
             ceres::Solver::Summary& summary) const {
    for (int restart = 0; restart <= k_max_restarts && max_iterations > 0; ++restart) {
      cost.new_run();
      ceres::Problem::Options po;
      po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
      ceres::Problem problem(po);
      problem.AddResidualBlock(&cost, nullptr, q.data());
      for (std::size_t j = 0; j < space.map.size(); ++j) {
        const auto [lo, hi] = space.q_bounds(j);
        problem.SetParameterLowerBound(q.data(), static_cast<int>(j), lo);
        problem.SetParameterUpperBound(q.data(), static_cast<int>(j), hi);
      }
      ceres::Solver::Options so = least_squares_options(max_iterations, 1e-9, 1e-9, &progress);
      so.initial_trust_region_radius = options.initial_trust_region_radius;

      ceres::Solve(so, &problem, &summary);
      const int used = static_cast<int>(summary.iterations.size()) - 1;
      result.iterations += used;
      max_iterations -= used;
      if (!(summary.termination_type == ceres::CONVERGENCE && cost.failures_in_a_row() > 0)) break;
      ++result.restarts;
    }
  }

  // Multi-start: a few iterations from every start (one cost function each, keeping the warm
  // starts of its own path, so the best start continues from equilibria near its
  // parameters). Returns the best start; q receives the point it reached.
  std::size_t best_start(const std::vector<std::unique_ptr<StretchResiduals>>& costs, const std::string& stage,
                         std::vector<double>& q, ceres::Solver::Summary& summary) const {
    std::size_t chosen = 0;
    if (result.starts.size() <= 1) return chosen;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < result.starts.size(); ++k) {
      auto& st = result.starts[k];
      progress.set_stage(stage + " start " + std::to_string(k + 1) + "/" + std::to_string(result.starts.size()),
                         options.start_iterations);
      std::vector<double> qk = space.start_q(st.params);
      solve(*costs[k], qk, options.start_iterations, summary);
      st.ok = summary.IsSolutionUsable() && std::isfinite(summary.final_cost);
      st.cost = summary.final_cost;
      st.iterations = static_cast<int>(summary.iterations.size()) - 1;
      st.message = summary.BriefReport();
      if (st.ok && st.cost < best) {
        best = st.cost;
        q = qk;
        chosen = k;
      }
    }
    return chosen;
  }
};

// The progress stage names the phase and the tests fitted together, e.g. "in-plane,
// stiffening (weft, warp)".
std::string stage_name(const std::string& law, const std::vector<DirectionFit>& directions) {
  std::string stage = "in-plane" + law + " (";
  for (std::size_t k = 0; k < directions.size(); ++k)
    stage += (k ? ", " : "") + std::string(db::to_string(directions[k].direction));
  return stage + ")";
}

// Re-evaluates at the solution so the reported curves belong to the final parameters, and
// records how well the data identify each free parameter: the covariance of q carried to the
// parameters (first order), sd(p) relative to p, which for a log-space slot is the standard
// deviation of log p. Returns whether the evaluation succeeded.
bool evaluate_solution(StretchResiduals& cost, const std::vector<double>& q, const SearchMap& map,
                       InplaneFitResult& result) {
  const std::vector<int>& free = map.free();
  const VecP p = cost.params_from(q.data());
  std::vector<double> res(static_cast<std::size_t>(cost.num_residuals()));
  const double* blocks[] = {q.data()};
  std::vector<double> jac(res.size() * free.size());
  double* jac_blocks[] = {jac.data()};
  const bool final_ok = cost.Evaluate(blocks, res.data(), jac_blocks);
  if (!final_ok || free.empty()) return final_ok;
  const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> J(
      jac.data(), static_cast<Eigen::Index>(res.size()), static_cast<Eigen::Index>(free.size()));
  const Eigen::MatrixXd JtJ = J.transpose() * J;
  const Eigen::MatrixXd D = map.jacobian(q.data());
  const Eigen::MatrixXd cov = D * JtJ.completeOrthogonalDecomposition().pseudoInverse() * D.transpose();
  for (std::size_t j = 0; j < free.size(); ++j) {
    const auto k = static_cast<Eigen::Index>(free[j]);
    const double sd = 0.01 * std::sqrt(std::max(cov(k, k), 0.0));
    const double pk = p[free[j]];
    const double pct = 100.0 * (pk != 0.0 ? sd / std::abs(pk) : std::numeric_limits<double>::infinity());
    result.sensitivity_pct[static_cast<std::size_t>(free[j])] = pct;
    if (!(pct <= k_weak_identification_pct)) result.weakly_identified.push_back(k_inplane_param_names[free[j]]);
  }
  return true;
}

// The fit's parameters, status, bounds and errors at the solution q.
void record_solution(const StretchResiduals& cost, const std::vector<double>& q, const SearchSpace& space,
                     const ceres::Solver::Summary& summary, bool final_ok, int max_iterations,
                     InplaneFitResult& result) {
  const std::vector<int>& free = space.map.free();
  result.params = from_vec(cost.params_from(q.data()));
  result.converged = summary.IsSolutionUsable() && final_ok && summary.termination_type == ceres::CONVERGENCE;
  result.message = final_ok ? summary.BriefReport() : "final evaluation failed: a scene did not reach equilibrium";
  result.hit_iteration_cap = final_ok && summary.termination_type == ceres::NO_CONVERGENCE;
  if (result.hit_iteration_cap)
    result.message = "stopped at the iteration cap (" + std::to_string(max_iterations) +
                     " iterations) before converging; the errors are those reached: " + result.message;
  for (std::size_t j = 0; j < free.size(); ++j) {
    const int k = free[j];
    result.bounds[k_inplane_param_names[k]] = space.p_bounds(j);
    const auto [lo, hi] = space.q_bounds(j);
    // 1e-3 of log space is 0.1 %; for a rate, 1e-3 absolute.
    if (q[j] - lo < 1e-3 || hi - q[j] < 1e-3) result.at_bounds.push_back(k_inplane_param_names[k]);
  }
  if (final_ok) {
    result.effects = cost.effects();
    results::ShellErrorSum force, compression;
    for (const auto& d : result.directions) {
      force.add(d.measured_force, d.simulated_force);
      if (!d.measured_compression.empty()) compression.add(d.measured_compression, d.simulated_compression);
    }
    result.stretch_force_pct = force.pct();
    result.compression_pct = compression.pct();  // NaN when not measured
  } else {
    // The curves belong to the last point that simulated, not to these parameters.
    for (auto& d : result.directions) {
      d.simulated_force.clear();
      d.simulated_compression.clear();
    }
    result.errors_reason = result.message;
  }
}

InplaneFitResult fit_inplane_from(const db::Fabric& fabric, const InplaneFitOptions& options,
                                  std::vector<InplaneStart> lockup_starts, const std::string& law) {
  const auto start_time = numerics::Clock::now();
  InplaneFitResult result;
  result.model = options.model;
  if (fabric.stretch_tests.empty()) {
    result.message = "the fabric has no stretch test";
    result.errors_reason = result.message;
    return result;
  }
  for (const auto& [dir, t] : fabric.stretch_tests) result.compression_measured |= t.curve.has_compression();
  Identification id;
  id.held = identify_thesis_params(fabric, id.free, result);
  if (options.model == InplaneModel::stiffening) identify_lockup_params(fabric, std::move(lockup_starts), id, result);
  std::sort(id.free.begin(), id.free.end());
  for (int i : id.free) result.identified.push_back(k_inplane_param_names[i]);
  if (options.start_iterations <= 0) result.starts.resize(1);

  std::vector<ClampedStretchScene> scenes = stretch_scenes(fabric, options, result);
  const SearchSpace space(id, options.model, result.directions);
  std::vector<std::unique_ptr<StretchResiduals>> costs;
  for (std::size_t k = 0; k < result.starts.size(); ++k)
    costs.push_back(std::make_unique<StretchResiduals>(scenes, result.directions, space.map,
                                                       std::max(1, options.threads), result.simulations));
  // Displayed error: the root-mean-square normalised residual, in percent.
  const double n_res = static_cast<double>(costs[0]->num_residuals());
  ProgressCallback progress(options.progress, start_time,
                            [n_res](double c) { return 100.0 * std::sqrt(2.0 * c / std::max(n_res, 1.0)); });
  quiet_solver_warnings();
  const CeresRuns runs{space, options, progress, result};
  const std::string stage = stage_name(law, result.directions);

  // A few iterations from every start, then the best one to convergence.
  std::vector<double> q = space.start_q(result.starts[0].params);
  ceres::Solver::Summary summary;
  const std::size_t chosen = runs.best_start(costs, stage, q, summary);
  result.chosen_start = static_cast<int>(chosen);
  StretchResiduals& cost = *costs[chosen];
  progress.set_stage(stage, options.max_iterations);
  runs.solve(cost, q, options.max_iterations, summary);
  const bool final_ok = evaluate_solution(cost, q, space.map, result);
  record_solution(cost, q, space, summary, final_ok, options.max_iterations, result);
  result.seconds = numerics::seconds_since(start_time);
  return result;
}

}  // namespace

}  // namespace yarnfit::shell
