#pragma once
// Benchmark functions with bounds, known minimiser and minimum, as in NLopt's
// test/testfuncs.c: every optimiser test runs over this table.

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "swarm/parameter_space.hpp"

namespace yarnfit::swarm::testing {

struct BenchmarkFunction {
  std::string name;
  std::vector<Parameter> parameters;
  std::function<double(const Eigen::VectorXd&)> f;
  Eigen::VectorXd minimiser;  // one of them, when there are several
  double minimum = 0.0;
  // Smooth, with a global basin the default swarm finds: swarm + COBYLA must reach
  // `minimum` to 1e-6. False for the multimodal functions whose global basin is one of
  // many similar ones (the swarm then only has to beat random search).
  bool smooth = false;

  [[nodiscard]] ParameterSpace space() const { return ParameterSpace(parameters); }
};

[[nodiscard]] const std::vector<BenchmarkFunction>& benchmark_table();
[[nodiscard]] const BenchmarkFunction& benchmark(const std::string& name);

}  // namespace yarnfit::swarm::testing
