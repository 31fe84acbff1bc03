#pragma once
// The options of a fit request's fields (pipeline/fit_request_fields.hpp), registered on a
// command from the field list with its help, bound to the request's members.

#include <CLI/CLI.hpp>

#include "pipeline/fit_request.hpp"
#include "pipeline/fit_request_fields.hpp"

namespace yarnfit::cli {

// The options of one group of the request's fields: the commands that share a group register
// it together (`fit`, `yarn fit` and `batch` the search settings, and so on).
void add_request_options(CLI::App& cmd, pipeline::FitRequest& request, pipeline::RequestGroup group);

// The first of a field's option names, the one messages use ("--local,--local-method":
// "--local").
std::string first_option_name(const char* names);

}  // namespace yarnfit::cli
