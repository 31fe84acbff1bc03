#include "swarm/parameter_space.hpp"
#include "numerics/util/error.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <stdexcept>

namespace yarnfit::swarm {

namespace {

// Shortest text that reads back as v: 0.2, not 0.20000000000000001.
std::string number(double v) {
  std::array<char, 32> buf{};
  const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  return std::string(buf.data(), r.ptr);
}

}  // namespace

ParameterSpace::ParameterSpace(std::vector<Parameter> parameters) : m_parameters(std::move(parameters)) {
  if (m_parameters.empty()) throw Error(ErrorCategory::input, "parameter space: no parameters");
  for (int i = 0; i < dimension(); ++i) {
    auto& p = m_parameters[static_cast<std::size_t>(i)];
    if (p.name.empty()) p.name = "x[" + std::to_string(i) + "]";
    const std::string where = "parameter space: " + label(i) + ": ";
    if (!std::isfinite(p.lower))
      throw Error(ErrorCategory::input, where + "lower is not finite (" + number(p.lower) + ")");
    if (!std::isfinite(p.upper)) throw Error(ErrorCategory::input, where + "upper is not finite (" + number(p.upper) + ")");
    if (!(p.lower < p.upper)) {
      throw Error(ErrorCategory::input, where + "lower (" + number(p.lower) + ") must be below upper (" +
                                  number(p.upper) + ")");
    }
    if (p.log_space && !(p.lower > 0.0)) {
      throw Error(ErrorCategory::input, where + "log_space needs lower > 0 (lower is " + number(p.lower) + ")");
    }
  }
}

ParameterSpace ParameterSpace::box(const Eigen::VectorXd& lower, const Eigen::VectorXd& upper) {
  if (lower.size() != upper.size()) {
    throw Error(ErrorCategory::input, "parameter space: lower has " + std::to_string(lower.size()) +
                                " entries but upper has " + std::to_string(upper.size()));
  }
  std::vector<Parameter> ps;
  for (Eigen::Index i = 0; i < lower.size(); ++i) ps.push_back({"", lower[i], upper[i], false});
  return ParameterSpace(std::move(ps));
}

std::string ParameterSpace::label(int i) const {
  return "'" + parameter(i).name + "' (parameter " + std::to_string(i) + ")";
}

void ParameterSpace::check_size(const Eigen::VectorXd& v, const char* what) const {
  if (v.size() != dimension()) {
    throw Error(ErrorCategory::input, std::string(what) + " has " + std::to_string(v.size()) +
                                " entries, the parameter space " + std::to_string(dimension()));
  }
}

Eigen::VectorXd ParameterSpace::to_unit(const Eigen::VectorXd& x) const {
  check_size(x, "point");
  Eigen::VectorXd u(x.size());
  for (int i = 0; i < dimension(); ++i) {
    const auto& p = parameter(i);
    if (!(x[i] >= p.lower && x[i] <= p.upper)) {
      throw Error(ErrorCategory::input, label(i) + " = " + number(x[i]) + " is outside its bounds [" + number(p.lower) +
                                  ", " + number(p.upper) + "]");
    }
    u[i] = p.log_space ? std::log(x[i] / p.lower) / std::log(p.upper / p.lower)
                       : (x[i] - p.lower) / (p.upper - p.lower);
    u[i] = std::clamp(u[i], 0.0, 1.0);
  }
  return u;
}

Eigen::VectorXd ParameterSpace::from_unit(const Eigen::VectorXd& u) const {
  check_size(u, "unit point");
  Eigen::VectorXd x(u.size());
  for (int i = 0; i < dimension(); ++i) {
    const auto& p = parameter(i);
    const double t = std::clamp(u[i], 0.0, 1.0);
    if (t == 0.0) {
      x[i] = p.lower;
    } else if (t == 1.0) {
      x[i] = p.upper;
    } else {
      x[i] = p.log_space ? p.lower * std::exp(t * std::log(p.upper / p.lower)) : p.lower + t * (p.upper - p.lower);
      x[i] = std::clamp(x[i], p.lower, p.upper);
    }
  }
  return x;
}

std::vector<std::string> ParameterSpace::bounds_problems(const Eigen::VectorXd& x) const {
  check_size(x, "point");
  std::vector<std::string> out;
  for (int i = 0; i < dimension(); ++i) {
    const auto& p = parameter(i);
    if (x[i] >= p.lower && x[i] <= p.upper) continue;
    const std::string name = p.name.empty() ? "x[" + std::to_string(i) + "]" : p.name;
    out.push_back(name + ": " + number(x[i]) + " is outside the search bounds [" + number(p.lower) + ", " +
                  number(p.upper) + "]");
  }
  return out;
}

bool ParameterSpace::contains(const Eigen::VectorXd& x) const {
  if (x.size() != dimension()) return false;
  for (int i = 0; i < dimension(); ++i) {
    if (!(x[i] >= parameter(i).lower && x[i] <= parameter(i).upper)) return false;
  }
  return true;
}

bool ParameterSpace::operator==(const ParameterSpace& other) const {
  if (dimension() != other.dimension()) return false;
  for (int i = 0; i < dimension(); ++i) {
    const auto& a = parameter(i);
    const auto& b = other.parameter(i);
    if (a.name != b.name || a.lower != b.lower || a.upper != b.upper || a.log_space != b.log_space) return false;
  }
  return true;
}

}  // namespace yarnfit::swarm
