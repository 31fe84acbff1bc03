#pragma once
// yarnfit's one error type (docs/architecture.md, "Errors"). Inputs are checked into problem
// lists before any work; an `Error` is thrown only where the caller cannot go on, and its
// category says what the person running yarnfit can do about it.

#include <stdexcept>
#include <string>

namespace yarnfit {

enum class ErrorCategory {
  input,     // what they gave cannot be used (an option, a record, a file's content): mend it
  conflict,  // something of theirs is in the way (a record that exists, a batch already running,
             // a name taken): move it, or say --force
  io,        // a file, folder or database cannot be read or written: a path, permissions, the disk
  solve,     // a simulation yarnfit was asked for did not converge: other settings or another model
  system,    // the machine refused what yarnfit needs (processes, sockets, OpenSSL, MPI)
};

class Error : public std::runtime_error {
 public:
  Error(ErrorCategory category, const std::string& what) : std::runtime_error(what), m_category(category) {}
  [[nodiscard]] ErrorCategory category() const noexcept { return m_category; }
  // Whether the user mends it in what they gave or have (input, conflict): exit code 2 on the
  // command line, 4xx in the service; the other categories are exit 1 and 5xx.
  [[nodiscard]] bool users_to_mend() const noexcept {
    return m_category == ErrorCategory::input || m_category == ErrorCategory::conflict;
  }

 private:
  ErrorCategory m_category;
};

// The same error with `prefix` before its text ("checkpoint F: "), keeping its category.
[[nodiscard]] inline Error with_context(const std::string& prefix, const Error& e) {
  return {e.category(), prefix + e.what()};
}

}  // namespace yarnfit
