#include "tests/swarm/benchmark_functions.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace yarnfit::swarm::testing {

namespace {

using Eigen::VectorXd;
constexpr double kPi = std::numbers::pi;

std::vector<Parameter> box(int d, double lower, double upper) {
  return std::vector<Parameter>(static_cast<std::size_t>(d), Parameter{"", lower, upper, false});
}

VectorXd constant(int d, double v) { return VectorXd::Constant(d, v); }

double rosenbrock(const VectorXd& x) {
  double f = 0.0;
  for (Eigen::Index i = 0; i + 1 < x.size(); ++i) {
    f += 100.0 * std::pow(x[i + 1] - x[i] * x[i], 2) + std::pow(1.0 - x[i], 2);
  }
  return f;
}

double rastrigin(const VectorXd& x) {
  double f = 10.0 * static_cast<double>(x.size());
  for (double xi : x) f += xi * xi - 10.0 * std::cos(2.0 * kPi * xi);
  return f;
}

double ackley(const VectorXd& x) {
  const double n = static_cast<double>(x.size());
  double sq = 0.0, cs = 0.0;
  for (double xi : x) {
    sq += xi * xi;
    cs += std::cos(2.0 * kPi * xi);
  }
  return -20.0 * std::exp(-0.2 * std::sqrt(sq / n)) - std::exp(cs / n) + 20.0 + std::numbers::e;
}

double griewank(const VectorXd& x) {
  double sum = 0.0, prod = 1.0;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    sum += x[i] * x[i] / 4000.0;
    prod *= std::cos(x[i] / std::sqrt(static_cast<double>(i + 1)));
  }
  return 1.0 + sum - prod;
}

double styblinski_tang(const VectorXd& x) {
  double f = 0.0;
  for (double xi : x) f += 0.5 * (xi * xi * xi * xi - 16.0 * xi * xi + 5.0 * xi);
  return f;
}

// Root of d/dx (x⁴ − 16x² + 5x) = 4x³ − 32x + 5 near −2.9, by Newton: the minimiser to
// full precision instead of a quoted decimal.
double styblinski_tang_root() {
  double x = -2.9;
  for (int k = 0; k < 50; ++k) x -= (4 * x * x * x - 32 * x + 5) / (12 * x * x - 32);
  return x;
}

double levy(const VectorXd& x) {
  const auto w = [&](Eigen::Index i) { return 1.0 + (x[i] - 1.0) / 4.0; };
  const Eigen::Index n = x.size();
  double f = std::pow(std::sin(kPi * w(0)), 2);
  for (Eigen::Index i = 0; i + 1 < n; ++i) {
    f += std::pow(w(i) - 1.0, 2) * (1.0 + 10.0 * std::pow(std::sin(kPi * w(i) + 1.0), 2));
  }
  f += std::pow(w(n - 1) - 1.0, 2) * (1.0 + std::pow(std::sin(2.0 * kPi * w(n - 1)), 2));
  return f;
}

double zakharov(const VectorXd& x) {
  double s1 = 0.0, s2 = 0.0;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    s1 += x[i] * x[i];
    s2 += 0.5 * static_cast<double>(i + 1) * x[i];
  }
  return s1 + s2 * s2 + s2 * s2 * s2 * s2;
}

