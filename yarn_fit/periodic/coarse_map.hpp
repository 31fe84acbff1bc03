#pragma once
// Uniform coarse deformation χ = (s, c, κ, U) of a periodic tile (thesis 6.5.1, 3.2.2, A.1)
// and the map that places yarn vertices:
//
//   x = Φ(X, h) + R(X) g,
//
// with X the in-plane reference position, h the height above the mid-plane and g the
// vertex's fluctuation in the co-rotated frame (the unrotated displacement of thesis 3.3.3,
// "alternative implementation"). Periodic copies of a vertex share g, so (R^T ũ)⁺ = (R^T ũ)⁻
// (3.21) holds by construction.
//
//  * κ = 0 (in-plane): Φ = (F X, h), R = I, F = (1+s) u uᵀ + (1−c) v vᵀ (6.3).
//  * κ ≠ 0 (cylindrical bend about the axis v, II = U diag(κ, 0) Uᵀ in reference
//    coordinates): with a = u·X, b = v·X and θ = κ a / (1+s) the angle turned,
//      Φ = (1−c) b v + (1+s) a [sinc θ · u + (θ/2) sinc²(θ/2) · e_z] + h n,
//      n = cos θ e_z − sin θ u,   R = rotation by θ in the (u, e_z) plane.
//    This is the exact singly-curved solution of (3.14)–(3.18) (A.1, "Analytic Solution"):
//    ∇φ = R S̄ with S̄ = F, and it reduces to the affine map as κ → 0 (the sinc forms are
//    evaluated with series near 0). The deformed mid-surface curvature is κ / (1+s)².
//
// A shift by a period is a rigid motion of the map (translation for κ = 0, screw motion
// about the cylinder axis otherwise), which is why each periodic element can be evaluated in
// one canonical copy.

#include <Eigen/Core>

namespace yarnfit::yarn {

struct CoarseDeformation {
  double stretch = 0.0;      // s: stretch along u (0.2 = 20 %)
  double compression = 0.0;  // c: contraction along v (w = (1 − c) w̄)
  double curvature = 0.0;    // κ [1/m]: normal curvature along u, in reference coordinates
  double angle = 0.0;        // direction of u from the weft (x) axis [rad]

  [[nodiscard]] Eigen::Vector2d u() const;
  [[nodiscard]] Eigen::Vector2d v() const;
  [[nodiscard]] Eigen::Matrix2d deformation_gradient() const;  // F
  [[nodiscard]] bool curved() const { return curvature != 0.0; }
};

// Standard directions of the material frame (weft = x): weft 0, bias π/4, warp π/2.
double weft_angle();
double bias_angle();
double warp_angle();

class CoarseMap {
 public:
  explicit CoarseMap(const CoarseDeformation& chi);
  // Φ(X, h) and R(X) for a reference point (X1, X2, h).
  void place(const Eigen::Vector3d& reference, Eigen::Vector3d& base,
             Eigen::Matrix3d& rotation) const;
  [[nodiscard]] const CoarseDeformation& deformation() const { return m_chi; }

 private:
  CoarseDeformation m_chi;
  Eigen::Matrix2d m_f;
  Eigen::Vector3d m_u3, m_v3;
};

// sin(x)/x, robust at 0.
double sinc(double x);

}  // namespace yarnfit::yarn
