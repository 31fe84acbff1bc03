#include "yarn_fit/fit/parameter_profile.hpp"

#include <omp.h>

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "numerics/util/clock.hpp"
#include "numerics/util/error.hpp"
#include "numerics/util/non_finite.hpp"

namespace yarnfit::yarn {

namespace {

using numerics::k_inf;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

std::vector<GaussNewtonRange> gauss_newton_ranges(const Eigen::MatrixXd& jtj, double g) {
  // Gauss–Newton model g(log p_fit + Δ) ≈ g + 2 r0ᵀJΔ + ΔᵀJᵀJΔ around a minimum (r0ᵀJ ≈ 0):
  // the smallest rise for Δ_i = δ with the others free is δ² / [(JᵀJ)⁻¹]_ii, and with the
  // others fixed δ² (JᵀJ)_ii. The range is the δ = log f at which that rise equals g.
  const auto dim = jtj.cols();
  const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(jtj);
  const Eigen::MatrixXd inverse = cod.pseudoInverse();
  // Where JᵀJ is singular, a parameter with a component along its null space can move
  // without any change of the residuals, however the others are set.
  const Eigen::MatrixXd null_projector = Eigen::MatrixXd::Identity(dim, dim) - inverse * jtj;
  std::vector<GaussNewtonRange> out(static_cast<std::size_t>(dim));
  for (Eigen::Index i = 0; i < dim; ++i) {
    auto& r = out[static_cast<std::size_t>(i)];
    const double alone = jtj(i, i);
    r.alone = alone > 0.0 ? std::exp(std::sqrt(g / alone)) : k_inf;
    const double var = inverse(i, i);
    const bool free = cod.rank() < dim && std::abs(null_projector(i, i)) > 1e-6;
    r.refitted = free || !(var > 0.0) ? k_inf : std::exp(std::sqrt(g * var));
  }
  return out;
}

ParameterProfile profile_parameters(const YarnObjective& objective, const swarm::ParameterSpace& space,
                                    const Eigen::VectorXd& x_fit, const ObjectiveResult& at_fit,
                                    const std::function<yarn::YarnParams(const Eigen::VectorXd&)>& to_params,
                                    double step, int threads) {
  if (!(step > 0.0 && step < 1.0)) throw Error(ErrorCategory::input, "parameter profile: step must be in (0, 1)");
  if (x_fit.size() != space.dimension())
    throw Error(ErrorCategory::input, "parameter profile: the fitted point has the wrong size");
  const auto start = numerics::Clock::now();
  ParameterProfile out;
  out.step = step;
  out.g_fit = at_fit.value;
  if (!at_fit.ok || at_fit.lower_bound) {
    out.message = "the fit's own evaluation is not complete";
    return out;
  }
  const int dim = space.dimension();
  // Evaluation 2i: p_i / (1 + step); 2i + 1: p_i × (1 + step), symmetric in log p_i. Outside
  // the search bounds is allowed: the profile is about the data, not the search box.
  std::vector<ObjectiveResult> sides(static_cast<std::size_t>(2 * dim));
  const double factor = 1.0 + step;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads > 0 ? threads : omp_get_max_threads())
  for (int k = 0; k < 2 * dim; ++k) {
    Eigen::VectorXd x = x_fit;
    x[k / 2] *= (k % 2 == 0) ? 1.0 / factor : factor;
    sides[static_cast<std::size_t>(k)] = objective.evaluate(to_params(x));
  }
  out.evaluations = 2 * dim;

