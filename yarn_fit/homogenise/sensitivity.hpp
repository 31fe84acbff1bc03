#pragma once
// Exact sensitivities of the homogenised read-outs at an equilibrium (issue 33: the yarn fit's
// residual Jacobian; the adjoint Gauss–Newton fits of seeds/001 applied to thesis 6.5.3).
//
// With Ψ(F, θ) = min_{C g = 0} E(g; F, θ) / A at a converged equilibrium g*, the first
// derivatives are the partial ones at fixed g (the envelope theorem: ∂Ψ/∂F = P, the coarse
// stress of 3.23), and the second follow from the implicit function theorem:
//
//   dg*/dq = −H_C⁻¹ E_gq,    d²Ψ/dq dq' = (E_qq' − E_gqᵀ H_C⁻¹ E_gq') / A,
//
// H_C⁻¹ the inverse of the exact Hessian on the constraint space C g = 0 (the KKT system of
// the constrained Newton step, solved by the Schur complement with the factorisation the
// solves keep), for q, q' among the entries of the in-plane F (x = F X + g) and the
// parameters θ. The read-outs are first derivatives of Ψ in F, so their parameter
// derivatives are the mixed block d²Ψ/dF dθ; the F–F block is the homogenised tangent.
// The rest shape (rest lengths, curvatures, period) is held: it is the fit's alternation that
// updates it between local runs (yarn_fit/fit).
//
// Free compression (readouts.hpp) accepts the first c whose orthogonal stress f = ∂Ψ/∂c lies
// within a band |f| ≤ τ; that c is piecewise constant in θ, and where Ψ is nearly flat in c the
// band is wide and the first c in it depends on where the search started. From the same solve,
// to first order: the root c* = c − f / f_c (f_c = d²Ψ/dc²), the band c* ± τ / f_c, and
// dc*/dθ = −(df/dθ) / f_c. free_compression_readout reports, as the tile's compression, the
// point of the band closest to a reference compression (the targets' c): the root itself when
// the reference lies outside the band on the far side, the reference when it lies inside (the
// tile is free of orthogonal stress to within τ there, and cannot tell those compressions
// apart), the band's edge otherwise; σ_s moves with it, σ' = σ_s + Ψ_sc (c' − c). Its
// derivative is dc*/dθ at the edge and 0 inside (the band's half-width τ / f_c also moves with
// θ, through d³Ψ/dc²dθ, which is not computed: an edge sample's derivative leaves it out). With
// τ = 0 the read-out is the root and its derivative exact. Where f_c ≤ 0 (no minimum) the
// accepted c is held, and where the band is wider than ±flat_band the tile is called flat.

#include <Eigen/Core>
#include <span>
#include <string>
#include <vector>

#include "yarn_fit/homogenise/readouts.hpp"
#include "yarn_fit/periodic/yarn_system.hpp"

namespace yarnfit::yarn {

struct EquilibriumSensitivity {
  bool ok = false;
  std::string message;  // why not (a curved χ, a Hessian not positive definite at the state)
  // d²Ψ/dvec(F)² [N/m], vec(F) = (F00, F10, F01, F11): the homogenised tangent at this state.
  Eigen::Matrix4d tangent = Eigen::Matrix4d::Zero();
  // 4 × k: dP/dθ_k = d²Ψ/dvec(F)dθ_k [N/m per unit of θ_k], with the equilibrium following θ.
  Eigen::MatrixXd stress_params;
  // n × 4: dg*/dvec(F), how the equilibrium moves with the coarse deformation (the predictor of
  // a continuation in s or c).
  Eigen::MatrixXd state_tangent;
  double shift = 0.0;  // relative shift the factorisation needed (the rigid translations' null space)
};

// At a converged equilibrium `g` of `system` (κ = 0), for the parameters `wanted`. Uses and
// refreshes the system's kept factorisation (one exact Hessian assembly and factorisation).
EquilibriumSensitivity equilibrium_sensitivity(const YarnSystem& system, const Eigen::VectorXd& g,
                                               std::span<const YarnParam> wanted);

// ∂/∂s and ∂/∂c of the coarse deformation χ as weights on vec(F):
// F = (1+s) u uᵀ + (1−c) v vᵀ gives vec(u uᵀ) and −vec(v vᵀ).
Eigen::Vector4d stretch_weights(const CoarseDeformation& chi);
Eigen::Vector4d compression_weights(const CoarseDeformation& chi);

// One read-out of a sample and its parameter derivatives.
struct SensitiveReadout {
  double compression = 0.0;  // c: the sample's, or (free compression) the band's point nearest the reference
  double stress_s = 0.0;     // σ_s at that c [N/m]
  Eigen::VectorXd d_compression;  // dc/dθ (0 at a fixed c, inside the band, or where c was held)
  Eigen::VectorXd d_stress;       // dσ_s/dθ [N/m per unit of θ]
  double stress_cc = 0.0;  // f_c = d²Ψ/dc² [N/m]
  double stress_sc = 0.0;  // d²Ψ/ds dc [N/m]
  // Free compression only.
  double root = 0.0;        // c*, to first order
  double half_width = 0.0;  // of the band τ / f_c (+inf where f_c ≤ 0)
  bool in_band = false;     // the reference lies inside the band: c is the reference
  bool flat = false;        // the band is wider than ±flat_band (Ψ nearly flat in c)
  bool held = false;        // f_c ≤ 0: no minimum here, the accepted c is kept
};

// The zero-orthogonal-stress compression by Newton's method on f = ∂Ψ/∂c with the exact
// f_c = d²Ψ/dc² of each solve, each next solve starting from the predicted state
// g + (dg*/dc) Δc: the search follows the branch of equilibria it starts on, in about two solves,
// where the bracketed search (readouts.hpp) restarts every trial from its anchor. It accepts the
// first c with |f| ≤ stress_tolerance, or, with a tolerance of 0, a Newton step below the c
// tolerance; steps are at most initial_step long. Where a solve fails or f_c ≤ 0 (no minimum
// nearby) it falls back to the bracketed search from the anchor. The sensitivity of the accepted
// state (for `wanted`) comes with it. `g` carries the start in and the accepted state out.
struct SensitiveSample {
  Sample sample;
  EquilibriumSensitivity sensitivity;
  bool fell_back = false;  // the bracketed search found it
};
SensitiveSample solve_free_compression_newton(YarnSystem& system, CoarseDeformation chi, Eigen::VectorXd& g,
                                              const CompressionOptions& compression,
                                              const EquilibriumOptions& options, std::span<const YarnParam> wanted);

// The read-out at the sample's own χ (fixed c): σ_s and dσ_s/dθ = dP/dθ along s.
SensitiveReadout fixed_compression_readout(const Sample& sample, const EquilibriumSensitivity& sensitivity);

struct BandOptions {
  double tolerance = 0.0;   // τ [N/m]: the band the search accepted (CompressionOptions::stress_tolerance)
  double reference = 0.0;   // the compression the band's nearest point is taken to (the targets')
  double flat_band = 0.05;  // half-widths above this are reported flat
};

// A free-compression sample (solve_free_compression) read as described above.
SensitiveReadout free_compression_readout(const Sample& sample, const EquilibriumSensitivity& sensitivity,
                                          const BandOptions& band);

}  // namespace yarnfit::yarn
