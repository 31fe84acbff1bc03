// yarn_fit.json as read back by report, export, resume and the service (fuzz/fuzz_result_json.hpp).
#include "fuzz/fuzz_result_json.hpp"
#include "results/yarn_fit_file.hpp"

YARNFIT_FUZZ_TARGET(yarn_fit_file) {
  using namespace yarnfit;
  return fuzz::read_result_json(data, size,
                                [](const nlohmann::json& j) { return results::yarn_fit_file_from_json(j); });
}
