#include "service/upload/unpack_zygote.hpp"
#include "numerics/util/error.hpp"

#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

namespace yarnfit::service {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

bool write_all(int fd, std::string_view text) {
  while (!text.empty()) {
    const ssize_t n = ::send(fd, text.data(), text.size(), MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    text.remove_prefix(static_cast<std::size_t>(n));
  }
  return true;
}

bool read_exactly(int fd, std::string& out, std::size_t n) {
  out.resize(n);
  std::size_t at = 0;
  while (at < n) {
    const ssize_t got = ::read(fd, out.data() + at, n - at);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) return false;
    at += static_cast<std::size_t>(got);
  }
  return true;
}

bool read_line(int fd, std::string& line) {
  line.clear();
  for (char c;;) {
    const ssize_t got = ::read(fd, &c, 1);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) return false;
    if (c == '\n') return true;
    line += c;
  }
}

json to_json(const UnpackedUpload& u) {
  return {{"ok", u.ok}, {"status", u.refusal.status}, {"message", u.refusal.message}, {"files", u.files}, {"bytes", u.unpacked_bytes}};
}

UnpackedUpload from_json(const json& j) {
  UnpackedUpload u;
  u.ok = j.value("ok", false);
  u.refusal = {j.value("status", 500), j.value("message", std::string("the unpacking failed"))};
  u.files = j.value("files", std::vector<std::string>{});
  u.unpacked_bytes = j.value("bytes", std::uintmax_t{0});
  return u;
}

// The helper: a request is a line {"destination", "size"} and `size` bytes of archive; the
// answer one line of JSON. It ends when the server closes its end (or dies: PDEATHSIG).
[[noreturn]] void helper(int fd, const UploadLimits& limits, const UnpackIsolation& isolation) {
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  for (std::string line, archive;;) {
    if (!read_line(fd, line)) ::_exit(0);
    const json request = json::parse(line, nullptr, false);
    if (!request.is_object() || !read_exactly(fd, archive, request.value("size", std::size_t{0}))) ::_exit(1);
    const UnpackedUpload u =
        unpack_upload_isolated(archive, request.value("destination", std::string()), limits, isolation);
    if (!write_all(fd, to_json(u).dump() + "\n")) ::_exit(1);
  }
}

}  // namespace

UnpackZygote::UnpackZygote(UploadLimits limits, UnpackIsolation isolation) {
  int fds[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0)
    throw Error(ErrorCategory::system, "cannot start the upload unpacker (socketpair)");
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) throw Error(ErrorCategory::system, "cannot start the upload unpacker (fork)");
  if (pid == 0) {
    ::close(fds[0]);
    helper(fds[1], limits, isolation);
  }
  ::close(fds[1]);
  m_fd = fds[0];
  m_pid = pid;
}

UnpackZygote::~UnpackZygote() {
  ::close(m_fd);
  int status = 0;
  while (::waitpid(m_pid, &status, 0) < 0 && errno == EINTR) {
  }
}

UnpackedUpload UnpackZygote::unpack(std::string_view archive, const fs::path& destination) {
  const std::lock_guard lock(m_mutex);
  const std::string head = json{{"destination", destination.string()}, {"size", archive.size()}}.dump() + "\n";
  std::string answer;
  if (!write_all(m_fd, head) || !write_all(m_fd, archive) || !read_line(m_fd, answer)) {
    UnpackedUpload u;
    u.refusal = {500, "the upload unpacker has stopped; restart the server"};
    return u;
  }
  return from_json(json::parse(answer, nullptr, false));
}

}  // namespace yarnfit::service
