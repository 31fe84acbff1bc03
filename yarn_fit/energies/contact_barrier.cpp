// Two-barrier yarn-yarn contact (thesis 6.7): Li et al.'s barrier in relative distance,
// squared, integrated over a segment pair with Simpson's rule on both segments.
//
// Barrier g(x) = f(x)², f(x) = −(x − 1)² log x on (0, 1):
//   f'  = −2 (x − 1) log x − (x − 1)²/x
//   f'' = −2 log x − 4 (x − 1)/x + (x − 1)²/x²
//   g' = 2 f f',  g'' = 2 (f'² + f f'').
// Contact element: per quadrature point pair (i, j), d = xa(s_i) − xb(s_j), D = |d|,
// D is linear-in-DOF composed with a norm, ∂D/∂x_k = c_k d̂ with c = (1 − s_i, s_i,
// −(1 − s_j), −s_j), so with ω = w_i w_j L̄a L̄b
//   ∇W  += ω e'(D) (c ⊗ d̂)
//   ∇²W += ω (c cᵀ) ⊗ [e'' d̂d̂ᵀ + (e'/D)(I − d̂d̂ᵀ)].
// (c cᵀ) ⊗ M is PSD iff M is, and M has the eigenvalues e'' (along d̂) and e'/D (twice):
// clamping both at 0 per point pair makes each term, and hence the sum, PSD.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

#include "yarn_fit/energies/yarn_elements.hpp"

namespace yarnfit::yarn {

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

// One barrier term: kc g(D/2R) and its derivatives with respect to D, all zero for D ≥ 2R.
struct BarrierTerm {
  double e = 0.0, de = 0.0, d2e = 0.0;
};

// f, f', f'' at x in (0, 1).
struct BarrierF {
  double f, df, d2f;
};

inline BarrierF barrier_f(double x) {
  const double lg = std::log(x);
  const double xm1 = x - 1.0;
  const double inv = 1.0 / x;
  return {-xm1 * xm1 * lg, -2.0 * xm1 * lg - xm1 * xm1 * inv,
          -2.0 * lg - 4.0 * xm1 * inv + xm1 * xm1 * inv * inv};
}

// Adds kc g(D/2R), kc g'/(2R), kc g''/(2R)² for D > 0. A term with R ≤ 0 or kc = 0 is absent.
inline void add_term(double distance, double kc, double radius, BarrierTerm& out) {
  if (kc == 0.0 || !(radius > 0.0)) return;
  const double scale = 1.0 / (2.0 * radius);
  const double x = distance * scale;
  if (x >= 1.0) return;
  const BarrierF b = barrier_f(x);
  out.e += kc * b.f * b.f;
  out.de += kc * scale * 2.0 * b.f * b.df;
  out.d2e += kc * scale * scale * 2.0 * (b.df * b.df + b.f * b.d2f);
}

inline Eigen::Index block_offset(std::size_t vertex) {
  return static_cast<Eigen::Index>(3 * vertex);
}

inline BarrierTerm contact_law(const TwoBarrierContact& m, double distance) {
  BarrierTerm t;
  add_term(distance, m.kc1, m.r1, t);
  add_term(distance, m.kc2, m.r2, t);
  return t;
}

}  // namespace

double Barrier::value(double x) {
  if (!(x > 0.0)) return inf;
  if (x >= 1.0) return 0.0;
  const BarrierF b = barrier_f(x);
  return b.f * b.f;
}

double Barrier::first(double x) {
  if (!(x > 0.0)) return -inf;
  if (x >= 1.0) return 0.0;
  const BarrierF b = barrier_f(x);
  return 2.0 * b.f * b.df;
}

double Barrier::second(double x) {
  if (!(x > 0.0)) return inf;
  if (x >= 1.0) return 0.0;
  const BarrierF b = barrier_f(x);
  return 2.0 * (b.df * b.df + b.f * b.d2f);
}

double TwoBarrierContact::cutoff_distance() const { return 2.0 * std::max(r1, r2); }

double TwoBarrierContact::e(double distance) const {
  if (!(distance > 0.0)) return inf;
  return contact_law(*this, distance).e;
}

double TwoBarrierContact::de(double distance) const {
  if (!(distance > 0.0)) return -inf;
  return contact_law(*this, distance).de;
}

double TwoBarrierContact::d2e(double distance) const {
  if (!(distance > 0.0)) return inf;
  return contact_law(*this, distance).d2e;
}

namespace {

// Simpson's rule on both edges: the 3 × 3 point pairs (x_a(s_i), x_b(s_j)) with weights
// w_i w_j L̄a L̄b. visit(d, dist, omega, si, sj) is called for each pair closer than the
// cutoff, d = x_a − x_b; false when two points coincide (the barrier is infinite there) or the
// bounding boxes of the edges already lie farther apart than the cutoff (`apart` says which).
template <class Visit>
bool for_each_point_pair(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1, double rest_length_a,
                         double rest_length_b, double cutoff, bool& apart, Visit&& visit) {
  const double cutoff2 = cutoff * cutoff;
  // Broad phase at element level: distance between the two axis-aligned bounding boxes.
  const Vec3 amin = a0.cwiseMin(a1), amax = a0.cwiseMax(a1);
  const Vec3 bmin = b0.cwiseMin(b1), bmax = b0.cwiseMax(b1);
  const Vec3 gap = (bmin - amax).cwiseMax(amin - bmax).cwiseMax(0.0);
  apart = gap.squaredNorm() >= cutoff2;
  if (apart) return true;
  static constexpr std::array<double, 3> s{0.0, 0.5, 1.0};
  static constexpr std::array<double, 3> w{1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0};
  const std::array<Vec3, 3> xa{a0, 0.5 * (a0 + a1), a1};
  const std::array<Vec3, 3> xb{b0, 0.5 * (b0 + b1), b1};
  const double rest_area = rest_length_a * rest_length_b;
  for (std::size_t i = 0; i < 3; ++i) {
    for (std::size_t j = 0; j < 3; ++j) {
      const Vec3 d = xa[i] - xb[j];
      const double dist2 = d.squaredNorm();
      if (dist2 >= cutoff2) continue;
      const double dist = std::sqrt(dist2);
      if (!(dist > 0.0)) return false;
      visit(d, dist, w[i] * w[j] * rest_area, s[i], s[j]);
    }
  }
  return true;
}

}  // namespace

