#pragma once
// Problems found in user input or in options, collected rather than thrown so that one run
// reports every problem of every file and every bad field of an option struct at once (SPEC
// §2, §5). Each renders as one line
//   file:line: field: message
// with ":line" left out where the file has no lines to point at (a missing file), and
// "file:line: " left out where the problem is in options rather than in a file (`field` then
// names the option, e.g. "particles: must be at least 2").
//
// Every option struct of the project validates the same way:
//   [[nodiscard]] Problems problems() const;   // every invalid field; empty when valid
// Lives in numerics, the lowest module, so that the solvers' and optimisers' options can use
// it; fabrics_db/problems.hpp names it db::Problems for the readers.

#include <cstddef>
#include <string>
#include <vector>

namespace yarnfit::numerics {

struct Problem {
  std::string file;     // path as the user would type it; empty for an option
  int line = 0;         // 1-based line in `file`; 0 when there is no line to name
  std::string field;    // YAML key path, CSV column or pyp section; "file" for the file itself
  std::string message;  // what is wrong and, where possible, what is expected

  [[nodiscard]] std::string to_string() const;
};

class Problems {
 public:
  void add(std::string file, int line, std::string field, std::string message);
  // A problem of an option (no file, no line): add_field("particles", "must be at least 2").
  void add_field(std::string field, std::string message) { add({}, 0, std::move(field), std::move(message)); }
  void append(const Problems& other);
  // `other`'s problems with `prefix` before each field ("newton." + "tolerance").
  void append(const Problems& other, const std::string& prefix);

  [[nodiscard]] bool empty() const { return m_items.empty(); }
  [[nodiscard]] std::size_t size() const { return m_items.size(); }
  [[nodiscard]] const std::vector<Problem>& items() const { return m_items; }
  // All problems, one per line, in the order they were found.
  [[nodiscard]] std::string to_string() const;
  // All problems on one line, joined by "; " (for an exception's message).
  [[nodiscard]] std::string one_line() const;

 private:
  std::vector<Problem> m_items;
};

}  // namespace yarnfit::numerics
