#include "yarn_fit/homogenise/sensitivity.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>

namespace yarnfit::yarn {

Eigen::Vector4d stretch_weights(const CoarseDeformation& chi) {
  const Eigen::Vector2d u = chi.u();
  const Eigen::Matrix2d m = u * u.transpose();
  return {m(0, 0), m(1, 0), m(0, 1), m(1, 1)};
}

Eigen::Vector4d compression_weights(const CoarseDeformation& chi) {
  const Eigen::Vector2d v = chi.v();
  const Eigen::Matrix2d m = v * v.transpose();
  return {-m(0, 0), -m(1, 0), -m(0, 1), -m(1, 1)};
}


namespace {

// Z with H Z + Cᵀ Λ = B, C Z = 0, for H positive definite on C z = 0 only: H itself is singular
// along the rigid translations (which the zero mean removes), and a yarn in tension can lower
// its energy by sliding along itself with the whole tile moving against it, which only the
// constraints forbid (stockinette, warp 30 %: an eigenvalue of H of −0.78 against 3.2 on the
// constraint space). So H + σI is factorised with the smallest shift σ = shift · d̄ that makes
// it positive definite, and the shift is taken out again by the fixed-point iteration
//   Z ← S(B + σ Z),   S the constrained solve with H + σI,
// whose fixed point solves the unshifted system and which contracts by σ / (λ_min + σ), λ_min
// the smallest curvature on the constraint space; it diverges only at an unstable state.
bool constrained_solve(numerics::ShiftedLdlt& factor, const Eigen::MatrixXd& c, const Eigen::MatrixXd& rhs,
                       Eigen::MatrixXd& z, double& shift) {
  bool factorised = false;
  for (shift = 1e-12; shift <= 1e-1 && !factorised; shift *= 10.0) factorised = factor.factorise(shift);
  shift /= 10.0;
  if (!factorised) return false;
  const double sigma = shift * factor.mean_diagonal();
  const numerics::ConstrainedSolver solver(factor, c);
  z = solver.solve(rhs);
  // Converged when an iteration changes Z by 1e-10 of its size, or when the changes stop
  // shrinking at the round-off of the solve (below 1e-7 of its size); an iteration that grows
  // a change above that means the constrained Hessian is not positive definite.
  double last_change = std::numeric_limits<double>::infinity();
  for (int it = 0; it < 200 && z.allFinite(); ++it) {
    const Eigen::MatrixXd next = solver.solve(rhs + sigma * z);
    const double change = (next - z).cwiseAbs().maxCoeff();
    const double size = next.cwiseAbs().maxCoeff();
    z = next;
    if (change <= 1e-10 * size) return z.allFinite();
    if (change >= last_change) return change <= 1e-7 * size && z.allFinite();
    last_change = change;
  }
  return false;
}

}  // namespace

EquilibriumSensitivity equilibrium_sensitivity(const YarnSystem& system, const Eigen::VectorXd& g,
                                               std::span<const YarnParam> wanted) {
  EquilibriumSensitivity out;
  if (system.deformation().curved()) {
    out.message = "sensitivities need an in-plane coarse deformation (kappa = 0)";
    return out;
  }
  const int n = system.dof_count();
  const AffineDerivatives affine = system.affine_derivatives(g);
  const ParameterDerivatives params = system.parameter_derivatives(g, wanted);

  numerics::Triplets lower;
  system.hessian(g, lower, /*project_psd=*/false, /*lower_only=*/true);
  numerics::ShiftedLdlt& factor = system.factorisation();
  factor.assemble(n, lower);
  const int k = static_cast<int>(wanted.size());
  Eigen::MatrixXd rhs(n, 4 + k);
  rhs << affine.gradient, params.gradient;
  Eigen::MatrixXd z;
  if (!constrained_solve(factor, system.constraints(), rhs, z, out.shift)) {
    out.message = "the Hessian at the equilibrium is not positive definite on the constraint space (an unstable "
                  "state): no sensitivities";
    return out;
  }
  const double area = system.area();
  const Eigen::Matrix4d tangent = (affine.hessian - affine.gradient.transpose() * z.leftCols<4>()) / area;
  out.tangent = 0.5 * (tangent + tangent.transpose());
  out.stress_params = (params.affine - affine.gradient.transpose() * z.rightCols(k)) / area;
  out.state_tangent = -z.leftCols<4>();
  out.ok = true;
  return out;
}

SensitiveSample solve_free_compression_newton(YarnSystem& system, CoarseDeformation chi, Eigen::VectorXd& g,
                                              const CompressionOptions& co, const EquilibriumOptions& options,
                                              std::span<const YarnParam> wanted) {
  SensitiveSample out;
  Eigen::VectorXd state = g, converged = g;
  double c = std::clamp(co.initial_guess, co.lower, co.upper);
  int solves = 0, iterations = 0;
  for (int it = 0; it < co.max_evaluations; ++it) {
    chi.compression = c;
    Sample s = simulate_sample(system, chi, state, options);
    ++solves;
    iterations += s.newton_iterations;
    if (!s.ok && it > 0 && s.last_solve.status == numerics::NewtonStatus::invalid_start) {
      state = converged;  // the predicted state crossed a barrier: from the last equilibrium instead
      s = simulate_sample(system, chi, state, options);
      ++solves;
      iterations += s.newton_iterations;
    }
    if (!s.ok) break;
    converged = state;
    EquilibriumSensitivity sens = equilibrium_sensitivity(system, state, wanted);
    if (!sens.ok) break;
    const Eigen::Vector4d wc = compression_weights(chi);
    const double fc = wc.dot(sens.tangent * wc);
    const double dc = fc > 0.0 ? std::clamp(-s.stress_c / fc, -co.initial_step, co.initial_step) : 0.0;
    const bool accepted = co.stress_tolerance > 0.0 ? std::abs(s.stress_c) <= co.stress_tolerance
                                                    : fc > 0.0 && std::abs(dc) < co.tolerance;
    if (accepted) {
      s.solves = solves;
      s.newton_iterations = iterations;
      s.stress_c_slope = fc;
      out.sample = std::move(s);
      out.sensitivity = std::move(sens);
      g = state;
      return out;
    }
    const double next = std::clamp(c + dc, co.lower, co.upper);
    if (!(fc > 0.0) || next == c) break;  // no minimum ahead along c: bracket instead
    state += sens.state_tangent * wc * (next - c);
    c = next;
  }
  // The bracketed search from the caller's state.
  out.fell_back = true;
  Eigen::VectorXd anchor = g;
  out.sample = solve_free_compression(system, chi, anchor, co, options);
  out.sample.solves += solves;
  out.sample.newton_iterations += iterations;
  if (!out.sample.ok) return out;
  chi.compression = out.sample.chi.compression;
  if (system.deformation().compression != chi.compression) {
    system.set_deformation(out.sample.chi);
    system.rebuild_contacts(anchor);
  }
  out.sensitivity = equilibrium_sensitivity(system, anchor, wanted);
  g = anchor;
  return out;
}

SensitiveReadout fixed_compression_readout(const Sample& sample, const EquilibriumSensitivity& sensitivity) {
  SensitiveReadout r;
  const Eigen::Vector4d ws = stretch_weights(sample.chi), wc = compression_weights(sample.chi);
  r.compression = sample.chi.compression;
  r.stress_s = sample.stress_s;
  r.stress_cc = wc.dot(sensitivity.tangent * wc);
  r.stress_sc = ws.dot(sensitivity.tangent * wc);
  r.d_stress = sensitivity.stress_params.transpose() * ws;
  r.d_compression = Eigen::VectorXd::Zero(r.d_stress.size());
  return r;
}

SensitiveReadout free_compression_readout(const Sample& sample, const EquilibriumSensitivity& sensitivity,
                                          const BandOptions& band) {
  SensitiveReadout r = fixed_compression_readout(sample, sensitivity);
  r.root = r.compression;
  if (!(r.stress_cc > 0.0)) {
    r.held = true;
    r.half_width = std::numeric_limits<double>::infinity();
    return r;
  }
  const Eigen::Vector4d wc = compression_weights(sample.chi);
  const Eigen::VectorXd d_root = -(sensitivity.stress_params.transpose() * wc) / r.stress_cc;
  r.root = sample.chi.compression - sample.stress_c / r.stress_cc;
  r.half_width = std::max(band.tolerance, 0.0) / r.stress_cc;
  r.flat = r.half_width > band.flat_band;
  const double nearest = std::clamp(band.reference, r.root - r.half_width, r.root + r.half_width);
  r.in_band = r.half_width > 0.0 && nearest == band.reference;
  if (!r.in_band) r.d_compression = d_root;
  r.stress_s += r.stress_sc * (nearest - sample.chi.compression);
  r.compression = nearest;
  r.d_stress += r.stress_sc * r.d_compression;
  return r;
}

}  // namespace yarnfit::yarn
