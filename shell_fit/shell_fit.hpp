#pragma once
// shell_fit — thin-shell model of a fabric swatch, fitted by simulation in the loop.
//
// Planned contents (SPEC §1 step 2, §3 "Shell"; thesis 6.3):
//   energies/   membrane (anisotropic StVK, eq. 6.1), area term kn1 (J−1)² + kn2 log²J,
//               edge bending k_θ κ² with κ = 3θ/H (eq. 6.4), gravity
//   scenes/     clamped stretch test (2-D membrane), pear-loop test (3-D)
//   solver/     static Newton with sparse direct solve, line search, indefiniteness guard
//   fit/        Ceres least squares in log-stiffness space, residuals of eq. 6.2
//   targets/    zero-orthogonal-stress uniaxial curves {s, c, σ_s} and {κ, σ_κ} (eq. 6.3)
// This module has no code yet; the target exists so the dependency graph is fixed.
namespace yarnfit::shell {}
