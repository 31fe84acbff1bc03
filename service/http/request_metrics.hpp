#pragma once
// Requests and their latency by route, and the text /metrics answers in the Prometheus
// exposition format (text/plain; version=0.0.4): yarnfit_http_requests_total{route,status},
// yarnfit_http_request_seconds{route} as a histogram, and the gauges the caller adds (jobs by
// state). Thread-safe: every handler thread records into it.

#include <map>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace yarnfit::service {

class RequestMetrics {
 public:
  void record(const std::string& route, int status, double seconds);
  // The exposition text; `jobs` are (state, count) pairs for yarnfit_jobs{state}.
  [[nodiscard]] std::string prometheus_text(const std::vector<std::pair<std::string, int>>& jobs) const;

 private:
  struct Latency {
    std::vector<long> buckets;  // counts of requests ≤ each bound of k_bounds
    long count = 0;
    double sum = 0;
  };
  mutable std::mutex m_mutex;
  std::map<std::pair<std::string, int>, long> m_requests;
  std::map<std::string, Latency> m_latency;
};

}  // namespace yarnfit::service
