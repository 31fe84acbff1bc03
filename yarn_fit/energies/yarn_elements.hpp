#pragma once
// Element energies of the yarn model (thesis 6.4; SPEC §3 "Yarn"), each with value, gradient
// and Hessian. An element sees only the 3-D positions of its own vertices; the periodic
// system (yarn_fit/periodic) places vertices, sums elements and maps derivatives back to
// the free degrees of freedom. All quantities are SI: positions in m, energies in J.
//
// Hessians can be projected onto the PSD cone per element (`project_psd`), which the Newton
// solver needs far from equilibrium. Where an analytic projection exists (springs and
// point-pair contacts: clamp the along-axis and transverse curvatures at 0) it is used,
// because it is exact and costs nothing; the bending element uses an eigen-decomposition.
//
// Outputs passed as non-null pointers are overwritten (not accumulated). Every function
// returns +infinity (never NaN) where the energy is undefined (two contact points at
// distance 0, a zero-length edge); gradient and Hessian are then unspecified.

#include <Eigen/Core>

namespace yarnfit::yarn {

using Vec3 = Eigen::Vector3d;
template <int N>
using Vec = Eigen::Matrix<double, N, 1>;
template <int N>
using Mat = Eigen::Matrix<double, N, N>;

// ---------------------------------------------------------------------------------------
// Biphasic stretch (6.5). Strain ε = ‖x1 − x0‖ / L̄ − 1. Energy of an edge of rest length
// L̄: W = L̄ · w(ε) with
//   w(ε) = ½ ks2 ε²                                    ε ≤ 0
//        = ½ ks1 ε²                                    0 ≤ ε ≤ ε̄s
//        = ½ (ks2 (ε − ε̄s)² + ks1 ε̄s (2ε − ε̄s))       ε̄s ≤ ε
// w is C¹ (w' continuous at 0 and ε̄s); w'' jumps there (ks2 | ks1 | ks2).
struct BiphasicStretch {
  double ks1 = 0.0;    // low-stretch stiffness [N]
  double ks2 = 0.0;    // compression and high-stretch stiffness [N]
  double eps_s = 0.0;  // onset strain of the stiff phase ε̄s [-]

  [[nodiscard]] double w(double strain) const;    // [N] (energy per rest length)
  [[nodiscard]] double dw(double strain) const;   // dw/dε [N]: the edge tension
  [[nodiscard]] double d2w(double strain) const;  // d²w/dε² [N] (one-sided: the right limit)
};

// Edge element on (x0, x1): DOF order x0, x1. +inf for a zero-length edge (no direction) or a
// rest length ≤ 0. Projection clamps the axial (w''/L̄) and transverse (w'/l) curvatures at 0.
double stretch_element(const Vec3& x0, const Vec3& x1, double rest_length,
                       const BiphasicStretch& model, Vec<6>* gradient, Mat<6>* hessian,
                       bool project_psd);

// ---------------------------------------------------------------------------------------
// Isotropic bending with rest curvature (6.6) at the vertex x1 between edges a = x1 − x0 and
// b = x2 − x1. Bergou et al.'s integrated curvature binormal κb = 2 a × b / (|a||b| + a·b)
// has magnitude κ = 2 tan(φ/2), φ the turning angle. With twist off (the default, SPEC §3)
// there is no material frame to hold the direction of a rest curvature vector; the energy is
// the frame-free limit of (6.6), where the frame turns freely about the tangent:
//   W = kb / (L̄a + L̄b) · (κ − κ̄)²,   κ̄ ≥ 0 the rest curvature magnitude.
// For κ̄ = 0 this is exactly (6.6). For κ̄ > 0 the magnitude |κb| has a cone at κb = 0; the
// element uses κ = sqrt(|κb|² + δ²) − δ with δ = 1e-8 so value, gradient and Hessian stay
// finite and smooth through a straight configuration (an O(δ) change in energy).
struct RodBending {
  double kb = 0.0;  // bending stiffness [N·m²]
};

// DOF order x0, x1, x2. Returns +inf when a or b has zero length or φ = π (folded back:
// a·b ≤ −(1 − 1e-12)|a||b|), or L̄a + L̄b ≤ 0.
double bending_element(const Vec3& x0, const Vec3& x1, const Vec3& x2, double rest_length_a,
                       double rest_length_b, double rest_curvature, const RodBending& model,
                       Vec<9>* gradient, Mat<9>* hessian, bool project_psd);

// Integrated curvature magnitude κ = |κb| = 2 tan(φ/2) of the corner x0-x1-x2 (no smoothing),
// used to reset rest curvatures (rest-shape heuristic) and by tests. +inf where
// bending_element is (a zero-length edge, a corner folded back).
double corner_curvature(const Vec3& x0, const Vec3& x1, const Vec3& x2);

// ---------------------------------------------------------------------------------------
// Barrier of Li et al. 2020 in relative distance (6.7): f(x) = −(x − 1)² log x for
// 0 < x < 1, 0 for x ≥ 1, +inf for x ≤ 0. The contact energy density uses f(x)² with
// x = D / (2R): a C² onset at D = 2R (f² ~ (1 − x)⁶) and a barrier at D → 0.
class Barrier {
 public:
  // f(x)² and its first two derivatives with respect to x; for x ≤ 0 their limits at 0⁺
  // (+inf, −inf, +inf), for x ≥ 1 exactly 0.
  static double value(double x);
  static double first(double x);
  static double second(double x);
};

// The two-barrier contact law between two centreline points at distance D:
//   e(D) = kc1 f(D / 2R1)² + kc2 f(D / 2R2)²        [N/m: energy per rest length²]
// The element multiplies by L̄a L̄b and integrates over both segments.
struct TwoBarrierContact {
  double kc1 = 0.0;  // soft barrier stiffness [N/m]
  double r1 = 0.0;   // soft barrier radius R1 [m]
  double kc2 = 0.0;  // stiff barrier stiffness [N/m]
  double r2 = 0.0;   // stiff barrier radius R2 [m]

