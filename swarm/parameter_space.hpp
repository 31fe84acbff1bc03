#pragma once
// The box an optimiser searches, and the map between the caller's parameters and the unit
// cube the optimisers work in.
//
// Both optimisers of this module move in u ∈ [0, 1]^d, one coordinate per parameter:
//   linear parameter:     x = lower + u · (upper − lower)
//   log-space parameter:  x = lower · (upper / lower)^u      (log x linear in u)
// so a velocity, a repulsion radius or a COBYLA step means the same fraction of every
// parameter's range, whatever its units, and a stiffness bounded by [1e-3, 10] is searched
// per decade rather than crowded against its upper bound (SPEC §3 "Parameters").

#include <Eigen/Core>
#include <string>
#include <vector>

namespace yarnfit::swarm {

struct Parameter {
  std::string name;  // used in error messages; "x[i]" when empty
  double lower = 0.0;
  double upper = 1.0;
  bool log_space = false;  // needs 0 < lower
};

class ParameterSpace {
 public:
  // Throws an input Error naming the parameter and the field when a bound is not
  // finite, lower ≥ upper, or a log-space parameter has lower ≤ 0.
  explicit ParameterSpace(std::vector<Parameter> parameters);

  // A box of linear parameters named x[0], x[1], ...
  [[nodiscard]] static ParameterSpace box(const Eigen::VectorXd& lower, const Eigen::VectorXd& upper);

  [[nodiscard]] int dimension() const { return static_cast<int>(m_parameters.size()); }
  [[nodiscard]] const std::vector<Parameter>& parameters() const { return m_parameters; }
  [[nodiscard]] const Parameter& parameter(int i) const { return m_parameters[static_cast<std::size_t>(i)]; }
  // "'kb' (parameter 2)" — how error messages refer to parameter i.
  [[nodiscard]] std::string label(int i) const;

  // Caller's coordinates → unit cube. Throws an input Error naming the parameter when
  // x has the wrong size, is not finite or lies outside the bounds.
  [[nodiscard]] Eigen::VectorXd to_unit(const Eigen::VectorXd& x) const;
  // Unit cube → caller's coordinates. u is clamped to [0, 1] first and the result to the
  // bounds (exp/log round-off must not step outside), so u = 0 and 1 give the bounds exactly.
  // Throws an input Error when u has the wrong size.
  [[nodiscard]] Eigen::VectorXd from_unit(const Eigen::VectorXd& u) const;

  [[nodiscard]] bool contains(const Eigen::VectorXd& x) const;
  // One line per coordinate of x outside its bounds, "NAME: V is outside the search bounds
  // [LO, HI]" (NAME as given, x[i] when empty); empty when x lies inside. x must have the
  // space's size (an input Error otherwise).
  [[nodiscard]] std::vector<std::string> bounds_problems(const Eigen::VectorXd& x) const;
  [[nodiscard]] bool operator==(const ParameterSpace& other) const;

 private:
  void check_size(const Eigen::VectorXd& v, const char* what) const;

  std::vector<Parameter> m_parameters;
};

}  // namespace yarnfit::swarm