std::vector<BenchmarkFunction> make_table() {
  std::vector<BenchmarkFunction> t;
  // Shifted spheres: the minimiser is off the centre of the box, so an optimiser biased to
  // the centre gains nothing.
  const VectorXd c5 = (VectorXd(5) << 1.0, -2.0, 0.5, 3.0, -1.0).finished();
  t.push_back({"sphere_3d", box(3, -5.12, 5.12), [c5](const VectorXd& x) { return (x - c5.head(3)).squaredNorm(); },
               c5.head(3), 0.0, true});
  t.push_back({"sphere_5d", box(5, -5.12, 5.12), [c5](const VectorXd& x) { return (x - c5).squaredNorm(); }, c5, 0.0,
               true});
  t.push_back({"rosenbrock_2d", box(2, -2.048, 2.048), rosenbrock, constant(2, 1.0), 0.0, true});
  t.push_back({"rosenbrock_4d", box(4, -2.048, 2.048), rosenbrock, constant(4, 1.0), 0.0, true});
  t.push_back({"booth_2d", box(2, -10.0, 10.0),
               [](const VectorXd& x) {
                 return std::pow(x[0] + 2 * x[1] - 7, 2) + std::pow(2 * x[0] + x[1] - 5, 2);
               },
               (VectorXd(2) << 1.0, 3.0).finished(), 0.0, true});
  t.push_back({"beale_2d", box(2, -4.5, 4.5),
               [](const VectorXd& x) {
                 const double a = x[0], b = x[1];
                 return std::pow(1.5 - a + a * b, 2) + std::pow(2.25 - a + a * b * b, 2) +
                        std::pow(2.625 - a + a * b * b * b, 2);
               },
               (VectorXd(2) << 3.0, 0.5).finished(), 0.0, true});
  t.push_back({"six_hump_camel_2d", {{"", -3.0, 3.0, false}, {"", -2.0, 2.0, false}},
               [](const VectorXd& x) {
                 const double a = x[0], b = x[1];
                 return (4 - 2.1 * a * a + a * a * a * a / 3) * a * a + a * b + (-4 + 4 * b * b) * b * b;
               },
               (VectorXd(2) << 0.08984201368301331, -0.7126564032704135).finished(), -1.0316284534898774, true});
  t.push_back({"zakharov_4d", box(4, -5.0, 10.0), zakharov, constant(4, 0.0), 0.0, true});
  // Log-space parameters spanning six decades, like the stiffnesses of SPEC §3: a bowl in
  // log10 x around minimisers of very different magnitude.
  const VectorXd cl = (VectorXd(3) << 0.02, 5.0, 300.0).finished();
  t.push_back({"log_sphere_3d", std::vector<Parameter>(3, Parameter{"", 1e-3, 1e3, true}),
               [cl](const VectorXd& x) {
                 return (x.array().log10() - cl.array().log10()).matrix().squaredNorm();
               },
               cl, 0.0, true});
  // Multimodal: many local minima around the global one. Styblinski–Tang is smooth but has
  // 2^d local minima, the others only 14 apart: the swarm lands in the wrong one for some
  // seeds.
  const double st = styblinski_tang_root();
  t.push_back({"styblinski_tang_3d", box(3, -5.0, 5.0), styblinski_tang, constant(3, st),
               styblinski_tang(constant(3, st)), false});
  t.push_back({"rastrigin_2d", box(2, -5.12, 5.12), rastrigin, constant(2, 0.0), 0.0, false});
  t.push_back({"rastrigin_3d", box(3, -5.12, 5.12), rastrigin, constant(3, 0.0), 0.0, false});
  t.push_back({"ackley_2d", box(2, -32.768, 32.768), ackley, constant(2, 0.0), 0.0, false});
  t.push_back({"ackley_3d", box(3, -32.768, 32.768), ackley, constant(3, 0.0), 0.0, false});
  t.push_back({"griewank_2d", box(2, -600.0, 600.0), griewank, constant(2, 0.0), 0.0, false});
  t.push_back({"levy_3d", box(3, -10.0, 10.0), levy, constant(3, 1.0), 0.0, false});
  return t;
}

}  // namespace

const std::vector<BenchmarkFunction>& benchmark_table() {
  static const std::vector<BenchmarkFunction> table = make_table();
  return table;
}

const BenchmarkFunction& benchmark(const std::string& name) {
  for (const auto& b : benchmark_table()) {
    if (b.name == name) return b;
  }
  throw std::invalid_argument("no benchmark function named " + name);
}

}  // namespace yarnfit::swarm::testing
