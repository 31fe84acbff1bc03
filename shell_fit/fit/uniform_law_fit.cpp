#include "shell_fit/fit/uniform_law_fit.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>

#include "shell_fit/fit/ceres_support.hpp"
#include "shell_fit/targets/uniform_targets.hpp"
#include "numerics/util/non_finite.hpp"

namespace yarnfit::shell {
namespace {

using numerics::k_nan;
using Values = std::array<double, k_inplane_param_count>;

// Stiffnesses and lock-up growths are searched as logarithms (they are positive and span
// decades); the coupling kxy (negative in some stiffening fits), the lock-up rates and shares
// as they are.
constexpr int k_kxy = 1;
bool searched_linearly(int k) { return k == k_kxy || is_lockup_rate(k) || is_lockup_share(k); }
double to_search(int k, double v) { return searched_linearly(k) ? v : std::log(std::max(v, 1e-300)); }
double from_search(int k, double z) { return searched_linearly(k) ? z : std::exp(z); }

struct DirectionSamples {
  double angle = 0.0;
  std::vector<db::UniaxialPoint> points;
  double stress_norm = 1.0, compression_norm = 1e-3;
};

std::vector<DirectionSamples> stretch_samples(const std::vector<db::DirectionTargets>& samples) {
  std::vector<DirectionSamples> out;
  for (const auto& t : samples) {
    if (t.stretch.size() < 2) continue;
    DirectionSamples d{db::pull_angle(t.direction), t.stretch, 0.0, 1e-3};
    for (const auto& p : t.stretch) {
      d.stress_norm = std::max(d.stress_norm, std::abs(p.stress));
      d.compression_norm = std::max(d.compression_norm, std::abs(p.compression));
    }
    if (d.stress_norm > 0.0) out.push_back(std::move(d));
  }
  return out;
}

// The law's σ_s and c* at every sample, by continuation along each direction's stretches;
// false when a point does not converge.
bool law_at_samples(const InplaneParams& p, const std::vector<DirectionSamples>& dirs,
                    std::vector<std::vector<db::UniaxialPoint>>& out) {
  out.assign(dirs.size(), {});
  for (std::size_t d = 0; d < dirs.size(); ++d) {
    double c = 0.0;
    for (const auto& s : dirs[d].points) {
      const db::UniaxialPoint u = uniaxial_point(p, dirs[d].angle, s.stretch, c);
      if (!u.converged) return false;
      c = u.compression;
      out[d].push_back(u);
    }
  }
  return true;
}

struct Residuals {
  const std::vector<DirectionSamples>* dirs;
  Values base;
  std::vector<int> free;
  bool operator()(double const* const* z, double* r) const {
    Values v = base;
    for (std::size_t i = 0; i < free.size(); ++i) v[static_cast<std::size_t>(free[i])] = from_search(free[i], z[0][i]);
    std::vector<std::vector<db::UniaxialPoint>> law;
    if (!law_at_samples(inplane_from_array(v), *dirs, law)) return false;
    std::size_t k = 0;
    for (std::size_t d = 0; d < dirs->size(); ++d) {
      const DirectionSamples& s = (*dirs)[d];
      for (std::size_t i = 0; i < s.points.size(); ++i) {
        r[k++] = (law[d][i].stress - s.points[i].stress) / s.stress_norm;
        r[k++] = (law[d][i].compression - s.points[i].compression) / s.compression_norm;
      }
    }
    return true;
  }
};

struct Run {
  bool ok = false;
  Values values{};
  double cost = std::numeric_limits<double>::infinity();
  int iterations = 0;
};

// Least squares over the parameters `free`, from `start`.
Run fit_from(const std::vector<DirectionSamples>& dirs, const Values& start, const std::vector<int>& free, int max_iterations) {
  Run run;
  {
    // A start where a sample has no free compression cannot be fitted from (and Ceres would
    // log its refusal): skip it.
    std::vector<std::vector<db::UniaxialPoint>> at_start;
    if (!law_at_samples(inplane_from_array(start), dirs, at_start)) return run;
  }
  std::size_t residual_count = 0;
  for (const auto& d : dirs) residual_count += 2 * d.points.size();
  auto* cost = new ceres::DynamicNumericDiffCostFunction<Residuals, ceres::CENTRAL>(new Residuals{&dirs, start, free});
  cost->AddParameterBlock(static_cast<int>(free.size()));
  cost->SetNumResiduals(static_cast<int>(residual_count));
  std::vector<double> z;
  for (const int k : free) z.push_back(to_search(k, start[static_cast<std::size_t>(k)]));
  ceres::Problem problem;
  problem.AddResidualBlock(cost, nullptr, z.data());
  for (std::size_t i = 0; i < free.size(); ++i) {
    const int k = free[i];
    const auto at = static_cast<int>(i);
    if (is_lockup_rate(k)) {
      problem.SetParameterLowerBound(z.data(), at, 0.0);
      problem.SetParameterUpperBound(z.data(), at, 40.0);
    } else if (is_lockup_share(k)) {
      problem.SetParameterLowerBound(z.data(), at, -3.0);
      problem.SetParameterUpperBound(z.data(), at, 3.0);
    } else if (k == k_kxy) {
      const double scale = 10.0 * std::max(std::abs(start[0]), std::abs(start[2]));
      problem.SetParameterLowerBound(z.data(), at, -scale);
      problem.SetParameterUpperBound(z.data(), at, scale);
    } else {
      problem.SetParameterLowerBound(z.data(), at, z[i] - 30.0);  // e^±30: far beyond any law
      problem.SetParameterUpperBound(z.data(), at, z[i] + 30.0);
    }
  }
  quiet_solver_warnings();
  ceres::Solver::Options so = least_squares_options(max_iterations, 1e-12, 1e-10, nullptr);
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  run.values = start;
  for (std::size_t i = 0; i < free.size(); ++i) run.values[static_cast<std::size_t>(free[i])] = from_search(free[i], z[i]);
  run.iterations = static_cast<int>(summary.iterations.size());
  run.ok = summary.IsSolutionUsable() && std::isfinite(summary.final_cost);
  run.cost = run.ok ? summary.final_cost : std::numeric_limits<double>::infinity();
  return run;
}

// Small-strain stiffnesses from the first nonzero sample of each direction (σ/s, c/s), split
// between K and the area terms as the shell stage's balanced start: half the coupling.
Values guess(const std::vector<db::DirectionTargets>& samples, double area_share) {
  std::map<db::Direction, std::pair<double, double>> slope;  // σ/s, c/s
  for (const auto& t : samples)
    for (const auto& p : t.stretch)
      if (p.stretch > 0.0) {
        slope[t.direction] = {p.stress / p.stretch, p.compression / p.stretch};
        break;
      }
  const auto of = [&](db::Direction d, db::Direction other) {
    return slope.count(d) ? slope[d] : slope.count(other) ? slope[other] : std::make_pair(1.0, 0.3);
  };
  const auto [sw, nw_raw] = of(db::Direction::weft, db::Direction::warp);
  const auto [sp, np_raw] = of(db::Direction::warp, db::Direction::weft);
  const double nw = std::clamp(nw_raw, 0.01, 0.9), np = std::clamp(np_raw, 0.01, 0.9);
  const double k11 = std::max(sw, 1e-9) / (1.0 - nw * np), k22 = std::max(sp, 1e-9) / (1.0 - nw * np);
  const double k12 = nw * k22;
  const double kn = 0.5 * area_share * k12;  // 2 kn of the coupling carried by the area terms
  InplaneParams p;
  p.kxx = std::max(k11 - 2.0 * kn, 1e-3 * k11);
  p.kyy = std::max(k22 - 2.0 * kn, 1e-3 * k22);
  p.kxy = std::max(k12 - 2.0 * kn, 1e-3 * k12);
  p.kn1 = p.kn2 = std::max(0.5 * kn, 1e-4 * std::sqrt(k11 * k22));
  p.kss = std::max(0.5 * (std::sqrt(k11 * k22) - k12), 0.05 * std::sqrt(k11 * k22));
  if (slope.count(db::Direction::bias)) p.kss = std::max(0.25 * slope[db::Direction::bias].first, 1e-3 * std::sqrt(k11 * k22));
  return to_array(p);
}

double yarn_metric(const std::vector<double>& sim, const std::vector<double>& ref, double floor = 0.0) {
  double top = floor, sum = 0.0;
  for (const double r : ref) top = std::max(top, std::abs(r));
  for (std::size_t i = 0; i < sim.size(); ++i) sum += std::abs(sim[i] - ref[i]);
  return sim.empty() || !(top > 0.0) ? k_nan : 100.0 * sum / static_cast<double>(sim.size()) / top;
}

double mean_of(const std::vector<double>& v) {
  double sum = 0.0;
  int n = 0;
  for (const double x : v)
    if (std::isfinite(x)) sum += x, ++n;
  return n > 0 ? sum / n : k_nan;
}

// Bending: Δσ_κ = 2 k_θ κ, least squares per direction; a slot without samples takes the mean
// of those with. Returns each fitted direction's misfit (the yarn metric).
std::vector<double> fit_bending_slopes(const std::vector<db::DirectionTargets>& samples,
                                       std::array<double, 3>& ktheta_out) {
  std::vector<double> misfit;
  std::array<std::optional<double>, 3> ktheta;
  for (const auto& t : samples) {
    if (t.bending.size() < 2) continue;
    double num = 0.0, den = 0.0;
    for (const auto& b : t.bending) num += b.stress * b.curvature, den += 2.0 * b.curvature * b.curvature;
    if (!(den > 0.0)) continue;
    const double k = num / den;
    ktheta[static_cast<std::size_t>(t.direction)] = k;
    std::vector<double> sim, ref;
    for (const auto& b : t.bending) sim.push_back(2.0 * k * b.curvature), ref.push_back(b.stress);
    misfit.push_back(yarn_metric(sim, ref));
  }
  double known = 0.0;
  int n_known = 0;
  for (const auto& k : ktheta)
    if (k) known += *k, ++n_known;
  for (std::size_t i = 0; i < 3; ++i)
    ktheta_out[i] = ktheta[i] ? *ktheta[i] : n_known > 0 ? known / n_known : 0.0;
  return misfit;
}

// The stiffening law's starts: the thesis fit's with a lock-up growth a tenth of the stiffness
// it adds to, rate 5 and no lateral share, and, when given, the start as it is.
std::vector<Values> lockup_starts(const Values& thesis, const std::optional<InplaneParams>& start, bool bias) {
  std::vector<Values> starts;
  Values from_thesis = thesis;
  from_thesis[6] = 0.1 * from_thesis[0], from_thesis[7] = 5.0;
  from_thesis[8] = 0.1 * from_thesis[2], from_thesis[9] = 5.0;
  from_thesis[10] = bias ? 0.1 * from_thesis[3] : 0.0, from_thesis[11] = bias ? 5.0 : 0.0;
  from_thesis[12] = from_thesis[13] = 0.0;
  starts.push_back(from_thesis);
  if (start) {
    Values given = to_array(*start);
    // A law without lock-up (or a thesis fit) gets the same small growth to start from.
    for (const int k : {6, 8, 10})
      if (!(given[static_cast<std::size_t>(k)] > 0.0)) given[static_cast<std::size_t>(k)] = from_thesis[static_cast<std::size_t>(k)], given[static_cast<std::size_t>(k + 1)] = 5.0;
    if (!bias) given[10] = given[11] = 0.0;
    starts.push_back(given);
  }
  return starts;
}

}  // namespace

UniformLawFit fit_law_to_samples(const std::vector<db::DirectionTargets>& samples, InplaneModel model,
                                 const std::optional<InplaneParams>& start) {
  UniformLawFit out;
  out.model = model;
  const std::vector<DirectionSamples> dirs = stretch_samples(samples);
  if (dirs.empty()) {
    out.message = "no direction has stretch samples";
    return out;
  }
  const bool bias = std::any_of(samples.begin(), samples.end(),
                                [](const db::DirectionTargets& t) { return t.direction == db::Direction::bias && t.stretch.size() >= 2; });
  // The thesis law: eq. 6.1's six (kss held without bias samples), from three splits of the
  // coupling between K and the area terms.
  // A direction without samples leaves its own stiffness (and lock-up) to the start: a law
  // fitted to weft samples alone sent kyy where the record's warp-straining clamps failed.
  const auto sampled = [&samples](db::Direction d) {
    return std::any_of(samples.begin(), samples.end(),
                       [d](const db::DirectionTargets& t) { return t.direction == d && t.stretch.size() >= 2; });
  };
  const bool weft = sampled(db::Direction::weft), warp = sampled(db::Direction::warp);
  std::vector<int> thesis_free{1, 4, 5};
  if (weft) thesis_free.insert(thesis_free.begin(), 0);
  else out.held.push_back("kxx: no weft samples (held at the start)");
  if (warp) thesis_free.insert(std::find(thesis_free.begin(), thesis_free.end(), 4), 2);
  else out.held.push_back("kyy: no warp samples (held at the start)");
  if (bias) thesis_free.insert(std::find(thesis_free.begin(), thesis_free.end(), 4), 3);
  else out.held.push_back("kss: no bias samples (held at the start)");
  Run best;
  std::vector<Values> starts;
  if (start) starts.push_back(to_array(*start));
  for (const double share : {0.5, 0.1, 0.9}) starts.push_back(guess(samples, share));
  for (Values s : starts) {
    for (int k = k_first_lockup_param; k < k_inplane_param_count; ++k) s[static_cast<std::size_t>(k)] = 0.0;
    const Run r = fit_from(dirs, s, thesis_free, 200);
    out.iterations += r.iterations;
    if (r.cost < best.cost) best = r;
  }
  if (model == InplaneModel::stiffening) {
    // The lock-up from the thesis fit (growth a tenth of the stiffness it adds to, rate 5, no
    // lateral share) and, when given, from the start as it is; every parameter then free.
    std::vector<int> all = thesis_free;
    if (weft) all.insert(all.end(), {6, 7, 12});
    if (warp) all.insert(all.end(), {8, 9, 13});
    if (bias) all.insert(all.end(), {10, 11});
    for (const Values& s : lockup_starts(best.values, start, bias)) {
      const Run r = fit_from(dirs, s, all, 300);
      out.iterations += r.iterations;
      if (r.cost < best.cost) best = r;
    }
  }
  if (!best.ok) {
    out.message = "no start led to a law that reproduces the samples (a uniaxial point did not converge)";
    return out;
  }
  out.params.inplane = inplane_from_array(best.values);
  // Misfit: the law against the samples, the yarn metric per direction.
  std::vector<std::vector<db::UniaxialPoint>> law;
  if (!law_at_samples(out.params.inplane, dirs, law)) {
    out.message = "the fitted law fails at a sample";
    return out;
  }
  std::vector<double> stress_pct, compression_pct, bending_pct;
  for (std::size_t d = 0; d < dirs.size(); ++d) {
    std::vector<double> s_law, s_ref, c_law, c_ref;
    for (std::size_t i = 0; i < dirs[d].points.size(); ++i) {
      s_law.push_back(law[d][i].stress), s_ref.push_back(dirs[d].points[i].stress);
      c_law.push_back(law[d][i].compression), c_ref.push_back(dirs[d].points[i].compression);
    }
    stress_pct.push_back(yarn_metric(s_law, s_ref));
    compression_pct.push_back(yarn_metric(c_law, c_ref, 1e-3));
  }
  bending_pct = fit_bending_slopes(samples, out.params.bending.ktheta);
  out.stress_misfit_pct = mean_of(stress_pct);
  out.compression_misfit_pct = mean_of(compression_pct);
  out.bending_misfit_pct = mean_of(bending_pct);
  out.ok = true;
  return out;
}

}  // namespace yarnfit::shell
