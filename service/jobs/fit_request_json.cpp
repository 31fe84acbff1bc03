#include "service/jobs/fit_request_json.hpp"

#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

namespace yarnfit::service {

using nlohmann::json;

namespace {

// How one field is read from JSON and written back.
struct Field {
  std::function<bool(const json&, ServiceFitRequest&)> read;  // false: wrong type
  std::function<void(const ServiceFitRequest&, json&, const std::string&)> write;
};

template <class T>
Field plain(T pipeline::FitRequest::*member) {
  return {[member](const json& v, ServiceFitRequest& r) {
            if constexpr (std::is_same_v<T, bool>) {
              if (!v.is_boolean()) return false;
            } else if constexpr (std::is_same_v<T, std::string>) {
              if (!v.is_string()) return false;
            } else if constexpr (std::is_same_v<T, int>) {
              if (!v.is_number_integer() || v.get<long long>() < std::numeric_limits<int>::min() ||
                  v.get<long long>() > std::numeric_limits<int>::max())
                return false;
            } else {
              if (!v.is_number_unsigned()) return false;
            }
            r.request.*member = v.get<T>();
            return true;
          },
          [member](const ServiceFitRequest& r, json& j, const std::string& name) { j[name] = r.request.*member; }};
}

Field optional_int(std::optional<int> pipeline::FitRequest::*member) {
  return {[member](const json& v, ServiceFitRequest& r) {
            if (!v.is_number_integer()) return false;
            const long long n = v.get<long long>();
            if (n < std::numeric_limits<int>::min() || n > std::numeric_limits<int>::max()) return false;
            r.request.*member = static_cast<int>(n);
            return true;
          },
          [member](const ServiceFitRequest& r, json& j, const std::string& name) {
            if (r.request.*member) j[name] = *(r.request.*member);
          }};
}

// A list of names (`export`: ["u3m", "table"]).
Field names(std::vector<std::string> pipeline::FitRequest::*member) {
  return {[member](const json& v, ServiceFitRequest& r) {
            if (!v.is_array()) return false;
            for (const auto& n : v)
              if (!n.is_string()) return false;
            r.request.*member = v.get<std::vector<std::string>>();
            return true;
          },
          [member](const ServiceFitRequest& r, json& j, const std::string& name) {
            if (!(r.request.*member).empty()) j[name] = r.request.*member;
          }};
}

const std::map<std::string, Field>& fields() {
  using R = pipeline::FitRequest;
  static const std::map<std::string, Field> table{
      {"stages", plain(&R::stages)},
      {"export", names(&R::exports)},
      {"budget", plain(&R::budget)},
      {"global_method", plain(&R::global_method)},
      {"local_method", plain(&R::local_method)},
      {"shell_model", plain(&R::shell_model)},
      {"max_iterations", plain(&R::max_iterations)},
      {"seed", plain(&R::seed)},
      {"full_range", plain(&R::full_range)},
      {"fab_held_out", names(&R::fab_held_out)},
      {"no_swarm", plain(&R::no_swarm)},
      {"linear_stretch", plain(&R::linear_stretch)},
      {"no_rest_shape", plain(&R::no_rest_shape)},
      {"no_profile", plain(&R::no_profile)},
      {"particles", optional_int(&R::particles)},
      {"iterations", optional_int(&R::iterations)},
      {"samples", optional_int(&R::samples)},
      {"local_samples", optional_int(&R::local_samples)},
      {"local_evaluations", optional_int(&R::local_evaluations)},
      {"starts", optional_int(&R::starts)},
      {"report",
       {[](const json& v, ServiceFitRequest& r) {
          if (!v.is_boolean()) return false;
          r.report = v.get<bool>();
          return true;
        },
        [](const ServiceFitRequest& r, json& j, const std::string& name) { j[name] = r.report; }}},
  };
  return table;
}

}  // namespace

ServiceFitRequest fit_request_from_json(const json& body, db::Problems& problems) {
  ServiceFitRequest out;
  const auto say = [&problems](const std::string& field, const std::string& message) {
    problems.add("request", 0, field, message);
  };
  if (!body.is_object()) {
    say("body", "expected a JSON object of fit options");
    return out;
  }
  for (const auto& [name, value] : body.items()) {
    const auto f = fields().find(name);
    if (f == fields().end()) say(name, "unknown field");
    else if (!f->second.read(value, out)) say(name, "wrong type: " + value.dump());
  }
  const auto bound = [&](const char* field, std::optional<int> value) {
    if (!value) return;
    int most = 0;
    for (const auto& b : k_request_bounds)
      if (std::string(b.field) == field) most = b.most;
    if (*value < 1 || *value > most)
      say(field, std::to_string(*value) + " is outside what the service runs: 1 to " + std::to_string(most));
  };
  const pipeline::FitRequest& r = out.request;
  bound("particles", r.particles);
  bound("iterations", r.iterations);
  bound("samples", r.samples);
  bound("local_samples", r.local_samples);
  bound("local_evaluations", r.local_evaluations);
  bound("starts", r.starts);
  if (body.contains("max_iterations")) bound("max_iterations", r.max_iterations);
  // The yarn stage alone fits a targets file, which a service request does not carry.
  if (out.request.stages != "shell" && out.request.stages != "all")
    say("stages", "'" + out.request.stages + "': a fit runs \"shell\" or \"all\"");
  return out;
}

json to_json(const ServiceFitRequest& request) {
  json j = json::object();
  for (const auto& [name, f] : fields()) f.write(request, j, name);
  return j;
}

}  // namespace yarnfit::service
