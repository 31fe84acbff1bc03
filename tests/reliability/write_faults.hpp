#pragma once
// Faults while writing (issue 52): a full disk, a read-only folder and a kill between the
// temporary file and the rename, each made to happen to one call, in this process or in a
// child of it.

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <exception>
#include <filesystem>
#include <functional>
#include <map>
#include <string>

#include "numerics/util/whole_file.hpp"
#include "tests/test_support.hpp"

namespace yarnfit::testing {

// While alive, no file this process writes may grow past `bytes` (RLIMIT_FSIZE): a write
// beyond fails with EFBIG, as one on a full disk fails with ENOSPC. SIGXFSZ is ignored so that
// the write fails rather than the process.
class FullDisk {
 public:
  explicit FullDisk(rlim_t bytes) {
    ::getrlimit(RLIMIT_FSIZE, &m_old);
    m_old_handler = std::signal(SIGXFSZ, SIG_IGN);
    const rlimit low{bytes, m_old.rlim_max};
    ::setrlimit(RLIMIT_FSIZE, &low);
  }
  ~FullDisk() {
    ::setrlimit(RLIMIT_FSIZE, &m_old);
    std::signal(SIGXFSZ, m_old_handler);
  }
  FullDisk(const FullDisk&) = delete;
  FullDisk& operator=(const FullDisk&) = delete;

 private:
  rlimit m_old{};
  void (*m_old_handler)(int) = nullptr;
};

// How a call run in a child process ended.
struct ChildEnd {
  bool killed = false;   // by SIGKILL
  bool threw = false;    // an exception left the call
  std::string message;   // its what()
};

// Runs `call` in a child process after `prepare` (in the child); the child's exception message
// comes back through a pipe.
inline ChildEnd run_in_child(const std::function<void()>& prepare, const std::function<void()>& call) {
  int fds[2];
  if (::pipe(fds) != 0) throw std::runtime_error("pipe");
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(fds[0]);
    std::string message;
    int code = 0;
    try {
      prepare();
      call();
    } catch (const std::exception& e) {
      message = e.what();
      code = 1;
    }
    if (!message.empty()) (void)!::write(fds[1], message.data(), message.size());
    ::_exit(code);
  }
  ::close(fds[1]);
  std::string message;
  char buffer[512];
  for (ssize_t n; (n = ::read(fds[0], buffer, sizeof buffer)) > 0;) message.append(buffer, static_cast<std::size_t>(n));
  ::close(fds[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ChildEnd end;
  end.killed = WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL;
  end.threw = WIFEXITED(status) && WEXITSTATUS(status) == 1;
  end.message = message;
  return end;
}

// `call` as a user who may not write into `folder` (root may write anywhere, so a root test
// runs it in a child as nobody; anyone else gets the folder's write permission taken away).
inline ChildEnd run_with_read_only_folder(const std::filesystem::path& folder, const std::function<void()>& call) {
  namespace fs = std::filesystem;
  const auto perms = fs::status(folder).permissions();
  fs::permissions(folder, fs::perms::owner_write | fs::perms::group_write | fs::perms::others_write,
                  fs::perm_options::remove);
  ChildEnd end = run_in_child(
      [] {
        if (::geteuid() == 0 && (::setgid(65534) != 0 || ::setuid(65534) != 0))
          throw std::runtime_error("cannot become nobody");
      },
      call);
  fs::permissions(folder, perms);
  return end;
}

// `call` killed (SIGKILL) in a child process when its first whole-file write has its temporary
// file written and is about to rename it.
inline ChildEnd run_killed_before_rename(const std::function<void()>& call) {
  return run_in_child(
      [] { numerics::detail::set_before_rename_hook([](const std::filesystem::path&) { ::raise(SIGKILL); }); }, call);
}

// Every regular file under `folder`, relative name → bytes (what a user would find there).
inline std::map<std::string, std::string> files_under(const std::filesystem::path& folder) {
  std::map<std::string, std::string> files;
  if (!std::filesystem::exists(folder)) return files;
  for (const auto& e : std::filesystem::recursive_directory_iterator(folder))
    if (e.is_regular_file()) files[e.path().lexically_relative(folder).string()] = read_file(e.path());
  return files;
}

// The names under `folder` that are temporary files of a whole-file write (".NAME.tmpPID").
inline std::vector<std::string> temporaries_under(const std::filesystem::path& folder) {
  std::vector<std::string> names;
  for (const auto& [name, bytes] : files_under(folder))
    if (std::filesystem::path(name).filename().string().starts_with(".") && name.find(".tmp") != std::string::npos)
      names.push_back(name);
  return names;
}

}  // namespace yarnfit::testing
