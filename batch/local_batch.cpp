// The local batch: each fabric's job in a forked child process, `jobs` at once. The parent is
// the ledger's only writer; the children report their stage and their outcome through a pipe
// as lines of JSON. A child that crashes takes only its fabric down (recorded as failed with
// its signal); a parent that dies takes its children with it (PR_SET_PDEATHSIG), so nothing
// keeps writing into DIR after a kill, and the next run takes the jobs over.
//
// The parent never runs an OpenMP region before forking (it loads records, hashes files and
// writes the ledger), so each child starts OpenMP afresh.
#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <mutex>
#include <optional>

#include <nlohmann/json.hpp>

#include "batch/batch.hpp"
#include "batch/batch_run.hpp"

namespace yarnfit::batch {

namespace {

using nlohmann::json;

volatile std::sig_atomic_t g_stop_signal = 0;
extern "C" void on_stop_signal(int signal) { g_stop_signal = signal; }

// SIGINT and SIGTERM ask the batch to stop (children killed, their jobs queued again) for
// the duration of the run; the previous handlers come back afterwards.
class StopSignals {
 public:
  StopSignals() {
    g_stop_signal = 0;
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &m_int);
    sigaction(SIGTERM, &sa, &m_term);
  }
  ~StopSignals() {
    sigaction(SIGINT, &m_int, nullptr);
    sigaction(SIGTERM, &m_term, nullptr);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

 private:
  struct sigaction m_int {}, m_term {};
};

void write_all(int fd, const std::string& text) {
  std::size_t at = 0;
  while (at < text.size()) {
    const ssize_t n = ::write(fd, text.data() + at, text.size() - at);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;  // the parent is gone: PDEATHSIG ends this process
    at += static_cast<std::size_t>(n);
  }
}

[[noreturn]] void child_main(const JobSpec& spec, const BatchOptions& options, int out_fd, int lock_fd,
                             pid_t parent) {
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != parent) ::_exit(3);  // the parent died before the line above
  ::close(lock_fd);
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  sigset_t none;  // a parent that takes signals with sigwait (the service) has them blocked
  sigemptyset(&none);
  ::pthread_sigmask(SIG_SETMASK, &none, nullptr);
  std::mutex mutex;
  StageThrottle throttle;
  const StageFn stage = [&](const std::string& s) {
    const std::lock_guard<std::mutex> guard(mutex);
    if (throttle.pass(s)) write_all(out_fd, json{{"stage", s}}.dump() + "\n");
  };
  const JobOutcome outcome = run_fabric_job(spec, options, stage);
  write_all(out_fd, json{{"outcome", to_message(outcome)}}.dump() + "\n");
  ::_exit(0);  // no destructors: the parent's ledger connection is not this process's to close
}

struct Child {
  pid_t pid = -1;
  int fd = -1;
  std::string fabric_id;
  std::string buffer;
  std::optional<JobOutcome> outcome;
};

// Reads what the child wrote; true at end of file.
bool drain(Child& c, BatchRun& run) {
  char buf[4096];
  bool eof = false;
  for (;;) {
    const ssize_t n = ::read(c.fd, buf, sizeof buf);
    if (n > 0) {
      c.buffer.append(buf, static_cast<std::size_t>(n));
      continue;
    }
    if (n == 0) eof = true;
    else if (errno == EINTR) continue;
    break;
  }
  for (std::size_t nl; (nl = c.buffer.find('\n')) != std::string::npos;) {
    const json j = json::parse(c.buffer.substr(0, nl), nullptr, false);
    c.buffer.erase(0, nl + 1);
    if (j.is_discarded()) continue;
    if (j.contains("stage")) run.stage(c.fabric_id, j["stage"].get<std::string>());
    if (j.contains("outcome")) c.outcome = job_outcome_from_message(j["outcome"].get<std::string>());
  }
  return eof;
}

std::string exit_description(int status) {
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    return "the fit process was killed by signal " + std::to_string(sig) + " (" + strsignal(sig) + ")";
  }
  return "the fit process exited with status " + std::to_string(WEXITSTATUS(status)) + " without a result";
}

