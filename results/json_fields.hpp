#pragma once
// Reading and writing the fields of the result files (inside results/ only): every reader names
// the field it failed on ("shell_fit.json: directions[1].stretch: expected an array of
// numbers"), and null stands for "no figure" (NaN) both ways, as pct_json/number_or_nan do.
//
// A field that is absent takes its default: files of older versions lack fields added since
// (the readers before the results module treated them alike). A field that is present with the
// wrong type throws std::runtime_error.

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
  // Throws std::runtime_error "FILE: PATH: expected WHAT".
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

// The file's `schema_version` (1 when absent: every file before the results module); a version
// above `current` (a newer yarnfit wrote it) throws.
[[nodiscard]] int schema_version(const json& j, const Where& at, int current);

// The JSON of the file at `path`; throws std::runtime_error naming it when it cannot be read or
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
