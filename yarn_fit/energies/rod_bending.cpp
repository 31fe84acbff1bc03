// Frame-free isotropic bending with rest curvature (thesis 6.6, SPEC §3 "Yarn").
//
// With a = x1 − x0, b = x2 − x1, p = |a||b|, q = a·b, n = a × b and χ = p + q, the squared
// curvature binormal is a function of p and q alone:
//   s = |κb|² = 4|n|²/χ² = 4 (p − q)/(p + q)     (|n|² = p² − q² = (p − q) χ),
// so its derivatives follow by the chain rule through p and q:
//   s_p = 8q/χ², s_q = −8p/χ², s_pp = −16q/χ³, s_qq = 16p/χ³, s_pq = 8(p − q)/χ³,
//   ∇p = (|b| â, |a| b̂), ∇q = (b, a),
//   ∇²p = [[|b|/|a| (I − ââᵀ), â b̂ᵀ], [b̂ âᵀ, |a|/|b| (I − b̂b̂ᵀ)]], ∇²q = [[0, I], [I, 0]].
// Near a straight corner s_p ∇p + s_q ∇q cancels to O(φ); that gradient is evaluated in the
// equivalent cancellation-free form ∇_a s = 8|b|/(χ²|a|) a × n, ∇_b s = −8|a|/(χ²|b|) b × n,
// and p − q as |n|²/χ. The Hessian terms are all O(1/L²) there, so it needs no such care.
//
// κ = sqrt(s + δ²) − δ, W = c (κ − κ̄)², c = kb/(L̄a + L̄b):
//   W_s = c (κ − κ̄)/r,  W_ss = c (δ + κ̄)/(2 r³),  r = sqrt(s + δ²),
// ∇W = W_s ∇s, ∇²W = W_ss ∇s ∇sᵀ + W_s ∇²s, mapped from (a, b) to (x0, x1, x2).
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "numerics/psd_projection.hpp"
#include "yarn_fit/energies/yarn_elements.hpp"

namespace yarnfit::yarn {

namespace {

constexpr double smoothing_delta = 1e-8;        // δ of κ = sqrt(|κb|² + δ²) − δ
constexpr double fold_tolerance = 1.0 - 1e-12;  // a·b ≤ −(1 − 1e-12)|a||b|: folded back

// The edges of a corner and the scalars its curvature depends on: p = |a||b|, q = a·b.
struct Corner {
  Vec3 a, b;
  double la, lb, p, q;
  Corner(const Vec3& x0, const Vec3& x1, const Vec3& x2)
      : a(x1 - x0), b(x2 - x1), la(a.norm()), lb(b.norm()), p(la * lb), q(a.dot(b)) {}
  // Zero-length edges and folded-back corners have no curvature.
  [[nodiscard]] bool degenerate() const {
    return !(la > 0.0) || !(lb > 0.0) || !(q > -fold_tolerance * p);
  }
};

}  // namespace

double corner_curvature(const Vec3& x0, const Vec3& x1, const Vec3& x2) {
  const Corner k(x0, x1, x2);
  if (k.degenerate()) return std::numeric_limits<double>::infinity();
  return 2.0 * k.a.cross(k.b).norm() / (k.p + k.q);
}

double bending_element(const Vec3& x0, const Vec3& x1, const Vec3& x2, double rest_length_a,
                       double rest_length_b, double rest_curvature, const RodBending& model,
                       Vec<9>* gradient, Mat<9>* hessian, bool project_psd) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  const Corner corner(x0, x1, x2);
  if (corner.degenerate()) return inf;
  const Vec3& a = corner.a;
  const Vec3& b = corner.b;
  const double la = corner.la, lb = corner.lb, p = corner.p, q = corner.q;
  const double rest_sum = rest_length_a + rest_length_b;
  if (!(rest_sum > 0.0)) return inf;

  const Vec3 n = a.cross(b);
  const double n2 = n.squaredNorm();
  const double chi = p + q;
  const double chi2 = chi * chi;
  const double s = 4.0 * n2 / chi2;
  const double delta = smoothing_delta;
  const double r = std::sqrt(s + delta * delta);
  const double kappa = s / (r + delta);  // = r − δ without cancellation
  const double c = model.kb / rest_sum;
  const double diff = kappa - rest_curvature;
  const double value = c * diff * diff;
  if (gradient == nullptr && hessian == nullptr) return value;

  // ∇s with respect to (a, b).
  const Vec3 ga = (8.0 * lb / (chi2 * la)) * a.cross(n);
  const Vec3 gb = (-8.0 * la / (chi2 * lb)) * b.cross(n);
  const double w_s = c * diff / r;

  if (gradient != nullptr) {
    gradient->segment<3>(0) = -w_s * ga;
    gradient->segment<3>(3) = w_s * (ga - gb);
    gradient->segment<3>(6) = w_s * gb;
  }
  if (hessian == nullptr) return value;

  const double chi3 = chi2 * chi;
  const double p_minus_q = n2 / chi;
  const double s_p = 8.0 * q / chi2;
  const double s_q = -8.0 * p / chi2;
  const double s_pp = -16.0 * q / chi3;
  const double s_qq = 16.0 * p / chi3;
  const double s_pq = 8.0 * p_minus_q / chi3;

  const Vec3 ah = a / la;
  const Vec3 bh = b / lb;
  Vec<6> grad_p;
  grad_p << lb * ah, la * bh;
  Vec<6> grad_q;
  grad_q << b, a;
  Vec<6> grad_s;
  grad_s << ga, gb;

  const Eigen::Matrix3d eye = Eigen::Matrix3d::Identity();
  Mat<6> hs = s_pp * (grad_p * grad_p.transpose()) + s_qq * (grad_q * grad_q.transpose()) +
              s_pq * (grad_p * grad_q.transpose() + grad_q * grad_p.transpose());
  hs.topLeftCorner<3, 3>() += (s_p * lb / la) * (eye - ah * ah.transpose());
  hs.bottomRightCorner<3, 3>() += (s_p * la / lb) * (eye - bh * bh.transpose());
  const Eigen::Matrix3d cross_block = s_p * (ah * bh.transpose()) + s_q * eye;
  hs.topRightCorner<3, 3>() += cross_block;
  hs.bottomLeftCorner<3, 3>() += cross_block.transpose();

  const double w_ss = c * (delta + rest_curvature) / (2.0 * r * r * r);
  const Mat<6> hw = w_ss * (grad_s * grad_s.transpose()) + w_s * hs;

  // (a, b) -> (x0, x1, x2): a = x1 − x0, b = x2 − x1.
  Eigen::Matrix<double, 6, 9> jac = Eigen::Matrix<double, 6, 9>::Zero();
  jac.block<3, 3>(0, 0) = -eye;
  jac.block<3, 3>(0, 3) = eye;
  jac.block<3, 3>(3, 3) = -eye;
  jac.block<3, 3>(3, 6) = eye;
  Mat<9> h9 = jac.transpose() * hw * jac;
  h9 = 0.5 * (h9 + h9.transpose()).eval();
  if (project_psd) numerics::project_psd<9>(h9);
  *hessian = h9;
  return value;
}

bool bending_element_sensitivity(const Vec3& x0, const Vec3& x1, const Vec3& x2, double rest_length_a,
                                 double rest_length_b, double rest_curvature, double& d_energy, Vec<9>& d_gradient) {
  // W = kb · (the element at kb = 1).
  d_energy = bending_element(x0, x1, x2, rest_length_a, rest_length_b, rest_curvature, RodBending{1.0}, &d_gradient,
                             nullptr, false);
  return std::isfinite(d_energy);
}

}  // namespace yarnfit::yarn

