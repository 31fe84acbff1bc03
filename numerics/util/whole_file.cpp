#include "numerics/util/whole_file.hpp"
#include "numerics/util/error.hpp"

#include <cerrno>
#include <charconv>
#include <cstring>
#include <fcntl.h>
#include <signal.h>
#include <stdexcept>
#include <unistd.h>

namespace yarnfit::numerics {

namespace {

std::function<void(const std::filesystem::path&)>& before_rename_hook() {
  static std::function<void(const std::filesystem::path&)> hook;
  return hook;
}

// ".NAME.tmp" followed by the pid of a process that no longer runs.
void remove_stale_temporaries(const std::filesystem::path& folder, const std::string& name) {
  const std::string prefix = "." + name + ".tmp";
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
    const std::string other = entry.path().filename().string();
    if (other.size() <= prefix.size() || other.compare(0, prefix.size(), prefix) != 0) continue;
    long pid = 0;
    const char* first = other.data() + prefix.size();
    const char* last = other.data() + other.size();
    const auto [end, err] = std::from_chars(first, last, pid);
    if (err != std::errc() || end != last || pid <= 0 || pid == ::getpid()) continue;
    if (process_is_gone(pid)) std::filesystem::remove(entry.path(), ec);
  }
}

}  // namespace

bool process_is_gone(long pid) { return pid > 0 && ::kill(static_cast<pid_t>(pid), 0) == -1 && errno == ESRCH; }

namespace detail {
void set_before_rename_hook(std::function<void(const std::filesystem::path&)> hook) {
  before_rename_hook() = std::move(hook);
}
}  // namespace detail

void write_file_whole(const std::filesystem::path& file, const std::string& text) {
  const auto folder = file.has_parent_path() ? file.parent_path() : std::filesystem::path(".");
  const std::string name = file.filename().string();
  const auto tmp = folder / ("." + name + ".tmp" + std::to_string(::getpid()));
  const auto fail = [&](int error) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw Error(ErrorCategory::io, "cannot write " + file.string() + ": " + std::strerror(error));
  };
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail(errno);
  for (std::size_t done = 0; done < text.size();) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int error = n < 0 ? errno : EIO;
      ::close(fd);
      fail(error);
    }
    done += static_cast<std::size_t>(n);
  }
  // Synced before the rename: after a power cut the name holds the old file or the new one.
  if (::fsync(fd) != 0) {
    const int error = errno;
    ::close(fd);
    fail(error);
  }
  if (::close(fd) != 0) fail(errno);
  try {
    if (before_rename_hook()) before_rename_hook()(tmp);
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw;
  }
  if (::rename(tmp.c_str(), file.c_str()) != 0) fail(errno);
  remove_stale_temporaries(folder, name);
}

}  // namespace yarnfit::numerics
