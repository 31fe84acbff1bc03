#pragma once
// Raw loopback connections for the service's tests, for what an HTTP client library will not
// send: a connection from a chosen 127.0.0.x address (another client, as the server counts
// them), bytes sent as they are, and the answer read to the server's close.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <string>

namespace yarnfit::testing {

// A connection to 127.0.0.1:port from the loopback address `from`, with a receive timeout.
inline int connect_from(int port, const char* from = "127.0.0.1", double timeout_s = 15) {
  const int s = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in local{};
  local.sin_family = AF_INET;
  ::inet_pton(AF_INET, from, &local.sin_addr);
  EXPECT_EQ(::bind(s, reinterpret_cast<sockaddr*>(&local), sizeof local), 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  EXPECT_EQ(::connect(s, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
  timeval tv{static_cast<time_t>(timeout_s), static_cast<suseconds_t>((timeout_s - static_cast<int>(timeout_s)) * 1e6)};
  ::setsockopt(s, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  return s;
}

// Everything the server sends until it closes (or the receive timeout).
inline std::string read_all(int s) {
  std::string out;
  char buf[4096];
  for (ssize_t n; (n = ::recv(s, buf, sizeof buf, 0)) > 0;) out.append(buf, static_cast<std::size_t>(n));
  return out;
}

}  // namespace yarnfit::testing
