#include "tests/test_support.hpp"

#include <array>
#include <atomic>
#include <cstdio>
#include <random>
#include <sstream>
#include <sys/wait.h>

namespace yarnfit::testing {

ScratchDir::ScratchDir(const std::string& tag) {
  static std::atomic<int> counter{0};
  std::random_device rd;
  m_path = fs::temp_directory_path() /
           ("yarnfit-" + tag + "-" + std::to_string(rd()) + "-" + std::to_string(counter++));
  fs::create_directories(m_path);
}

ScratchDir::~ScratchDir() {
  std::error_code ec;
  fs::remove_all(m_path, ec);
}

void write_file(const fs::path& file, const std::string& text) {
  fs::create_directories(file.parent_path());
  std::ofstream out(file, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + file.string());
}

std::string read_file(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

fs::path shared_dir() {
  if (const char* env = std::getenv("YARNFIT_SHARED_DIR"); env && *env) return env;
  return fs::weakly_canonical(fs::path(YARNFIT_SHARED_DIR));
}

fs::path shared_pattern(const std::string& name) { return shared_dir() / "data" / "patterns" / name; }

bool running_in_ci() {
  const char* ci = std::getenv("CI");
  return ci && std::string(ci) == "true";
}

std::string quoted(const fs::path& p) {
  std::string s = "'";
  for (char c : p.string()) {
    if (c == '\'') s += "'\\''";
    else s += c;
  }
  return s + "'";
}

CommandResult run_cli(const std::string& args) {
  ScratchDir tmp("cli");
  const fs::path out = tmp / "stdout";
  const fs::path err = tmp / "stderr";
  const std::string cmd = quoted(YARNFIT_CLI) + " " + args + " >" + quoted(out) + " 2>" +
                          quoted(err) + " </dev/null";
  const int status = std::system(cmd.c_str());
  CommandResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_file(out);
  r.err = read_file(err);
  return r;
}

}  // namespace yarnfit::testing
