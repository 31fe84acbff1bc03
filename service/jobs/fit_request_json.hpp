#pragma once
// A service fit request (the body of POST /api/v1/fabrics/{id}/fits) read into the request the
// command line fills (pipeline/fit_request.hpp), so that a fit asked over HTTP is the fit
// `yarnfit fit` would run with the same words:
//
//   {"stages": "all", "budget": "quick", "seed": 7, "report": true}
//
// Fields: the request's fields marked served in pipeline/fit_request_fields.hpp (stages is
// "shell" or "all" here), under their names there, and report (default true).
// An unknown field, a value of the wrong type or a name the fit cannot use is a problem
// naming the field; the stages' own ranges are checked as `fit`'s are. A fit asked by a
// stranger must also end in a time the server can give it: the sizes of the search are
// bounded (request_bounds(), docs/service.md), past them a problem names the field. The
// threads of a fit are the server's (`serve --threads-per-job`), not the request's.

#include <vector>

#include <nlohmann/json.hpp>

#include "fabrics_db/problems.hpp"
#include "pipeline/fit_request.hpp"

namespace yarnfit::service {

// The largest size of each search field a service request may ask for: two to ten times what
// the thorough budget uses (yarn_fit/fit/budget.cpp; the shell stage's default 1000
// iterations), and at least 1 each. Listed with the fields (pipeline/fit_request_fields.hpp).
struct RequestBound {
  const char* field;
  int most;
};
[[nodiscard]] std::vector<RequestBound> request_bounds();

struct ServiceFitRequest {
  pipeline::FitRequest request;
  bool report = true;  // the fabric's own report, written with its results
};

// `body` as a request; every problem goes to `problems` (file "request", line 0).
[[nodiscard]] ServiceFitRequest fit_request_from_json(const nlohmann::json& body, db::Problems& problems);

// The request back as JSON (what the service keeps to resume a job after a restart).
[[nodiscard]] nlohmann::json to_json(const ServiceFitRequest& request);

}  // namespace yarnfit::service
