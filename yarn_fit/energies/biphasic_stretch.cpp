// Biphasic stretch (thesis 6.5): a spring with three linear force regimes (ks2 | ks1 | ks2).
#include <algorithm>
#include <cmath>
#include <limits>

#include "yarn_fit/energies/yarn_elements.hpp"

namespace yarnfit::yarn {

double BiphasicStretch::w(double strain) const {
  if (strain < 0.0) return 0.5 * ks2 * strain * strain;
  if (strain < eps_s) return 0.5 * ks1 * strain * strain;
  const double over = strain - eps_s;
  return 0.5 * (ks2 * over * over + ks1 * eps_s * (2.0 * strain - eps_s));
}

double BiphasicStretch::dw(double strain) const {
  if (strain < 0.0) return ks2 * strain;
  if (strain < eps_s) return ks1 * strain;
  return ks2 * (strain - eps_s) + ks1 * eps_s;
}

double BiphasicStretch::d2w(double strain) const {
  // Right limits at the kinks: ε = 0 belongs to the soft phase, ε = ε̄s to the stiff one
  // (with ε̄s = 0 the soft phase is empty and ε = 0 is stiff on both sides).
  if (strain < 0.0) return ks2;
  if (strain < eps_s) return ks1;
  return ks2;
}

double stretch_element(const Vec3& x0, const Vec3& x1, double rest_length,
                       const BiphasicStretch& model, Vec<6>* gradient, Mat<6>* hessian,
                       bool project_psd) {
  const Vec3 e = x1 - x0;
  const double l = e.norm();
  if (!(l > 0.0) || !(rest_length > 0.0)) return std::numeric_limits<double>::infinity();
  const double strain = l / rest_length - 1.0;
  const double value = rest_length * model.w(strain);
  if (gradient == nullptr && hessian == nullptr) return value;

  const Vec3 t = e / l;
  const double tension = model.dw(strain);  // dW/dl
  if (gradient != nullptr) {
    gradient->head<3>() = -tension * t;
    gradient->tail<3>() = tension * t;
  }
  if (hessian != nullptr) {
    // d²W/dx1² = (w''/L̄) t tᵀ + (w'/l)(I − t tᵀ); the element Hessian is [[H, −H], [−H, H]].
    double axial = model.d2w(strain) / rest_length;
    double transverse = tension / l;
    if (project_psd) {
      // [[H, −H], [−H, H]] = [1 −1]ᵀ[1 −1] ⊗ H has the eigenvalues 2·eig(H) and 0, and H has
      // the eigenvalues axial (along t) and transverse (twice): clamping both is exact.
      axial = std::max(axial, 0.0);
      transverse = std::max(transverse, 0.0);
    }
    const Eigen::Matrix3d tt = t * t.transpose();  // formed unscaled: exactly symmetric
    const Eigen::Matrix3d h = transverse * Eigen::Matrix3d::Identity() + (axial - transverse) * tt;
    hessian->topLeftCorner<3, 3>() = h;
    hessian->bottomRightCorner<3, 3>() = h;
    hessian->topRightCorner<3, 3>() = -h;
    hessian->bottomLeftCorner<3, 3>() = -h;
  }
  return value;
}

bool stretch_element_sensitivity(const Vec3& x0, const Vec3& x1, double rest_length, const BiphasicStretch& model,
                                 Vec<3>& d_energy, Eigen::Matrix<double, 6, 3>& d_gradient) {
  const Vec3 e = x1 - x0;
  const double l = e.norm();
  if (!(l > 0.0) || !(rest_length > 0.0)) return false;
  const double strain = l / rest_length - 1.0;
  const double es = model.eps_s;
  // ∂w/∂θ and ∂w'/∂θ on the branch of w that ε lies in (the same tests as w and dw).
  Vec<3> dw, dtension;
  if (strain < 0.0) {
    dw << 0.0, 0.0, 0.5 * strain * strain;
    dtension << 0.0, 0.0, strain;
  } else if (strain < es) {
    dw << 0.5 * strain * strain, 0.0, 0.0;
    dtension << strain, 0.0, 0.0;
  } else {
    const double over = strain - es;
    dw << 0.5 * es * (2.0 * strain - es), (model.ks1 - model.ks2) * over, 0.5 * over * over;
    dtension << es, model.ks1 - model.ks2, over;
  }
  d_energy = rest_length * dw;
  const Vec3 t = e / l;
  d_gradient.topRows<3>() = -t * dtension.transpose();
  d_gradient.bottomRows<3>() = t * dtension.transpose();
  return true;
}

}  // namespace yarnfit::yarn

