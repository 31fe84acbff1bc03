// Yarn parameters as YAML or JSON (`--params`, `--start`): read_yarn_params names every
// problem with its line and key and gives nothing then.
#include "fuzz/fuzz_support.hpp"
#include "yarn_fit/model/yarn_params.hpp"

YARNFIT_FUZZ_TARGET(yarn_params) {
  using namespace yarnfit;
  const auto file = fuzz::input_file(fuzz::as_text(data, size), "params.yaml");
  db::Problems problems;
  const auto params = yarn::read_yarn_params(file, yarn::ParameterScales{400.0, 2e-4}, problems);
  if (params && !problems.empty()) fuzz::finding("yarn_params: a result beside problems");
  return 0;
}