// Stops a child and waits for it.
void stop_child(Child& c) {
  ::kill(c.pid, SIGKILL);
  int status = 0;
  ::waitpid(c.pid, &status, 0);
  ::close(c.fd);
}

// What the feed asks for between two looks at the children: new fabrics and cancellations.
void follow_feed(BatchRun& run, std::vector<Child>& children) {
  const BatchFeed& feed = run.options().feed;
  for (const BatchFabric& f : feed.take()) run.add(f);
  if (!feed.cancelled) return;
  for (const std::string& key : feed.cancelled()) {
    const auto c = std::find_if(children.begin(), children.end(), [&](const Child& x) { return x.fabric_id == key; });
    if (c != children.end()) {
      stop_child(*c);
      children.erase(c);
    }
    run.cancel(key, k_cancelled_by_owner);
  }
}

}  // namespace

BatchSummary run_batch(const BatchOptions& options) {
  BatchRun run(options);
  const StopSignals signals;
  const BatchFeed& feed = run.options().feed;
  const auto stopping = [&feed] { return g_stop_signal != 0 || (feed.stop && feed.stop()); };
  const std::string host = host_name();
  std::vector<Child> children;
  run.tick(true);
  bool stopped = false;
  while (!(stopped = stopping())) {
    if (feed) follow_feed(run, children);
    while (g_stop_signal == 0 && run.has_queued() && static_cast<int>(children.size()) < run.options().jobs) {
      const JobSpec spec = run.next();
      int fds[2] = {-1, -1};
      const bool piped = ::pipe2(fds, O_CLOEXEC) == 0;
      std::cout.flush();
      std::cerr.flush();
      std::fflush(nullptr);
      const pid_t parent = ::getpid();
      const pid_t pid = piped ? ::fork() : -1;
      if (pid < 0) {
        // Out of processes or descriptors for now: this fabric fails with the reason, the rest go on.
        const std::string why = std::string("cannot start a fit process: ") + std::strerror(errno);
        if (piped) ::close(fds[0]), ::close(fds[1]);
        run.started(spec, host, 0);
        run.finished(spec.fabric_id, {false, why});
        continue;
      }
      if (pid == 0) {
        ::close(fds[0]);
        child_main(spec, run.options(), fds[1], run.lock().fd(), parent);
      }
      ::close(fds[1]);
      ::fcntl(fds[0], F_SETFL, ::fcntl(fds[0], F_GETFL) | O_NONBLOCK);
      children.push_back({pid, fds[0], spec.fabric_id, "", std::nullopt});
      run.started(spec, host, pid);
    }
    if (children.empty() && !feed) break;

    std::vector<pollfd> polls;
    for (const auto& c : children) polls.push_back({c.fd, POLLIN, 0});
    ::poll(polls.data(), polls.size(), 250);
    for (std::size_t i = 0; i < children.size();) {
      Child& c = children[i];
      drain(c, run);
      int status = 0;
      if (::waitpid(c.pid, &status, WNOHANG) != c.pid) {
        ++i;
        continue;
      }
      // Exited: the rest of its messages are in the pipe (the write end is closed now).
      ::fcntl(c.fd, F_SETFL, ::fcntl(c.fd, F_GETFL) & ~O_NONBLOCK);
      while (!drain(c, run)) {
      }
      ::close(c.fd);
      if (!c.outcome && g_stop_signal != 0) run.interrupted(c.fabric_id);  // Ctrl-C reached the child too
      else run.finished(c.fabric_id, c.outcome ? *c.outcome : JobOutcome{false, exit_description(status)});
      children.erase(children.begin() + static_cast<std::ptrdiff_t>(i));
    }
    run.tick();
  }
  for (auto& c : children) {
    stop_child(c);
    run.interrupted(c.fabric_id);
  }
  run.tick(true);
  return run.summary(stopped);
}

}  // namespace yarnfit::batch
