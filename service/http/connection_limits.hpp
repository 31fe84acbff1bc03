#pragma once
// The bounds on the service's connections (service/http/gated_server.hpp says how they hold).

#include <cstddef>

namespace yarnfit::service {

struct ConnectionLimits {
  int head_deadline_ms = 10000;  // a request's head must arrive whole within this
  int keep_alive_s = 5;          // an idle kept-alive connection waits this long for its next request
  int per_client = 64;           // connections open at once from one address
  int total = 512;               // connections open at once in all
  int backlog = 1024;            // connections the kernel queues before they are accepted
  int workers = 32;              // requests served at once (an event stream holds one)
  std::size_t max_head_bytes = 16u << 10;
  int requests_per_connection = 1000;
};

// What the gate has done, for /metrics and the tests.
struct GateCounts {
  long long waiting = 0;       // connections waiting for a request head now
  long long serving = 0;       // connections a worker serves now
  long long refused = 0;       // refused at acceptance (over a bound), since start
  long long timed_out = 0;     // closed at their deadline, since start
};

}  // namespace yarnfit::service
