#include "service/jobs/fit_request_json.hpp"

#include <limits>
#include <optional>
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
  for (const auto& item : body.items()) {
    // Named, not bound: a lambda may not capture a structured binding before C++20 in clang 14.
    const std::string& name = item.key();
    const json& value = item.value();
    bool known = false, typed = true;
    if (name == "report") {
      known = true;
      typed = read_value(value, out.report);
    }
    pipeline::for_each_request_field(out.request, [&](const pipeline::RequestField& f, auto& member) {
      if (!f.served || name != f.name) return;
      known = true;
      typed = read_value(value, member);
    });
    if (!known) say(name, "unknown field");
    else if (!typed) say(name, "wrong type: " + value.dump());
  }
  // The sizes the body asks for, each within what the service runs.
  pipeline::for_each_request_field(out.request, [&](const pipeline::RequestField& f, const auto& member) {
    if (!f.served || f.served_most == 0 || !body.contains(f.name)) return;
    const std::optional<long long> value = size_of(member);
    if (value && (*value < 1 || *value > f.served_most))
      say(f.name, std::to_string(*value) + " is outside what the service runs: 1 to " + std::to_string(f.served_most));
  });
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
