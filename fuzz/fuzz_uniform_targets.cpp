// The uniform-targets CSV (`yarn fit --targets`): every problem listed, nothing returned then.
#include "fabrics_db/targets/uniform_targets.hpp"
#include "fuzz/fuzz_support.hpp"

YARNFIT_FUZZ_TARGET(uniform_targets) {
  using namespace yarnfit;
  const auto file = fuzz::input_file(fuzz::as_text(data, size), "uniform_targets.csv");
  db::Problems problems;
  const auto targets = db::read_uniform_targets(file, problems);
  if (targets && !problems.empty()) fuzz::finding("uniform_targets: a result beside problems");
  return 0;
}
