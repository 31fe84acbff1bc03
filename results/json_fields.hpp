#pragma once
// Reading and writing the fields of the result files (inside results/ only): every reader names
// the field it failed on ("shell_fit.json: directions[1].stretch: expected an array of
// numbers"), and null stands for "no figure" (NaN) both ways, as pct_json/number_or_nan do.
//
// A field that is absent takes its default: files of older versions lack fields added since
// (the readers before the results module treated them alike). A field that is present with the
// wrong type throws an Error.

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "results/search_bound.hpp"

namespace yarnfit::results::detail {

using nlohmann::json;

// Where a field is, for messages: the file's name, then the path inside it
// ("shell_fit.json: directions[1].stretch: expected …").
class Where {
 public:
  explicit Where(std::string file, std::string path = "") : m_file(std::move(file)), m_path(std::move(path)) {}
  [[nodiscard]] Where operator/(const std::string& key) const {
    return Where(m_file, m_path + (m_path.empty() ? "" : ".") + key);
  }
  [[nodiscard]] Where operator[](std::size_t i) const { return Where(m_file, m_path + "[" + std::to_string(i) + "]"); }
  // Throws an Error "FILE: PATH: expected WHAT".
  [[noreturn]] void bad(const std::string& what) const;

 private:
  std::string m_file;
  std::string m_path;
};

// The member `key` of `j` (an object), or nullptr when absent.
[[nodiscard]] const json* member(const json& j, const char* key);
// `j` must be an object (throws naming `at` otherwise).
void expect_object(const json& j, const Where& at);

// The member as a number; absent → `fallback`, null → NaN.
[[nodiscard]] double number(const json& j, const char* key, const Where& at, double fallback);
// The member as an optional number: absent or null → empty.
[[nodiscard]] std::optional<double> optional_number(const json& j, const char* key, const Where& at);
[[nodiscard]] int integer(const json& j, const char* key, const Where& at, int fallback);
[[nodiscard]] long long long_integer(const json& j, const char* key, const Where& at, long long fallback);
[[nodiscard]] bool boolean(const json& j, const char* key, const Where& at, bool fallback);
// A string; absent or null → `fallback`.
[[nodiscard]] std::string string(const json& j, const char* key, const Where& at, const std::string& fallback = "");
// An array of numbers (null cells NaN); absent → empty.
[[nodiscard]] std::vector<double> numbers(const json& j, const char* key, const Where& at);
// An array of strings; absent → empty.
[[nodiscard]] std::vector<std::string> strings(const json& j, const char* key, const Where& at);
// An object of numbers (null → NaN); absent or null → empty.
[[nodiscard]] std::map<std::string, double> number_map(const json& j, const char* key, const Where& at);
// An object of string lists; absent → empty.
[[nodiscard]] std::map<std::string, std::vector<std::string>> string_lists(const json& j, const char* key, const Where& at);

// Writing: numbers as pct_json (NaN and ±inf null), lists cell by cell alike.
[[nodiscard]] json numbers_json(const std::vector<double>& values);
[[nodiscard]] json number_map_json(const std::map<std::string, double>& values);
// A string, or null when empty.
[[nodiscard]] json string_or_null(const std::string& s);

// A member object, or an empty one when absent (its fields then take their defaults); a member
// that is not an object throws.
[[nodiscard]] const json& object_or_empty(const json& j, const char* key, const Where& at);

// One list of a record's fields serves its writer and its reader. A record's `fields(f, r)`
// calls `f(key, member, fallback)` for each plain field and `f.object(key, body)` for a nested
// object, whose body gets the same kind of `f` for that object:
//   template <class F, class R> void stage_fields(F& f, R& s) {
//     f("particles", s.particles, 0);
//     f.object("window", [&](auto& w) { w("lower", s.lower, k_nan); });
//   }
// FieldWriter puts every member into JSON as it is (a NaN is written as null); FieldReader
// takes each from JSON as number(), integer(), boolean() and string() do, the fallback when
// absent, and names the field it cannot read.
class FieldWriter {
 public:
  explicit FieldWriter(json& j) : m_j(j) {}
  template <class T, class Fallback>
  void operator()(const char* key, const T& value, const Fallback& /*fallback*/) {
    m_j[key] = value;
  }
  // A number; NaN and ±inf as null (pct_json's "no figure").
  void operator()(const char* key, double value, double /*fallback*/) {
    m_j[key] = std::isfinite(value) ? json(value) : json();
  }
  // Numbers, each NaN and ±inf as null (numbers_json).
  void operator()(const char* key, const std::vector<double>& value, const std::vector<double>& /*fallback*/) {
    m_j[key] = numbers_json(value);
  }
  // A (weft, warp) pair, each NaN as null.
  void operator()(const char* key, const std::array<double, 2>& value, const std::array<double, 2>& /*fallback*/) {
    m_j[key] = numbers_json({value[0], value[1]});
  }
  template <class Body>
  void object(const char* key, Body&& body) {
    json inner = json::object();
    FieldWriter w(inner);
    body(w);
    m_j[key] = std::move(inner);
  }