double contact_element(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1,
                       double rest_length_a, double rest_length_b,
                       const TwoBarrierContact& model, Vec<12>* gradient, Mat<12>* hessian,
                       bool project_psd) {
  if (gradient != nullptr) gradient->setZero();
  if (hessian != nullptr) hessian->setZero();

  double value = 0.0;
  bool apart = false;
  const bool finite = for_each_point_pair(a0, a1, b0, b1, rest_length_a, rest_length_b, model.cutoff_distance(), apart,
                                          [&](const Vec3& d, double dist, double omega, double si, double sj) {
    const BarrierTerm law = contact_law(model, dist);
    value += omega * law.e;
    if (gradient == nullptr && hessian == nullptr) return;
    const std::array<double, 4> c{1.0 - si, si, sj - 1.0, -sj};
    const Vec3 dh = d / dist;
    if (gradient != nullptr) {
      const Vec3 f = (omega * law.de) * dh;
      for (std::size_t k = 0; k < 4; ++k) {
        const double ck = c[k];
        if (ck != 0.0) gradient->segment<3>(block_offset(k)) += ck * f;
      }
    }
    if (hessian != nullptr) {
      double axial = law.d2e;
      double transverse = law.de / dist;
      if (project_psd) {
        axial = std::max(axial, 0.0);
        transverse = std::max(transverse, 0.0);
      }
      if (axial == 0.0 && transverse == 0.0) return;
      // The outer product is formed before scaling so that m is exactly symmetric (Eigen
      // folds a scalar factor into one side of a product, which breaks that in the last bit).
      const Eigen::Matrix3d dd = dh * dh.transpose();
      const Eigen::Matrix3d m =
          omega * (transverse * Eigen::Matrix3d::Identity() + (axial - transverse) * dd);
      for (std::size_t k = 0; k < 4; ++k) {
        const double ck = c[k];
        if (ck == 0.0) continue;
        for (std::size_t l = k; l < 4; ++l) {
          const double cl = c[l];
          if (cl == 0.0) continue;
          hessian->block<3, 3>(block_offset(k), block_offset(l)) += (ck * cl) * m;
        }
      }
    }
  });
  if (apart) return 0.0;
  if (!finite) return inf;
  if (hessian != nullptr) {
    // Only the upper block triangle was accumulated (diagonal blocks are symmetric).
    for (int k = 1; k < 4; ++k) {
      for (int l = 0; l < k; ++l) {
        hessian->block<3, 3>(3 * k, 3 * l) = hessian->block<3, 3>(3 * l, 3 * k).transpose();
      }
    }
  }
  return value;
}

namespace {

// One barrier's parameter derivatives at distance D: ∂e/∂kc, ∂e/∂R and of e' = de/dD.
struct BarrierSensitivity {
  double e_kc = 0.0, e_r = 0.0, de_kc = 0.0, de_r = 0.0;
};

BarrierSensitivity barrier_sensitivity(double distance, double kc, double radius) {
  BarrierSensitivity out;
  if (!(radius > 0.0)) return out;
  const double x = distance / (2.0 * radius);
  if (x >= 1.0) return out;
  const BarrierF b = barrier_f(x);
  const double g = b.f * b.f;
  const double g1 = 2.0 * b.f * b.df;
  const double g2 = 2.0 * (b.df * b.df + b.f * b.d2f);
  out.e_kc = g;
  out.e_r = -kc * g1 * x / radius;
  out.de_kc = g1 / (2.0 * radius);
  out.de_r = -kc * (x * g2 + g1) / (2.0 * radius * radius);
  return out;
}

}  // namespace

bool contact_element_sensitivity(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1,
                                 double rest_length_a, double rest_length_b, const TwoBarrierContact& model,
                                 Vec<4>& d_energy, Eigen::Matrix<double, 12, 4>& d_gradient) {
  d_energy.setZero();
  d_gradient.setZero();
  bool apart = false;
  return for_each_point_pair(a0, a1, b0, b1, rest_length_a, rest_length_b, model.cutoff_distance(), apart,
                             [&](const Vec3& d, double dist, double omega, double si, double sj) {
    const BarrierSensitivity soft = model.kc1 != 0.0 ? barrier_sensitivity(dist, model.kc1, model.r1) : BarrierSensitivity{};
    const BarrierSensitivity stiff = model.kc2 != 0.0 ? barrier_sensitivity(dist, model.kc2, model.r2) : BarrierSensitivity{};
    const Vec<4> de(soft.e_kc, soft.e_r, stiff.e_kc, stiff.e_r);
    const Vec<4> dde(soft.de_kc, soft.de_r, stiff.de_kc, stiff.de_r);
    d_energy += omega * de;
    const std::array<double, 4> c{1.0 - si, si, sj - 1.0, -sj};
    const Vec3 dh = d / dist;
    for (std::size_t k = 0; k < 4; ++k) {
      if (c[k] == 0.0) continue;
      d_gradient.block<3, 4>(block_offset(k), 0) += (omega * c[k]) * dh * dde.transpose();
    }
  });
}

}  // namespace yarnfit::yarn