  // A barrier with R ≤ 0 or kc = 0 is absent. e, de, d2e at D ≤ 0: +inf, −inf, +inf.
  [[nodiscard]] double cutoff_distance() const;  // 2 max(R1, R2): e(D) = 0 beyond it
  [[nodiscard]] double e(double distance) const;
  [[nodiscard]] double de(double distance) const;
  [[nodiscard]] double d2e(double distance) const;
};

// Segment pair a = (a0, a1), b = (b0, b1) (6.7):
//   W = L̄a L̄b Σ_i Σ_j w_i w_j e(|xa(s_i) − xb(s_j)|),
// Simpson's rule on both segments (s ∈ {0, ½, 1}, w ∈ {1/6, 4/6, 1/6}), xa(s) the linear
// interpolation. DOF order a0, a1, b0, b1. Returns 0 with zero outputs when the segments'
// bounding boxes are farther apart than the cutoff (the broad-phase test at element level);
// +inf when two quadrature points coincide (D = 0).
double contact_element(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1,
                       double rest_length_a, double rest_length_b,
                       const TwoBarrierContact& model, Vec<12>* gradient, Mat<12>* hessian,
                       bool project_psd);

// ---------------------------------------------------------------------------------------
// Parameter derivatives (the fit's sensitivities, thesis 6.5.3 with exact Jacobians): at fixed
// positions, ∂W/∂θ and ∂(∇ₓW)/∂θ for the parameters θ an element depends on, in the DOF order
// of the element above. Each returns false where the element itself is undefined (+inf);
// outputs are overwritten.

// θ = (ks1, ε̄s, ks2). w is piecewise in ε, so these are the derivatives of the branch ε lies
// in (∂w'/∂ε̄s jumps from 0 to ks1 − ks2 at ε = ε̄s, as w'' does).
bool stretch_element_sensitivity(const Vec3& x0, const Vec3& x1, double rest_length, const BiphasicStretch& model,
                                 Vec<3>& d_energy, Eigen::Matrix<double, 6, 3>& d_gradient);

// θ = (kb): W is linear in kb.
bool bending_element_sensitivity(const Vec3& x0, const Vec3& x1, const Vec3& x2, double rest_length_a,
                                 double rest_length_b, double rest_curvature, double& d_energy, Vec<9>& d_gradient);

// θ = (kc1, R1, kc2, R2). With x = D/2R, ∂e/∂R = −kc g'(x) x/R and
// ∂e'/∂R = −kc (x g''(x) + g'(x)) / (2R²), e' = de/dD.
bool contact_element_sensitivity(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1,
                                 double rest_length_a, double rest_length_b, const TwoBarrierContact& model,
                                 Vec<4>& d_energy, Eigen::Matrix<double, 12, 4>& d_gradient);

}  // namespace yarnfit::yarn
