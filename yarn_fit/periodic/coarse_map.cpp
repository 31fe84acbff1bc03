#include "yarn_fit/periodic/coarse_map.hpp"

#include <cmath>
#include <numbers>

namespace yarnfit::yarn {

Eigen::Vector2d CoarseDeformation::u() const { return {std::cos(angle), std::sin(angle)}; }
Eigen::Vector2d CoarseDeformation::v() const { return {-std::sin(angle), std::cos(angle)}; }
Eigen::Matrix2d CoarseDeformation::deformation_gradient() const {
  const Eigen::Vector2d uu = u();
  const Eigen::Vector2d vv = v();
  return (1.0 + stretch) * uu * uu.transpose() + (1.0 - compression) * vv * vv.transpose();
}

double weft_angle() { return 0.0; }
double bias_angle() { return std::numbers::pi / 4.0; }
double warp_angle() { return std::numbers::pi / 2.0; }

double sinc(double x) {
  // Series below 1e-4: 1 − x²/6 + x⁴/120 has error < 1e-20 there.
  if (std::abs(x) < 1e-4) {
    const double x2 = x * x;
    return 1.0 - x2 / 6.0 + x2 * x2 / 120.0;
  }
  return std::sin(x) / x;
}

CoarseMap::CoarseMap(const CoarseDeformation& chi) : m_chi(chi), m_f(chi.deformation_gradient()) {
  const Eigen::Vector2d u = chi.u();
  const Eigen::Vector2d v = chi.v();
  m_u3 = {u.x(), u.y(), 0.0};
  m_v3 = {v.x(), v.y(), 0.0};
}

void CoarseMap::place(const Eigen::Vector3d& reference, Eigen::Vector3d& base,
                      Eigen::Matrix3d& rotation) const {
  const Eigen::Vector2d planar = reference.head<2>();
  const double h = reference.z();
  if (!m_chi.curved()) {
    base.head<2>() = m_f * planar;
    base.z() = h;
    rotation.setIdentity();
    return;
  }
  const Eigen::Vector3d ez = Eigen::Vector3d::UnitZ();
  const double a = m_u3.head<2>().dot(planar);
  const double b = m_v3.head<2>().dot(planar);
  const double s1 = 1.0 + m_chi.stretch;
  const double theta = m_chi.curvature * a / s1;
  const double half = sinc(0.5 * theta);
  const double c = std::cos(theta);
  const double s = std::sin(theta);
  const Eigen::Vector3d n = c * ez - s * m_u3;
  base = (1.0 - m_chi.compression) * b * m_v3 +
         s1 * a * (sinc(theta) * m_u3 + 0.5 * theta * half * half * ez) + h * n;
  // Rotation by θ in the (u, e_z) plane: u -> cos θ u + sin θ e_z, e_z -> n, v fixed.
  rotation = m_v3 * m_v3.transpose() + (c * m_u3 + s * ez) * m_u3.transpose() + n * ez.transpose();
}

}  // namespace yarnfit::yarn
