// How a command's outcome reaches the user: its problems and failed writes on stderr, and the
// exit code (cli/commands.hpp).
#include <iostream>

#include "cli/commands.hpp"
#include "cli/option_names.hpp"

namespace yarnfit::cli {

bool write_files(const std::string& out, const std::function<void()>& write) {
  try {
    write();
    return true;
  } catch (const std::exception& e) {
    std::cerr << out << ": file: " << e.what() << "\n";
    return false;
  }
}

int invalid_input(const db::Problems& problems, const std::string& prefix) {
  const db::Problems named = as_options(problems);
  for (const auto& p : named.items()) std::cerr << prefix << p.to_string() << "\n";
  return k_exit_invalid_input;
}

}  // namespace yarnfit::cli
