#pragma once
// cpp-httplib's server with a gate in front of its workers (issue 47, defect 4).
//
// httplib gives every accepted connection a worker thread at once, and a worker waits there for
// the request to arrive: 200 connections that send nothing held all 32 workers for seconds, and
// /healthz waited behind them. Here a connection gets a worker only once the head of a request
// (request line and headers) has arrived whole; until then it is one file descriptor in an epoll
// set watched by a single gate thread, which
// - closes it when its head has not arrived within `head_deadline_ms` of its acceptance (or
//   of its first byte after a kept-alive request; an idle kept-alive connection waits at most
//   `keep_alive_s`), answering 408 when a partial head had arrived;
// - refuses it at once with 503 when its address already holds `per_client` connections, or the
//   server `total` (a connection counts from acceptance to close, waiting or served);
// - answers 400 when the head grows past `max_head_bytes` without ending (as httplib answers a
//   header line over 8 KiB).
// A kept-alive connection goes back to the gate between requests, so idle clients hold no
// worker either. The listening socket's backlog is `backlog` (httplib's own is 5).
//
// The worker runs httplib's own request processing (Server::process_request) on the
// connection, so routing, handlers and responses are httplib's unchanged.

#include <httplib.h>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "service/http/connection_limits.hpp"

namespace yarnfit::service {

class GatedServer : public httplib::Server {
 public:
  GatedServer(ConnectionLimits limits, int read_timeout_s, int write_timeout_s);
  ~GatedServer() override;
  GatedServer(const GatedServer&) = delete;
  GatedServer& operator=(const GatedServer&) = delete;

  // After bind_to_port: the listening socket's backlog set to the limits'.
  void size_backlog();
  // Stops serving: httplib's listener, then the gate and the workers (idempotent).
  void shut_down();
  [[nodiscard]] GateCounts counts() const;

 private:
  // Called by httplib's accept loop for each connection: hands it to the gate (never blocks).
  bool process_and_close_socket(socket_t sock) override;

  struct Gate;
  std::unique_ptr<Gate> m_gate;
};

}  // namespace yarnfit::service
