// The service's fit request (POST /api/v1/fits): the body as the service parses it, then
// fit_request_from_json, which lists every problem and never throws.
#include <nlohmann/json.hpp>

#include "fuzz/fuzz_support.hpp"
#include "service/jobs/fit_request_json.hpp"

YARNFIT_FUZZ_TARGET(fit_request) {
  using namespace yarnfit;
  const nlohmann::json body = nlohmann::json::parse(fuzz::as_text(data, size), nullptr, false);
  if (body.is_discarded()) return 0;
  db::Problems problems;
  const service::ServiceFitRequest request = service::fit_request_from_json(body, problems);
  if (problems.empty()) (void)service::to_json(request);  // what the service keeps to resume
  return 0;
}
