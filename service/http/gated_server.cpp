#include "service/http/gated_server.hpp"
#include "numerics/util/error.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace yarnfit::service {

namespace {

using Clock = std::chrono::steady_clock;

// The address a connection comes from (its IP, without the port): the unit of the per-client bound.
std::string peer_address(int sock) {
  sockaddr_storage a{};
  socklen_t n = sizeof a;
  if (::getpeername(sock, reinterpret_cast<sockaddr*>(&a), &n) != 0) return "?";
  char text[INET6_ADDRSTRLEN] = {};
  const void* where = a.ss_family == AF_INET6 ? static_cast<const void*>(&reinterpret_cast<sockaddr_in6*>(&a)->sin6_addr)
                                              : static_cast<const void*>(&reinterpret_cast<sockaddr_in*>(&a)->sin_addr);
  return ::inet_ntop(a.ss_family, where, text, sizeof text) != nullptr ? text : "?";
}

void send_all(int sock, const std::string& text) {
  for (std::size_t at = 0; at < text.size();) {
    const ssize_t n = ::send(sock, text.data() + at, text.size() - at, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    at += static_cast<std::size_t>(n);
  }
}

// A whole response written by the gate itself, before any request was read (`error` is the
// gate's own text: nothing of the client's is quoted).
void answer(int sock, int status, const char* reason, const std::string& error) {
  const std::string body = R"({"error":")" + error + R"(","problems":[]})" + "\n";
  send_all(sock, "HTTP/1.1 " + std::to_string(status) + " " + reason +
                     "\r\nContent-Type: application/json\r\nX-Content-Type-Options: nosniff\r\n"
                     "Connection: close\r\n" + (status == 503 ? "Retry-After: 1\r\n" : "") + "Content-Length: " +
                     std::to_string(body.size()) + "\r\n\r\n" + body);
}

void answer_and_close(int sock, int status, const char* reason, const std::string& error) {
  answer(sock, status, reason, error);
  ::shutdown(sock, SHUT_WR);
  ::close(sock);
}

// Waits up to `timeout_s` for `events` on `sock`; false on a timeout, an error or a stop.
bool wait_for(int sock, short events, time_t timeout_s, const std::atomic<bool>& stopping) {
  const auto until = Clock::now() + std::chrono::seconds(timeout_s);
  while (!stopping) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(until - Clock::now()).count();
    if (left <= 0) return false;
    pollfd p{sock, events, 0};
    // In slices, so that a stop ends a waiting worker soon.
    const int r = ::poll(&p, 1, static_cast<int>(std::min<long long>(left, 250)));
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) return false;
    if (r > 0) return (p.revents & (POLLERR | POLLNVAL)) == 0 || (p.revents & events) != 0;
  }
  return false;
}

// A connection as httplib's request processing reads and writes it: as httplib's own
// SocketStream does (a 4 KiB read buffer; the line reader takes a byte at a time), with the
// service's timeouts, and ending when the server stops.
class GateStream : public httplib::Stream {
 public:
  GateStream(int sock, time_t read_timeout_s, time_t write_timeout_s, const std::atomic<bool>& stopping)
      : m_sock(sock), m_read_timeout(read_timeout_s), m_write_timeout(write_timeout_s), m_stopping(stopping) {}

  bool is_readable() const override { return wait_for(m_sock, POLLIN, m_read_timeout, m_stopping); }
  bool is_writable() const override {
    if (!wait_for(m_sock, POLLOUT, m_write_timeout, m_stopping)) return false;
    // Alive: nothing to read, or something (not an end of stream) to read.
    pollfd p{m_sock, POLLIN, 0};
    if (::poll(&p, 1, 0) == 0) return true;
    char c;
    return ::recv(m_sock, &c, 1, MSG_PEEK | MSG_DONTWAIT) > 0;
  }
  ssize_t read(char* ptr, size_t size) override {
    if (m_off < m_filled) {
      const std::size_t n = std::min(size, m_filled - m_off);
      std::memcpy(ptr, m_buffer.data() + m_off, n);
      m_off += n;
      return static_cast<ssize_t>(n);
    }
    if (!is_readable()) return -1;
    if (size >= m_buffer.size()) return receive(ptr, size);
    m_off = m_filled = 0;
    const ssize_t n = receive(m_buffer.data(), m_buffer.size());
    if (n <= 0) return n;
    m_filled = static_cast<std::size_t>(n);
    const std::size_t given = std::min(size, m_filled);
    std::memcpy(ptr, m_buffer.data(), given);
    m_off = given;
    return static_cast<ssize_t>(given);
  }
  ssize_t write(const char* ptr, size_t size) override {
    if (!is_writable()) return -1;
    for (;;) {
      const ssize_t n = ::send(m_sock, ptr, size, MSG_NOSIGNAL);
      if (n < 0 && errno == EINTR) continue;
      return n;
    }
  }
  void get_remote_ip_and_port(std::string& ip, int& port) const override { address_of(true, ip, port); }
  void get_local_ip_and_port(std::string& ip, int& port) const override { address_of(false, ip, port); }
  socket_t socket() const override { return m_sock; }