 private:
  json& m_j;
};

class FieldReader {
 public:
  FieldReader(const json& j, Where at) : m_j(j), m_at(std::move(at)) { expect_object(j, m_at); }
  void operator()(const char* key, double& value, double fallback) const;
  void operator()(const char* key, int& value, int fallback) const;
  void operator()(const char* key, long long& value, long long fallback) const;
  void operator()(const char* key, std::uint64_t& value, std::uint64_t fallback) const;  // ≥ 0
  void operator()(const char* key, bool& value, bool fallback) const;
  void operator()(const char* key, std::string& value, const std::string& fallback) const;
  // Two numbers (weft, warp); absent → the fallback.
  void operator()(const char* key, std::array<double, 2>& value, const std::array<double, 2>& fallback) const;
  // An array of numbers (null cells NaN), or of strings; absent → the fallback.
  void operator()(const char* key, std::vector<double>& value, const std::vector<double>& fallback) const;
  void operator()(const char* key, std::vector<std::string>& value, const std::vector<std::string>& fallback) const;
  // An object of numbers; absent → the fallback.
  void operator()(const char* key, std::map<std::string, double>& value,
                  const std::map<std::string, double>& fallback) const;
  template <class Body>
  void object(const char* key, Body&& body) const {
    const FieldReader r(object_or_empty(m_j, key, m_at), m_at / key);
    body(r);
  }

 private:
  const json& m_j;
  Where m_at;
};

// The record `r` as a JSON object, and a record read from the object `j` at `at`, through its
// field list (`fields`: a generic lambda (auto& f, auto& record) that calls the record's list).
template <class Record, class Fields>
[[nodiscard]] json fields_json(const Record& r, Fields fields) {
  json j = json::object();
  FieldWriter w(j);
  fields(w, r);
  return j;
}
template <class Record, class Fields>
[[nodiscard]] Record read_fields(const json& j, const Where& at, Fields fields) {
  Record r;
  const FieldReader f(j, at);
  fields(f, r);
  return r;
}

// The file's `schema_version` (1 when absent: every file before the results module); a version
// above `current` (a newer yarnfit wrote it) throws.
[[nodiscard]] int schema_version(const json& j, const Where& at, int current);

// The opening every result file's reader shares: `j` is an object and its schema_version is
// one this yarnfit reads. The file's record, its schema_version filled, the rest defaults.
template <class File>
[[nodiscard]] File open_result(const json& j, const Where& at, int current) {
  expect_object(j, at);
  File f;
  f.schema_version = schema_version(j, at, current);
  return f;
}

// The JSON of the file at `path`; throws an Error naming it when it cannot be read or
// is not JSON.
[[nodiscard]] json read_json_file(const std::filesystem::path& path);

// The `bounds` object of a result file: {name: {lower, upper, log}}.
[[nodiscard]] json bounds_json(const std::map<std::string, SearchBound>& bounds);
[[nodiscard]] std::map<std::string, SearchBound> read_bounds(const json& j, const Where& at);

// Calls read(element, where) for each element of the array member `key` (absent: none); each
// element must be an object.
template <class Read>
void for_each_object(const json& j, const char* key, const Where& at, Read&& read) {
  const json* v = member(j, key);
  if (!v) return;
  if (!v->is_array()) (at / key).bad("an array");
  for (std::size_t i = 0; i < v->size(); ++i) {
    expect_object((*v)[i], (at / key)[i]);
    read((*v)[i], (at / key)[i]);
  }
}

}  // namespace yarnfit::results::detail
