#pragma once
// The lock-up term of the "stiffening" in-plane model: a function of one strain measure
// x ≥ 0 (a material-frame Green strain, SPEC §3 "Shell") whose curvature grows
// exponentially,
//
//   φ''(x) = l · (e^{bx} − 1) / b                        [N/m]
//   φ'(x)  = l · (e^{bx} − 1 − bx) / b²                  (stress, N/m)
//   φ(x)   = l · (e^{bx} − 1 − bx − b²x²/2) / b³          (energy density, J/m²)
//
// and φ = 0 for x ≤ 0. Why this form:
// * φ(0) = φ'(0) = φ''(0) = 0: the small-strain stiffness stays eq. 6.1's K, so the initial
//   slopes keep their meaning and the term adds only the toe-to-lock-up growth.
// * l is the growth of the tangent stiffness per unit strain at x = 0 (φ''' (0) = l) and b
//   how fast that growth accelerates: b → 0 gives the cubic φ = l x³/6 (a polynomial
//   stiffening), large b the exponential lock-up of a knit whose loops have jammed (the
//   Fung-type law of soft tissue, which also has a slack toe and a locked collagen network).
// * φ is convex and nondecreasing on x ≥ 0 for l, b ≥ 0, so composed with a Green strain
//   that is convex along a uniaxial path it stays convex there (lockup_curve.cpp).
// * Linear in l; b enters nonlinearly, and ∂φ/∂b, ∂φ'/∂b, ∂φ''/∂b are given for the fit's
//   exact sensitivities (rate_derivative).
//
// With h_n(y) = Σ_k y^k/(k+n)! (h_1 = (e^y − 1)/y, …) the three read φ = l x³ h_3(bx),
// φ' = l x² h_2(bx), φ'' = l x h_1(bx): smooth at b = 0 and free of cancellation when
// evaluated by the series for small y.

namespace yarnfit::shell {

struct LockupCurve {
  double l = 0.0;  // [N/m], ≥ 0
  double b = 0.0;  // [-], ≥ 0
  // When true the three functions return their derivatives with respect to b instead (the
  // per-parameter sensitivities of MembraneTerm); l stays a factor.
  bool rate_derivative = false;

  [[nodiscard]] bool active() const { return l != 0.0; }
  [[nodiscard]] double energy(double x) const;   // φ(x)
  [[nodiscard]] double stress(double x) const;   // φ'(x)
  [[nodiscard]] double tangent(double x) const;  // φ''(x)
  // φ'''(x) = l e^{bx} (x > 0): the tangent's slope, needed by the sensitivity law of a
  // lock-up's lateral share (InplaneMaterial::parameter_derivative).
  [[nodiscard]] double third(double x) const;
};

// h_n(y) (n = 1, 2, 3) and its derivative, for y ≥ 0; +∞ where e^y overflows.
double lockup_h(int n, double y);
double lockup_dh(int n, double y);

}  // namespace yarnfit::shell