 private:
  ssize_t receive(char* ptr, std::size_t size) const {
    for (;;) {
      const ssize_t n = ::recv(m_sock, ptr, size, 0);
      if (n < 0 && errno == EINTR) continue;
      return n;
    }
  }
  void address_of(bool peer, std::string& ip, int& port) const {
    sockaddr_storage a{};
    socklen_t n = sizeof a;
    const int r = peer ? ::getpeername(m_sock, reinterpret_cast<sockaddr*>(&a), &n)
                       : ::getsockname(m_sock, reinterpret_cast<sockaddr*>(&a), &n);
    ip.clear();
    port = 0;
    if (r != 0) return;
    char text[INET6_ADDRSTRLEN] = {};
    if (a.ss_family == AF_INET6) {
      const auto* six = reinterpret_cast<const sockaddr_in6*>(&a);
      if (::inet_ntop(AF_INET6, &six->sin6_addr, text, sizeof text) != nullptr) ip = text;
      port = ntohs(six->sin6_port);
    } else {
      const auto* four = reinterpret_cast<const sockaddr_in*>(&a);
      if (::inet_ntop(AF_INET, &four->sin_addr, text, sizeof text) != nullptr) ip = text;
      port = ntohs(four->sin_port);
    }
  }

  int m_sock;
  time_t m_read_timeout, m_write_timeout;
  const std::atomic<bool>& m_stopping;
  std::array<char, 4096> m_buffer{};
  std::size_t m_off = 0, m_filled = 0;
};

// httplib's accept loop hands each connection to a task queue; this one runs the hand-over at
// once on the accepting thread (it only registers the connection with the gate).
class AtOnce : public httplib::TaskQueue {
 public:
  void enqueue(std::function<void()> fn) override { fn(); }
  void shutdown() override {}
};

}  // namespace

struct GatedServer::Gate {
  // A connection waiting for the head of its next request.
  struct Waiting {
    std::string client;
    Clock::time_point deadline;
    int served = 0;        // requests served on it so far
    bool started = false;  // a byte of the next head has arrived
  };

  Gate(GatedServer& s, ConnectionLimits l, int read_s, int write_s)
      : server(s), limits(l), read_timeout_s(read_s), write_timeout_s(write_s),
        head(limits.max_head_bytes + 1), workers(static_cast<std::size_t>(std::max(1, l.workers))) {
    epoll = ::epoll_create1(EPOLL_CLOEXEC);
    wake = ::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
    if (epoll < 0 || wake < 0) throw Error(ErrorCategory::system, "cannot start the connection gate (epoll)");
    epoll_event ev{};
    ev.events = EPOLLIN;
    ev.data.fd = wake;
    ::epoll_ctl(epoll, EPOLL_CTL_ADD, wake, &ev);
    thread = std::thread([this] { loop(); });
  }

  ~Gate() { stop(); }

  // From acceptance: refused over a bound, else waiting for its first head.
  void admit(int sock) {
    std::string client = peer_address(sock);
    std::string refusal;
    {
      const std::lock_guard lock(mutex);
      if (stopping) refusal = "the server is stopping";
      else if (open_total >= limits.total)
        refusal = "the server holds " + std::to_string(limits.total) + " connections; try again later";
      else if (open_of[client] >= limits.per_client)
        refusal = "your address holds " + std::to_string(limits.per_client) + " connections; close one first";
      if (refusal.empty()) {
        ++open_total;
        ++open_of[client];
      } else {
        ++counts.refused;
      }
    }
    if (!refusal.empty()) return answer_and_close(sock, 503, "Service Unavailable", refusal);
    wait_for_head(sock, {std::move(client), Clock::now() + std::chrono::milliseconds(limits.head_deadline_ms), 0, false});
  }

