#include "service/upload/isolated_unpack.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

namespace yarnfit::service {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// The address space this process maps now [bytes] (/proc/self/statm's first field, in pages).
std::uintmax_t mapped_bytes() {
  std::ifstream statm("/proc/self/statm");
  std::uintmax_t pages = 0;
  statm >> pages;
  return pages * static_cast<std::uintmax_t>(::sysconf(_SC_PAGESIZE));
}

void set_limit(int resource, rlim_t value) {
  const rlimit r{value, value};
  ::setrlimit(resource, &r);
}

[[noreturn]] void child(std::string_view archive, const fs::path& destination, const UploadLimits& limits,
                        const UnpackIsolation& isolation, std::uintmax_t mapped, int out) {
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  set_limit(RLIMIT_AS, static_cast<rlim_t>(mapped + isolation.extra_memory_bytes));
  set_limit(RLIMIT_CPU, static_cast<rlim_t>(isolation.cpu_seconds));
  set_limit(RLIMIT_FSIZE, static_cast<rlim_t>(limits.max_file_bytes + 1));
  std::string message;
  try {
    const UnpackedUpload u = unpack_upload(archive, destination, limits);
    message = json{{"ok", u.ok},
                   {"status", u.refusal.status},
                   {"message", u.refusal.message},
                   {"files", u.files},
                   {"bytes", u.unpacked_bytes}}
                  .dump();
  } catch (const std::bad_alloc&) {
    ::_exit(4);
  } catch (...) {
    ::_exit(5);
  }
  for (std::size_t at = 0; at < message.size();) {
    const ssize_t n = ::write(out, message.data() + at, message.size() - at);
    if (n <= 0) ::_exit(6);
    at += static_cast<std::size_t>(n);
  }
  ::_exit(0);
}

UnpackedUpload refused(const fs::path& destination, int status, const std::string& message) {
  std::error_code ec;
  fs::remove_all(destination, ec);
  // The unpacker's hidden staging folders beside the destination (a killed child left them).
  const std::string hidden = "." + destination.filename().string();
  for (const auto& e : fs::directory_iterator(destination.parent_path(), ec))
    if (e.path().filename().string().rfind(hidden, 0) == 0) fs::remove_all(e.path(), ec);
  UnpackedUpload u;
  u.refusal = {status, message};
  return u;
}

}  // namespace

UnpackedUpload unpack_upload_isolated(std::string_view archive, const fs::path& destination, const UploadLimits& limits,
                                      const UnpackIsolation& isolation) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) return refused(destination, 500, "cannot unpack now (no pipe)");
  const std::uintmax_t mapped = mapped_bytes();
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    return refused(destination, 500, "cannot unpack now (no process)");
  }
  if (pid == 0) {
    ::close(fds[0]);
    child(archive, destination, limits, isolation, mapped, fds[1]);
  }
  ::close(fds[1]);
  std::string answer;
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(isolation.wall_seconds);
  bool late = false;
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(until - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      late = true;
      break;
    }
    pollfd p{fds[0], POLLIN, 0};
    const int ready = ::poll(&p, 1, static_cast<int>(left.count()));
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) continue;
    char buf[4096];
    const ssize_t n = ::read(fds[0], buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    answer.append(buf, static_cast<std::size_t>(n));
  }
  ::close(fds[0]);
  if (late) ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  const std::string too_costly = "the archive took more than the unpacking may use (";
  if (late) return refused(destination, 413, too_costly + std::to_string(isolation.wall_seconds) + " s)");
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    if (sig == SIGXCPU) return refused(destination, 413, too_costly + std::to_string(isolation.cpu_seconds) + " s of CPU)");
    if (sig == SIGXFSZ) return refused(destination, 413, too_costly + "a file over the size limit)");
    return refused(destination, 413, too_costly + "memory; signal " + std::to_string(sig) + ")");
  }
  if (WEXITSTATUS(status) == 4) return refused(destination, 413, too_costly + "memory)");
  const json j = json::parse(answer, nullptr, false);
  if (WEXITSTATUS(status) != 0 || !j.is_object()) return refused(destination, 500, "the unpacking failed");
  UnpackedUpload u;
  u.ok = j.value("ok", false);
  u.refusal = {j.value("status", 0), j.value("message", "")};
  u.files = j.value("files", std::vector<std::string>{});
  u.unpacked_bytes = j.value("bytes", std::uintmax_t{0});
  return u;
}

}  // namespace yarnfit::service
