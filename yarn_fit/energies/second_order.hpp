#pragma once
// A number that carries its gradient and Hessian over N variables (forward-mode automatic
// differentiation to second order), for the rod bending element (rod_bending.cpp).
//
// Why not a jet of jets (ceres::Jet<ceres::Jet<double, N>, N>): that type carries the value's
// gradient twice and every second derivative in an N × N block of jets, so each product costs
// N + 1 jet products, about 13 (N + 1)² flops; here a product updates the value, the gradient
// and the symmetric Hessian once, f g → f H_g + g H_f + ∇f ∇gᵀ + ∇g ∇fᵀ, about 5 N² flops. The
// numbers are the same up to rounding (tests/yarn_fit/energies/test_second_order.cpp holds the
// bending element's Hessian to the jet-of-jets one).
//
// Only what the bending element uses is defined: +, −, ×, ÷, sqrt, and mixing with doubles.
#include <Eigen/Core>
#include <cmath>

namespace yarnfit::yarn {

template <int N>
struct SecondOrder {
  using Gradient = Eigen::Matrix<double, N, 1>;
  using Hessian = Eigen::Matrix<double, N, N>;

  double a = 0.0;                    // the value
  Gradient g = Gradient::Zero();     // ∂/∂x
  Hessian h = Hessian::Zero();       // ∂²/∂x², symmetric

  SecondOrder() = default;
  explicit SecondOrder(double value) : a(value) {}
  // Storage the caller fills whole: an operation's result is written once, not zeroed first.
  struct Unset {};
  explicit SecondOrder(Unset) : g(), h() {}
  // The i-th variable at `value`.
  static SecondOrder variable(double value, int i) {
    SecondOrder x(value);
    x.g[i] = 1.0;
    return x;
  }

  SecondOrder& operator+=(const SecondOrder& y) {
    a += y.a;
    g += y.g;
    h += y.h;
    return *this;
  }
  SecondOrder& operator-=(const SecondOrder& y) {
    a -= y.a;
    g -= y.g;
    h -= y.h;
    return *this;
  }
  SecondOrder& operator*=(const SecondOrder& y) { return *this = *this * y; }
  SecondOrder& operator/=(const SecondOrder& y) { return *this = *this / y; }

  friend SecondOrder operator+(SecondOrder x, const SecondOrder& y) { return x += y; }
  friend SecondOrder operator-(SecondOrder x, const SecondOrder& y) { return x -= y; }
  friend SecondOrder operator-(const SecondOrder& x) {
    SecondOrder out{Unset{}};
    out.a = -x.a;
    out.g = -x.g;
    out.h = -x.h;
    return out;
  }
  friend SecondOrder operator*(const SecondOrder& x, const SecondOrder& y) {
    SecondOrder out{Unset{}};
    out.a = x.a * y.a;
    out.g = x.a * y.g + y.a * x.g;
    const Hessian cross = x.g * y.g.transpose();
    out.h = x.a * y.h + y.a * x.h + cross + cross.transpose();
    return out;
  }
  // A function φ of x, given φ(x), φ'(x), φ''(x): ∇φ = φ' ∇x, ∇²φ = φ' ∇²x + φ'' ∇x ∇xᵀ.
  friend SecondOrder chain(const SecondOrder& x, double value, double first, double second) {
    SecondOrder out{Unset{}};
    out.a = value;
    out.g = first * x.g;
    out.h = first * x.h + second * (x.g * x.g.transpose());
    return out;
  }
  friend SecondOrder operator/(const SecondOrder& x, const SecondOrder& y) {
    const double inv = 1.0 / y.a;
    return x * chain(y, inv, -inv * inv, 2.0 * inv * inv * inv);
  }
  friend SecondOrder sqrt(const SecondOrder& x) {
    const double root = std::sqrt(x.a);
    return chain(x, root, 0.5 / root, -0.25 / (root * x.a));
  }

  // With doubles.
  friend SecondOrder operator*(double s, SecondOrder x) {
    x.a *= s;
    x.g *= s;
    x.h *= s;
    return x;
  }
  friend SecondOrder operator*(const SecondOrder& x, double s) { return s * x; }
  friend SecondOrder operator/(const SecondOrder& x, double s) { return (1.0 / s) * x; }
  friend SecondOrder operator+(SecondOrder x, double s) {
    x.a += s;
    return x;
  }
  friend SecondOrder operator-(SecondOrder x, double s) {
    x.a -= s;
    return x;
  }
};

}  // namespace yarnfit::yarn

namespace Eigen {
// Lets Eigen's fixed-size vectors (the bending element's edge vectors, their cross products)
// hold SecondOrder numbers.
template <int N>
struct NumTraits<yarnfit::yarn::SecondOrder<N>> : GenericNumTraits<yarnfit::yarn::SecondOrder<N>> {
  using Real = yarnfit::yarn::SecondOrder<N>;
  using NonInteger = Real;
  using Nested = Real;
  using Literal = Real;
  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    RequireInitialization = 1,
    ReadCost = 1,
    AddCost = N * N,
    MulCost = 5 * N * N,
  };
  static inline int digits10() { return NumTraits<double>::digits10(); }
};
}  // namespace Eigen