  void wait_for_head(int sock, Waiting w) {
    {
      const std::lock_guard lock(mutex);
      waiting[sock] = std::move(w);
    }
    epoll_event ev{};
    ev.events = EPOLLIN | EPOLLRDHUP | EPOLLET;
    ev.data.fd = sock;
    if (::epoll_ctl(epoll, EPOLL_CTL_ADD, sock, &ev) != 0) close_waiting(sock);
    poke();  // its deadline may be the nearest now
  }

  void poke() const {
    const std::uint64_t one = 1;
    [[maybe_unused]] const ssize_t n = ::write(wake, &one, sizeof one);
  }

  // Forgets a connection, waiting or served, and closes it: uncounted first, so that a client
  // that saw the close and connects again finds its place free.
  void release(int sock, const std::string& client) {
    {
      const std::lock_guard lock(mutex);
      --open_total;
      if (--open_of[client] <= 0) open_of.erase(client);
    }
    ::shutdown(sock, SHUT_RDWR);
    ::close(sock);
  }

  void close_waiting(int sock, int status = 0) {
    ::epoll_ctl(epoll, EPOLL_CTL_DEL, sock, nullptr);
    std::string client;
    {
      const std::lock_guard lock(mutex);
      const auto w = waiting.find(sock);
      if (w == waiting.end()) return;
      client = w->second.client;
      waiting.erase(w);
    }
    if (status == 408)
      answer(sock, 408, "Request Timeout",
             "the request's head did not arrive within " + std::to_string(limits.head_deadline_ms) + " ms");
    // httplib's own word for a head it cannot read (its header lines end at 8 KiB).
    if (status == 400)
      answer(sock, 400, "Bad Request",
             "the request cannot be read (a head over " + std::to_string(limits.max_head_bytes) +
                 " bytes, or a header line over 8 KiB)");
    release(sock, client);
  }

