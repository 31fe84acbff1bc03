#include "results/json_fields.hpp"

#include <limits>
#include <stdexcept>

#include "fabrics_db/text_util.hpp"
#include "numerics/util/error.hpp"
#include "results/metrics/error_metrics.hpp"
#include "numerics/util/non_finite.hpp"

namespace yarnfit::results::detail {

namespace {

using numerics::k_nan;

const char* type_name(const json& j) { return j.type_name(); }

}  // namespace

void Where::bad(const std::string& what) const {
  throw Error(ErrorCategory::input, m_file + ": " + (m_path.empty() ? "" : m_path + ": ") + "expected " + what);
}

const json* member(const json& j, const char* key) {
  const auto it = j.find(key);
  return it == j.end() ? nullptr : &*it;
}

void expect_object(const json& j, const Where& at) {
  if (!j.is_object()) at.bad(std::string("an object (found ") + type_name(j) + ")");
}

const json& object_or_empty(const json& j, const char* key, const Where& at) {
  static const json empty = json::object();
  const json* v = member(j, key);
  if (!v) return empty;
  expect_object(*v, at / key);
  return *v;
}

void FieldReader::operator()(const char* key, double& value, double fallback) const {
  value = number(m_j, key, m_at, fallback);
}
void FieldReader::operator()(const char* key, int& value, int fallback) const {
  value = integer(m_j, key, m_at, fallback);
}
void FieldReader::operator()(const char* key, long long& value, long long fallback) const {
  value = long_integer(m_j, key, m_at, fallback);
}
void FieldReader::operator()(const char* key, std::array<double, 2>& value,
                             const std::array<double, 2>& fallback) const {
  const std::vector<double> v = numbers(m_j, key, m_at);
  if (v.empty()) {
    value = fallback;
    return;
  }
  if (v.size() != 2) (m_at / key).bad("two numbers (weft, warp)");
  value = {v[0], v[1]};
}
void FieldReader::operator()(const char* key, std::vector<double>& value, const std::vector<double>& fallback) const {
  value = member(m_j, key) ? numbers(m_j, key, m_at) : fallback;
}
void FieldReader::operator()(const char* key, std::vector<std::string>& value,
                             const std::vector<std::string>& fallback) const {
  value = member(m_j, key) ? strings(m_j, key, m_at) : fallback;
}
void FieldReader::operator()(const char* key, std::map<std::string, double>& value,
                             const std::map<std::string, double>& fallback) const {
  value = member(m_j, key) ? number_map(m_j, key, m_at) : fallback;
}
void FieldReader::operator()(const char* key, std::uint64_t& value, std::uint64_t fallback) const {
  const json* v = member(m_j, key);
  if (!v) {
    value = fallback;
    return;
  }
  if (!v->is_number_unsigned() && !(v->is_number_integer() && v->get<long long>() >= 0))
    (m_at / key).bad("a non-negative integer");
  value = v->get<std::uint64_t>();
}
void FieldReader::operator()(const char* key, bool& value, bool fallback) const {
  value = boolean(m_j, key, m_at, fallback);
}
void FieldReader::operator()(const char* key, std::string& value, const std::string& fallback) const {
  value = string(m_j, key, m_at, fallback);
}

double number(const json& j, const char* key, const Where& at, double fallback) {
  const json* v = member(j, key);
  if (!v) return fallback;
  if (v->is_null()) return k_nan;
  if (!v->is_number()) (at / key).bad(std::string("a number or null (found ") + type_name(*v) + ")");
  return v->get<double>();
}

std::optional<double> optional_number(const json& j, const char* key, const Where& at) {
  const json* v = member(j, key);
  if (!v || v->is_null()) return std::nullopt;
  if (!v->is_number()) (at / key).bad(std::string("a number or null (found ") + type_name(*v) + ")");
  return v->get<double>();
}

long long long_integer(const json& j, const char* key, const Where& at, long long fallback) {
  const json* v = member(j, key);
  if (!v) return fallback;
  if (!v->is_number_integer()) (at / key).bad(std::string("an integer (found ") + type_name(*v) + ")");
  return v->get<long long>();
}

int integer(const json& j, const char* key, const Where& at, int fallback) {
  return static_cast<int>(long_integer(j, key, at, fallback));
}

bool boolean(const json& j, const char* key, const Where& at, bool fallback) {
  const json* v = member(j, key);
  if (!v) return fallback;
  if (!v->is_boolean()) (at / key).bad(std::string("true or false (found ") + type_name(*v) + ")");
  return v->get<bool>();
}

std::string string(const json& j, const char* key, const Where& at, const std::string& fallback) {
  const json* v = member(j, key);
  if (!v || v->is_null()) return fallback;
  if (!v->is_string()) (at / key).bad(std::string("a string (found ") + type_name(*v) + ")");
  return v->get<std::string>();
}

std::vector<double> numbers(const json& j, const char* key, const Where& at) {
  std::vector<double> out;
  const json* v = member(j, key);
  if (!v) return out;
  if (!v->is_array()) (at / key).bad(std::string("an array of numbers (found ") + type_name(*v) + ")");
  for (std::size_t i = 0; i < v->size(); ++i) {
    const json& x = (*v)[i];
    if (!x.is_number() && !x.is_null()) (at / key)[i].bad(std::string("a number or null (found ") + type_name(x) + ")");
    out.push_back(number_or_nan(x));
  }
  return out;
}

std::vector<std::string> strings(const json& j, const char* key, const Where& at) {
  std::vector<std::string> out;
  const json* v = member(j, key);
  if (!v) return out;
  if (!v->is_array()) (at / key).bad(std::string("an array of strings (found ") + type_name(*v) + ")");
  for (std::size_t i = 0; i < v->size(); ++i) {
    const json& x = (*v)[i];
    if (!x.is_string()) (at / key)[i].bad(std::string("a string (found ") + type_name(x) + ")");
    out.push_back(x.get<std::string>());
  }
  return out;
}

std::map<std::string, double> number_map(const json& j, const char* key, const Where& at) {
  std::map<std::string, double> out;
  const json* v = member(j, key);
  if (!v || v->is_null()) return out;
  expect_object(*v, at / key);
  for (const auto& [name, x] : v->items()) out[name] = number(*v, name.c_str(), at / key, k_nan);
  return out;
}

std::map<std::string, std::vector<std::string>> string_lists(const json& j, const char* key, const Where& at) {
  std::map<std::string, std::vector<std::string>> out;
  const json* v = member(j, key);
  if (!v) return out;
  expect_object(*v, at / key);
  for (const auto& [name, x] : v->items()) out[name] = strings(*v, name.c_str(), at / key);
  return out;
}

json numbers_json(const std::vector<double>& values) {
  json out = json::array();
  for (double v : values) out.push_back(pct_json(v));
  return out;
}

json number_map_json(const std::map<std::string, double>& values) {
  json out = json::object();
  for (const auto& [name, v] : values) out[name] = pct_json(v);
  return out;
}

json string_or_null(const std::string& s) { return s.empty() ? json() : json(s); }

int schema_version(const json& j, const Where& at, int current) {
  const int version = integer(j, "schema_version", at, 1);
  if (version < 1 || version > current)
    (at / "schema_version").bad("1 to " + std::to_string(current) + " (found " + std::to_string(version) +
                                "; a newer yarnfit wrote it)");
  return version;
}

json read_json_file(const std::filesystem::path& path) {
  std::string text, why;
  if (!db::read_text_file(path, text, why)) throw Error(ErrorCategory::io, path.string() + ": " + why);
  json j = json::parse(text, nullptr, false);
  if (j.is_discarded()) throw Error(ErrorCategory::input, path.string() + ": not JSON");
  return j;
}

json bounds_json(const std::map<std::string, SearchBound>& bounds) {
  json j = json::object();
  for (const auto& [name, b] : bounds) j[name] = {{"lower", b.lower}, {"upper", b.upper}, {"log", b.log}};
  return j;
}

std::map<std::string, SearchBound> read_bounds(const json& j, const Where& at) {
  std::map<std::string, SearchBound> out;
  const json* v = member(j, "bounds");
  if (!v) return out;
  expect_object(*v, at / "bounds");
  for (const auto& [name, b] : v->items()) {
    const Where w = at / "bounds" / name;
    expect_object(b, w);
    out[name] = {number(b, "lower", w, k_nan), number(b, "upper", w, k_nan), boolean(b, "log", w, true)};
  }
  return out;
}

}  // namespace yarnfit::results::detail
