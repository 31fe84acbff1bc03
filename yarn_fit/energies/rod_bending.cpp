// Rod bending with a rest curvature vector (thesis 6.6, SPEC §3 "Yarn"; Bergou et al. 2008):
// see yarn_elements.hpp for the energy and the frames.
//
// The energy is written once, over the edge vectors (a, b), for any scalar type. Its gradient
// comes from forward-mode automatic differentiation with Ceres' jets over the 6 edge
// coordinates, its Hessian from SecondOrder numbers (second_order.hpp: value, gradient and
// Hessian carried together, several times cheaper than the jet of jets it replaced, which
// stays as bending_element_by_nested_jets for the tests), then mapped to (x0, x1, x2). The
// expression is smooth wherever it is finite (no square root of the curvature, unlike the
// magnitude form), so no smoothing is needed through a straight corner.
#include <ceres/jet.h>

#include <cmath>
#include <limits>
#include <type_traits>

#include <Eigen/Geometry>

#include "numerics/psd_projection.hpp"
#include "yarn_fit/energies/second_order.hpp"
#include "yarn_fit/energies/yarn_elements.hpp"

namespace yarnfit::yarn {

namespace {

constexpr double fold_tolerance = 1.0 - 1e-12;  // a·b ≤ −(1 − 1e-12)|a||b|: folded back

using Jet1 = ceres::Jet<double, 6>;
using Jet2 = ceres::Jet<Jet1, 6>;
using Second = SecondOrder<6>;
template <class T>
using V3 = Eigen::Matrix<T, 3, 1>;

double value_of(double x) { return x; }
double value_of(const Second& x) { return x.a; }
// A constant of scalar type T (a jet's constructor from a double is explicit and nests).
template <class T>
T lift(double x) {
  if constexpr (std::is_same_v<T, double> || std::is_same_v<T, Second>)
    return T(x);
  else
    return T(lift<typename T::Scalar>(x));
}
template <class T>
V3<T> lift(const Vec3& v) {
  return {lift<T>(v[0]), lift<T>(v[1]), lift<T>(v[2])};
}
template <class T, int N>
double value_of(const ceres::Jet<T, N>& x) {
  return value_of(x.a);
}

// Dot products written out: Eigen's reductions start from Scalar(0), which a jet of jets lacks.
template <class T>
T dot(const V3<T>& u, const V3<T>& v) {
  return u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
}

// The material frame's first director on an edge of tangent t: the anchor's director carried
// by parallel transport, P(t0 → t) d0 = d0 − (d0·t)/(1 + t0·t) (t0 + t). False where the edge
// has turned back against its anchor.
template <class T>
bool carried_director(const V3<T>& t, const EdgeAnchor& anchor, V3<T>& m1) {
  const V3<T> t0 = lift<T>(anchor.tangent);
  const V3<T> d0 = lift<T>(anchor.director);
  const T beta = lift<T>(1.0) + dot(t, t0);
  if (!(value_of(beta) > 1.0 - fold_tolerance)) return false;
  m1 = d0 - (dot(d0, t) / beta) * (t0 + t);
  return true;
}

// The curvature vector κ of the corner with edges a, b. κb is read in both edges' frames,
// g_e = (κb·m2, −κb·m1); the two readings differ by the twist τ between the frames (frame a
// carried across the corner against frame b), and κ = (g_a + g_b) / (2 cos(τ/2)) is their
// mean direction at |κb|'s length, so κ̄ = 0 gives the frame-free c|κb|² whatever the twist.
// False where κ is undefined (a zero edge, a folded corner, an edge turned back against its
// anchor, frames twisted by π).
template <class T>
bool curvature_of(const V3<T>& a, const V3<T>& b, const CornerFrames& frames, T& k1, T& k2) {
  using std::sqrt;
  const T la = sqrt(dot(a, a));
  const T lb = sqrt(dot(b, b));
  if (!(value_of(la) > 0.0) || !(value_of(lb) > 0.0)) return false;
  const V3<T> ta = a / la;
  const V3<T> tb = b / lb;
  const T chi = lift<T>(1.0) + dot(ta, tb);
  if (!(value_of(chi) > 1.0 - fold_tolerance)) return false;
  const V3<T> kb = (lift<T>(2.0) / chi) * ta.cross(tb);
  V3<T> m1a, m1b;
  if (!carried_director(ta, frames.in, m1a) || !carried_director(tb, frames.out, m1b)) return false;
  const V3<T> across = m1a - (dot(m1a, tb) / chi) * (ta + tb);  // m1a carried onto edge b
  const T twice_cos_sq = lift<T>(2.0) * (lift<T>(1.0) + dot(across, m1b));  // (2 cos(τ/2))²
  if (!(value_of(twice_cos_sq) > 1e-12)) return false;
  const T scale = lift<T>(1.0) / sqrt(twice_cos_sq);
  k1 = scale * (dot(kb, ta.cross(m1a)) + dot(kb, tb.cross(m1b)));
  k2 = -scale * (dot(kb, m1a) + dot(kb, m1b));
  return true;
}

template <class T>
bool energy_of(const V3<T>& a, const V3<T>& b, const CornerFrames& frames, const Eigen::Vector2d& rest, double c,
               T& energy) {
  T k1, k2;
  if (!curvature_of(a, b, frames, k1, k2)) return false;
  const T d1 = k1 - lift<T>(rest[0]);
  const T d2 = k2 - lift<T>(rest[1]);
  energy = lift<T>(c) * (d1 * d1 + d2 * d2);
  return true;
}

// (a, b) → (x0, x1, x2): a = x1 − x0, b = x2 − x1.
Vec<9> gradient_in_positions(const Vec<6>& g) {
  Vec<9> out;
  out.segment<3>(0) = -g.segment<3>(0);
  out.segment<3>(3) = g.segment<3>(0) - g.segment<3>(3);
  out.segment<3>(6) = g.segment<3>(3);
  return out;
}
Mat<9> hessian_in_positions(const Mat<6>& h) {
  Eigen::Matrix<double, 6, 9> jac = Eigen::Matrix<double, 6, 9>::Zero();
  const Eigen::Matrix3d eye = Eigen::Matrix3d::Identity();
  jac.block<3, 3>(0, 0) = -eye;
  jac.block<3, 3>(0, 3) = eye;
  jac.block<3, 3>(3, 3) = -eye;
  jac.block<3, 3>(3, 6) = eye;
  return jac.transpose() * h * jac;
}

}  // namespace

EdgeAnchor anchor_along(const Vec3& edge) {
  EdgeAnchor out;
  out.tangent = edge.normalized();
  // Horizontal and ⊥ to the tangent, ẑ × t, so a tile turned in its plane gets turned anchors
  // (to the bit, for quarter turns); an edge within 6° of vertical takes x̂ made ⊥ instead.
  const Vec3 across = Vec3::UnitZ().cross(out.tangent);
  if (across.norm() > 0.1) {
    out.director = across.normalized();
  } else {
    const Vec3 e = Vec3::UnitX();
    out.director = (e - e.dot(out.tangent) * out.tangent).normalized();
  }
  return out;
}

EdgeAnchor carried_anchor(const EdgeAnchor& anchor, const Eigen::Matrix3d& rotation, const Vec3& edge) {
  const Vec3 t0 = (rotation * anchor.tangent).normalized();
  const Vec3 d0 = rotation * anchor.director;
  const Vec3 t = edge.normalized();
  const double beta = 1.0 + t0.dot(t);
  if (!(beta > 1.0 - fold_tolerance)) return anchor_along(edge);  // turned back: no transport
  Vec3 d = d0 - (d0.dot(t) / beta) * (t0 + t);
  d -= d.dot(t) * t;
  return {t, d.normalized()};
}

Eigen::Vector2d corner_curvature(const Vec3& x0, const Vec3& x1, const Vec3& x2, const CornerFrames& frames) {
  double k1 = 0.0, k2 = 0.0;
  if (!curvature_of<double>(x1 - x0, x2 - x1, frames, k1, k2))
    return Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  return {k1, k2};
}

double corner_curvature(const Vec3& x0, const Vec3& x1, const Vec3& x2) {
  const Vec3 a = x1 - x0;
  const Vec3 b = x2 - x1;
  const double p = a.norm() * b.norm();
  const double q = a.dot(b);
  if (!(p > 0.0) || !(q > -fold_tolerance * p)) return std::numeric_limits<double>::infinity();
  return 2.0 * a.cross(b).norm() / (p + q);
}

double bending_element(const Vec3& x0, const Vec3& x1, const Vec3& x2, double rest_length_a,
                       double rest_length_b, const CornerFrames& frames, const Eigen::Vector2d& rest_curvature,
                       const RodBending& model, Vec<9>* gradient, Mat<9>* hessian, bool project_psd) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  const double rest_sum = rest_length_a + rest_length_b;
  if (!(rest_sum > 0.0)) return inf;
  const double c = model.kb / rest_sum;
  const Vec3 a = x1 - x0;
  const Vec3 b = x2 - x1;