  // What has arrived on a waiting connection: a whole head goes to a worker.
  void look_at(int sock) {
    const ssize_t n = ::recv(sock, head.data(), head.size(), MSG_PEEK | MSG_DONTWAIT);
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) return;
    if (n <= 0) return close_waiting(sock);  // closed by the client, or an error
    const std::string_view seen(head.data(), static_cast<std::size_t>(n));
    if (seen.find("\r\n\r\n") != std::string_view::npos || seen.find("\n\n") != std::string_view::npos)
      return hand_over(sock);
    if (static_cast<std::size_t>(n) > limits.max_head_bytes) return close_waiting(sock, 400);
    const std::lock_guard lock(mutex);
    const auto w = waiting.find(sock);
    if (w == waiting.end() || w->second.started) return;
    w->second.started = true;
    // A kept-alive connection's next head has the whole head deadline from its first byte (a
    // new connection's counts from its acceptance).
    if (w->second.served > 0)
      w->second.deadline = std::max(w->second.deadline, Clock::now() + std::chrono::milliseconds(limits.head_deadline_ms));
  }

  void hand_over(int sock) {
    ::epoll_ctl(epoll, EPOLL_CTL_DEL, sock, nullptr);
    Waiting w;
    {
      const std::lock_guard lock(mutex);
      const auto found = waiting.find(sock);
      if (found == waiting.end()) return;
      w = std::move(found->second);
      waiting.erase(found);
      ++counts.serving;
    }
    workers.enqueue([this, sock, w = std::move(w)]() mutable { serve(sock, std::move(w)); });
  }

  // On a worker: one request, then back to the gate (kept alive) or closed.
  void serve(int sock, Waiting w) {
    GateStream stream(sock, read_timeout_s, write_timeout_s, stopping);
    const bool last = w.served + 1 >= limits.requests_per_connection;
    bool closed = false;
    const bool ok = server.process_request(stream, last, closed, nullptr);
    {
      const std::lock_guard lock(mutex);
      --counts.serving;
    }
    if (!ok || closed || last || stopping) return release(sock, w.client);
    wait_for_head(sock, {std::move(w.client), Clock::now() + std::chrono::seconds(limits.keep_alive_s), w.served + 1, false});
  }

  // Closes what is past its deadline; returns the milliseconds to the next deadline.
  int expire() {
    const auto now = Clock::now();
    std::vector<std::pair<int, bool>> late;  // socket, had started a head
    auto next = now + std::chrono::seconds(1);
    {
      const std::lock_guard lock(mutex);
      for (const auto& [sock, w] : waiting) {
        if (w.deadline <= now) late.emplace_back(sock, w.started);
        else next = std::min(next, w.deadline);
      }
      counts.timed_out += static_cast<long long>(late.size());
    }
    for (const auto& [sock, started] : late) close_waiting(sock, started ? 408 : 0);
    return static_cast<int>(std::chrono::duration_cast<std::chrono::milliseconds>(next - now).count()) + 1;
  }

  void loop() {
    std::array<epoll_event, 64> events{};
    int timeout_ms = 1000;
    while (!stopping) {
      const int n = ::epoll_wait(epoll, events.data(), static_cast<int>(events.size()), timeout_ms);
      if (n < 0 && errno != EINTR) break;
      for (int i = 0; i < n; ++i) {
        const int fd = events[static_cast<std::size_t>(i)].data.fd;
        if (fd == wake) {
          std::uint64_t drained = 0;
          [[maybe_unused]] const ssize_t r = ::read(wake, &drained, sizeof drained);
          continue;
        }
        look_at(fd);
      }
      timeout_ms = expire();
    }
  }

  void stop() {
    {
      const std::lock_guard lock(mutex);
      if (stopped) return;
      stopped = true;
      stopping = true;
    }
    poke();
    if (thread.joinable()) thread.join();
    workers.shutdown();  // the requests being served end (their streams see `stopping`)
    std::vector<int> left;
    {
      const std::lock_guard lock(mutex);
      for (const auto& [sock, w] : waiting) left.push_back(sock);
    }
    for (const int sock : left) close_waiting(sock);
    ::close(epoll);
    ::close(wake);
  }

  GatedServer& server;
  ConnectionLimits limits;
  time_t read_timeout_s, write_timeout_s;
  std::vector<char> head;  // the gate thread's look at a head
  httplib::ThreadPool workers;
  int epoll = -1, wake = -1;
  std::thread thread;

  mutable std::mutex mutex;  // guards everything below
  std::map<int, Waiting> waiting;
  std::map<std::string, int> open_of;
  int open_total = 0;
  GateCounts counts;
  std::atomic<bool> stopping{false};
  bool stopped = false;
};

GatedServer::GatedServer(ConnectionLimits limits, int read_timeout_s, int write_timeout_s)
    : m_gate(std::make_unique<Gate>(*this, limits, read_timeout_s, write_timeout_s)) {
  new_task_queue = [] { return new AtOnce; };
  set_read_timeout(read_timeout_s, 0);
  set_write_timeout(write_timeout_s, 0);
}

GatedServer::~GatedServer() { shut_down(); }

void GatedServer::size_backlog() {
  // listen() again on a listening socket sets its backlog anew (Linux).
  if (svr_sock_ != INVALID_SOCKET) ::listen(svr_sock_, m_gate->limits.backlog);
}

void GatedServer::shut_down() {
  // As Server::stop, but also before the listener has started (stop() does nothing until then,
  // and a listener started afterwards would never end): its socket is closed either way.
  const socket_t sock = svr_sock_.exchange(INVALID_SOCKET);
  if (sock != INVALID_SOCKET) {
    ::shutdown(sock, SHUT_RDWR);
    ::close(sock);
  }
  m_gate->stop();
}

GateCounts GatedServer::counts() const {
  const std::lock_guard lock(m_gate->mutex);
  GateCounts c = m_gate->counts;
  c.waiting = static_cast<long long>(m_gate->waiting.size());
  return c;
}

bool GatedServer::process_and_close_socket(socket_t sock) {
  m_gate->admit(sock);
  return true;
}

}  // namespace yarnfit::service