  // One-sided differences both ways, and JᵀJ as the mean of their two Gram matrices. Central
  // differences cancel where the residuals have a kink at the fit (ε̄s, where the yarns leave
  // the soft phase, moved both ways gave the same residuals and g 9 % higher on either side:
  // a central J of nearly 0 and a range of 1e19); each one-sided secant sees the rise.
  const Eigen::VectorXd r0 = residual_vector(at_fit);
  const double log_step = std::log(1.0 + step);
  Eigen::MatrixXd forward(r0.size(), dim), backward(r0.size(), dim);
  std::vector<bool> complete(static_cast<std::size_t>(dim), true);
  for (int i = 0; i < dim; ++i) {
    const ObjectiveResult& lo = sides[static_cast<std::size_t>(2 * i)];
    const ObjectiveResult& hi = sides[static_cast<std::size_t>(2 * i + 1)];
    ParameterProfileEntry e;
    e.name = space.parameter(i).name;
    e.value = x_fit[i];
    e.g_lower = lo.ok ? lo.value : k_inf;
    e.g_upper = hi.ok ? hi.value : k_inf;
    const Eigen::VectorXd r_lo = lo.ok ? residual_vector(lo) : Eigen::VectorXd();
    const Eigen::VectorXd r_hi = hi.ok ? residual_vector(hi) : Eigen::VectorXd();
    if (r_lo.size() != r0.size() || r_hi.size() != r0.size()) {
      complete[static_cast<std::size_t>(i)] = false;
      forward.col(i).setZero();
      backward.col(i).setZero();
      if (!out.message.empty()) out.message += "; ";
      out.message += e.name + ": " + (!lo.ok ? lo.message : !hi.ok ? hi.message : std::string("residuals differ"));
    } else {
      forward.col(i) = (r_hi - r0) / log_step;
      backward.col(i) = (r0 - r_lo) / log_step;
    }
    out.entries.push_back(std::move(e));
  }

  const Eigen::MatrixXd jtj = 0.5 * (forward.transpose() * forward + backward.transpose() * backward);
  const std::vector<GaussNewtonRange> ranges = gauss_newton_ranges(jtj, out.g_fit);
  for (int i = 0; i < dim; ++i) {
    ParameterProfileEntry& e = out.entries[static_cast<std::size_t>(i)];
    const bool ok = complete[static_cast<std::size_t>(i)];
    e.range_factor = ok ? ranges[static_cast<std::size_t>(i)].refitted : kNaN;
    e.range_alone_factor = ok ? ranges[static_cast<std::size_t>(i)].alone : kNaN;
  }
  out.computed = true;
  out.seconds = numerics::seconds_since(start);
  return out;
}

ParameterProfile profile_from_jacobian(const swarm::ParameterSpace& space, const Eigen::VectorXd& x_fit,
                                       const Eigen::VectorXd& residuals, const Eigen::MatrixXd& jacobian_log,
                                       double step) {
  if (!(step > 0.0 && step < 1.0)) throw Error(ErrorCategory::input, "parameter profile: step must be in (0, 1)");
  if (jacobian_log.cols() != space.dimension() || jacobian_log.rows() != residuals.size())
    throw Error(ErrorCategory::input, "parameter profile: the Jacobian does not match the space and the residuals");
  ParameterProfile out;
  out.from_jacobian = true;
  out.step = step;
  out.g_fit = residuals.squaredNorm();
  const double log_step = std::log(1.0 + step);
  const std::vector<GaussNewtonRange> ranges =
      gauss_newton_ranges(jacobian_log.transpose() * jacobian_log, out.g_fit);
  for (int i = 0; i < space.dimension(); ++i) {
    ParameterProfileEntry e;
    e.name = space.parameter(i).name;
    e.value = x_fit[i];
    e.g_lower = (residuals - log_step * jacobian_log.col(i)).squaredNorm();
    e.g_upper = (residuals + log_step * jacobian_log.col(i)).squaredNorm();
    e.range_factor = ranges[static_cast<std::size_t>(i)].refitted;
    e.range_alone_factor = ranges[static_cast<std::size_t>(i)].alone;
    out.entries.push_back(std::move(e));
  }
  out.computed = true;
  return out;
}

results::Identifiability to_record(const ParameterProfile& p) {
  results::Identifiability out{p.computed, p.from_jacobian ? "jacobian" : "evaluations", p.message, p.step, p.g_fit,
                               {},         p.evaluations,                                 p.seconds};
  // An unbounded range (+inf: the residuals do not pin it) is written null with "free".
  for (const auto& e : p.entries)
    out.parameters[e.name] = {e.value,          e.g_lower,
                              e.g_upper,        e.range_factor,
                              e.range_alone_factor, std::isinf(e.range_factor),
                              std::isinf(e.range_alone_factor)};
  return out;
}

}  // namespace yarnfit::yarn