  if (hessian != nullptr) {
    V3<Second> aj, bj;
    for (int i = 0; i < 3; ++i) {
      aj[i] = Second::variable(a[i], i);
      bj[i] = Second::variable(b[i], 3 + i);
    }
    Second w;
    if (!energy_of(aj, bj, frames, rest_curvature, c, w)) return inf;
    const Mat<6> h6 = 0.5 * (w.h + w.h.transpose());
    Mat<9> h9 = hessian_in_positions(h6);
    if (project_psd) numerics::project_psd<9>(h9);
    *hessian = h9;
    if (gradient != nullptr) *gradient = gradient_in_positions(w.g);
    return w.a;
  }
  if (gradient != nullptr) {
    V3<Jet1> aj, bj;
    for (int i = 0; i < 3; ++i) {
      aj[i] = Jet1(a[i], i);
      bj[i] = Jet1(b[i], 3 + i);
    }
    Jet1 w;
    if (!energy_of(aj, bj, frames, rest_curvature, c, w)) return inf;
    *gradient = gradient_in_positions(w.v);
    return w.a;
  }
  double w = 0.0;
  if (!energy_of<double>(a, b, frames, rest_curvature, c, w)) return inf;
  return w;
}

double bending_element_by_nested_jets(const Vec3& x0, const Vec3& x1, const Vec3& x2, double rest_length_a,
                                      double rest_length_b, const CornerFrames& frames,
                                      const Eigen::Vector2d& rest_curvature, const RodBending& model,
                                      Vec<9>& gradient, Mat<9>& hessian) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  const double rest_sum = rest_length_a + rest_length_b;
  if (!(rest_sum > 0.0)) return inf;
  const Vec3 a = x1 - x0;
  const Vec3 b = x2 - x1;
  V3<Jet2> aj, bj;
  for (int i = 0; i < 3; ++i) {
    aj[i] = Jet2(Jet1(a[i], i), i);
    bj[i] = Jet2(Jet1(b[i], 3 + i), 3 + i);
  }
  Jet2 w;
  if (!energy_of(aj, bj, frames, rest_curvature, model.kb / rest_sum, w)) return inf;
  Mat<6> h6;
  for (int i = 0; i < 6; ++i) h6.col(i) = w.v[i].v;
  hessian = hessian_in_positions(0.5 * (h6 + h6.transpose()));
  gradient = gradient_in_positions(w.a.v);
  return w.a.a;
}

bool bending_element_sensitivity(const Vec3& x0, const Vec3& x1, const Vec3& x2, double rest_length_a,
                                 double rest_length_b, const CornerFrames& frames,
                                 const Eigen::Vector2d& rest_curvature, double& d_energy, Vec<9>& d_gradient) {
  // W = kb · (the element at kb = 1).
  d_energy = bending_element(x0, x1, x2, rest_length_a, rest_length_b, frames, rest_curvature, RodBending{1.0},
                             &d_gradient, nullptr, false);
  return std::isfinite(d_energy);
}

}  // namespace yarnfit::yarn
