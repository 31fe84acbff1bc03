#include "service/http/request_metrics.hpp"

#include <array>
#include <sstream>

namespace yarnfit::service {

namespace {

// Upper bounds of the latency buckets [s]: a status poll should sit in the first few, an
// upload or a report in the last.
constexpr std::array<double, 10> k_bounds{0.001, 0.0025, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 1.0, 5.0};

// A label value with \ " and newline escaped, as the format asks.
std::string label(const std::string& value) {
  std::string out;
  for (const char c : value) {
    if (c == '\\' || c == '"') out += '\\';
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    out += c;
  }
  return out;
}

}  // namespace

void RequestMetrics::record(const std::string& route, int status, double seconds) {
  const std::lock_guard lock(m_mutex);
  ++m_requests[{route, status}];
  Latency& l = m_latency[route];
  if (l.buckets.empty()) l.buckets.assign(k_bounds.size(), 0);
  for (std::size_t i = 0; i < k_bounds.size(); ++i)
    if (seconds <= k_bounds[i]) ++l.buckets[i];
  ++l.count;
  l.sum += seconds;
}

std::string RequestMetrics::prometheus_text(const std::vector<std::pair<std::string, int>>& jobs) const {
  std::ostringstream out;
  out << "# HELP yarnfit_jobs Fit jobs by state.\n# TYPE yarnfit_jobs gauge\n";
  for (const auto& [state, n] : jobs) out << "yarnfit_jobs{state=\"" << label(state) << "\"} " << n << "\n";
  const std::lock_guard lock(m_mutex);
  out << "# HELP yarnfit_http_requests_total HTTP requests by route and status.\n"
      << "# TYPE yarnfit_http_requests_total counter\n";
  for (const auto& [key, n] : m_requests)
    out << "yarnfit_http_requests_total{route=\"" << label(key.first) << "\",status=\"" << key.second << "\"} " << n
        << "\n";
  out << "# HELP yarnfit_http_request_seconds Time to answer a request, by route.\n"
      << "# TYPE yarnfit_http_request_seconds histogram\n";
  for (const auto& [route, l] : m_latency) {
    const std::string r = label(route);
    for (std::size_t i = 0; i < k_bounds.size(); ++i)
      out << "yarnfit_http_request_seconds_bucket{route=\"" << r << "\",le=\"" << k_bounds[i] << "\"} " << l.buckets[i]
          << "\n";
    out << "yarnfit_http_request_seconds_bucket{route=\"" << r << "\",le=\"+Inf\"} " << l.count << "\n";
    out << "yarnfit_http_request_seconds_sum{route=\"" << r << "\"} " << l.sum << "\n";
    out << "yarnfit_http_request_seconds_count{route=\"" << r << "\"} " << l.count << "\n";
  }
  return out.str();
}

}  // namespace yarnfit::service
