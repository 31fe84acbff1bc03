#include "service/jobs/fit_request_json.hpp"

#include <limits>
#include <optional>
#include <set>
#include <string>
#include <type_traits>
#include <vector>

#include "pipeline/fit_request_fields.hpp"

namespace yarnfit::service {

using nlohmann::json;

namespace {

using pipeline::is_list;
using pipeline::is_optional;

// `v` into `member` when it is of the member's type (an int within int's range, a seed a
// non-negative integer, a list of names strings); false otherwise, `member` untouched.
template <class T>
bool read_value(const json& v, T& member) {
  if constexpr (is_optional<T>) {
    typename T::value_type value{};
    if (!read_value(v, value)) return false;
    member = value;
  } else if constexpr (is_list<T>) {
    if (!v.is_array()) return false;
    for (const auto& n : v)
      if (!n.is_string()) return false;
    member = v.get<T>();
  } else if constexpr (std::is_same_v<T, bool>) {
    if (!v.is_boolean()) return false;
    member = v.get<bool>();
  } else if constexpr (std::is_same_v<T, std::string>) {
    if (!v.is_string()) return false;
    member = v.get<std::string>();
  } else if constexpr (std::is_same_v<T, int>) {
    if (!v.is_number_integer() || v.get<long long>() < std::numeric_limits<int>::min() ||
        v.get<long long>() > std::numeric_limits<int>::max())
      return false;
    member = v.get<int>();
  } else if constexpr (std::is_unsigned_v<T>) {
    if (!v.is_number_unsigned()) return false;
    member = v.get<T>();
  } else {
    static_assert(std::is_floating_point_v<T>);
    if (!v.is_number()) return false;
    member = v.get<T>();
  }
  return true;
}

// A size's value as given, or none (not given, or of the wrong type).
template <class T>
std::optional<long long> size_of(const T& member) {
  if constexpr (is_optional<T>) {
    if (member) return *member;
    return std::nullopt;
  } else if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>) {
    return static_cast<long long>(member);
  } else {
    return std::nullopt;
  }
}

}  // namespace

std::vector<RequestBound> request_bounds() {
  std::vector<RequestBound> out;
  pipeline::FitRequest request;
  pipeline::for_each_request_field(request, [&out](const pipeline::RequestField& f, const auto&) {
    if (f.served && f.served_most > 0) out.push_back({f.name, f.served_most});
  });
  return out;
}

ServiceFitRequest fit_request_from_json(const json& body, db::Problems& problems) {
  ServiceFitRequest out;
  const auto say = [&problems](const std::string& field, const std::string& message) {
    problems.add("request", 0, field, message);
  };
  if (!body.is_object()) {
    say("body", "expected a JSON object of fit options");
    return out;
  }
  // One walk of the field list reads every served field the body gives and checks its size;
  // what is left of the body is "report" or unknown.
  std::set<std::string> read;
  pipeline::for_each_request_field(out.request, [&](const pipeline::RequestField& f, auto& member) {
    if (!f.served) return;
    const auto given = body.find(f.name);
    if (given == body.end()) return;
    read.insert(f.name);
    if (!read_value(*given, member)) {
      say(f.name, "wrong type: " + given->dump());
      return;
    }
    const std::optional<long long> size = f.served_most > 0 ? size_of(member) : std::nullopt;
    if (size && (*size < 1 || *size > f.served_most))
      say(f.name, std::to_string(*size) + " is outside what the service runs: 1 to " + std::to_string(f.served_most));
  });
  for (const auto& item : body.items()) {
    if (item.key() == "report") {
      if (!read_value(item.value(), out.report)) say("report", "wrong type: " + item.value().dump());
    } else if (read.count(item.key()) == 0) {
      say(item.key(), "unknown field");
    }
  }
  // The yarn stage alone fits a targets file, which a service request does not carry.
  if (out.request.stages != "shell" && out.request.stages != "all")
    say("stages", "'" + out.request.stages + "': a fit runs \"shell\" or \"all\"");
  return out;
}

json to_json(const ServiceFitRequest& request) {
  json j = json::object();
  pipeline::for_each_request_field(request.request, [&j](const pipeline::RequestField& f, const auto& member) {
    using T = std::decay_t<decltype(member)>;
    if (!f.served) return;
    if constexpr (is_optional<T>) {
      if (member) j[f.name] = *member;
    } else if constexpr (is_list<T>) {
      if (!member.empty()) j[f.name] = member;
    } else {
      j[f.name] = member;
    }
  });
  j["report"] = request.report;
  return j;
}

}  // namespace yarnfit::service
