// Load on the fitting service (issue 35's goal: 16 concurrent clients, 2,000 requests — status
// polls, listings and 20 uploads — while 2 fits run: 0 errors, status p99 ≤ 50 ms). Loopback
// only; bounded in count (REQUESTS) and time (the clients stop after 300 s whatever is left).
//
//   build/bench/bench_service [CLIENTS [REQUESTS]]
//   build/bench/bench_service starve [POLLERS [SILENT [SECONDS]]]
//
// Starts the service in this process on 127.0.0.1:<any port> over a fresh data folder (two
// fits of the bundled example records with the quick budget, `--jobs 2`, one thread each),
// runs the clients, prints the latency percentiles by kind of request and the errors, and
// stops the service (the fits are stopped with it).
//
// `starve` (issue 47's goal: /healthz within 1 s beside 200 silent connections, the job list's
// p99 ≤ 100 ms with 50 polling clients): POLLERS clients (50) poll the job list and /healthz
// for SECONDS (10), first alone, then beside SILENT connections (200, from 50 loopback
// addresses 127.0.2.x) that send nothing and reconnect whenever the server closes them; a
// prober times /healthz on a fresh connection every 50 ms. Prints p50/p99/max per phase.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <archive.h>
#include <archive_entry.h>

#include <nlohmann/json.hpp>

#include "service/accounts/accounts.hpp"
#include "service/http/fitting_service.hpp"

// After the project's headers: <httplib.h> brings <resolv.h>, whose `_res` macro breaks Eigen.
#include <httplib.h>

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

namespace {

const fs::path k_examples = fs::path(YARNFIT_SOURCE_DIR) / "examples" / "fabrics";

std::string read(const fs::path& f) {
  std::ifstream in(f, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

la_ssize_t append(archive*, void* out, const void* buffer, size_t size) {
  static_cast<std::string*>(out)->append(static_cast<const char*>(buffer), size);
  return static_cast<la_ssize_t>(size);
}

// The example record `name` zipped as its folder, with the id `id`.
std::string zipped(const std::string& name, const std::string& id) {
  std::string out;
  archive* a = archive_write_new();
  archive_write_set_format_zip(a);
  archive_write_open(a, &out, nullptr, append, nullptr);
  for (const auto& e : fs::directory_iterator(k_examples / name)) {
    std::string data = read(e.path());
    if (e.path().filename() == "fabric.yaml") {
      const auto at = data.find("id: " + name);
      if (at != std::string::npos) data.replace(at, 4 + name.size(), "id: " + id);
    }
    archive_entry* entry = archive_entry_new();
    archive_entry_set_pathname(entry, (id + "/" + e.path().filename().string()).c_str());
    archive_entry_set_filetype(entry, AE_IFREG);
    archive_entry_set_perm(entry, 0644);
    archive_entry_set_size(entry, static_cast<la_int64_t>(data.size()));
    archive_write_header(a, entry);
    archive_write_data(a, data.data(), data.size());
    archive_entry_free(entry);
  }
  archive_write_close(a);
  archive_write_free(a);
  return out;
}

struct Sample {
  std::string kind;
  double ms = 0;
  bool error = false;
};

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const auto i = static_cast<std::size_t>(std::ceil(p / 100.0 * static_cast<double>(v.size()))) - 1;
  return v[std::min(i, v.size() - 1)];
}

// A fresh data folder named `name` beside the temporary files with one user, "bench"; its token.
fs::path fresh_data(const std::string& name, std::string& token) {
  const fs::path data = fs::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
  fs::remove_all(data);
  yarnfit::service::Accounts accounts((fs::create_directories(data), data / "accounts.db"));
  token = accounts.add_user("bench", false).token;
  return data;
}

// A connection to 127.0.0.1:port from loopback address `from`; -1 when it fails.
int connect_from(int port, const std::string& from) {
  const int s = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in local{};
  local.sin_family = AF_INET;
  ::inet_pton(AF_INET, from.c_str(), &local.sin_addr);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::bind(s, reinterpret_cast<sockaddr*>(&local), sizeof local) != 0 ||
      ::connect(s, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
    ::close(s);
    return -1;
  }
  timeval tv{30, 0};
  ::setsockopt(s, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  return s;
}

// GET /healthz on a fresh connection: milliseconds to the whole answer, and whether it was 200.
std::pair<double, bool> probe_healthz(int port) {
  const auto t0 = Clock::now();
  const int s = connect_from(port, "127.0.0.1");
  if (s < 0) return {std::chrono::duration<double, std::milli>(Clock::now() - t0).count(), false};
  const std::string request = "GET /healthz HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n";
  ::send(s, request.data(), request.size(), MSG_NOSIGNAL);
  std::string answer;
  char buf[1024];
  for (ssize_t n; (n = ::recv(s, buf, sizeof buf, 0)) > 0;) answer.append(buf, static_cast<std::size_t>(n));
  ::close(s);
  return {std::chrono::duration<double, std::milli>(Clock::now() - t0).count(), answer.rfind("HTTP/1.1 200", 0) == 0};
}

void print_row(const char* phase, const char* what, const std::vector<double>& ms, int errors) {
  std::printf("%-22s %-10s %7zu %6d %9.2f %9.2f %9.2f\n", phase, what, ms.size(), errors, percentile(ms, 50),
              percentile(ms, 99), percentile(ms, 100));
}

// The `starve` scenario (see the top of the file).
int starve(int pollers, int silent, int seconds) {
  std::string token;
  const fs::path data = fresh_data("yarnfit_bench_starve", token);
  yarnfit::service::ServiceOptions o;
  o.port = 0;
  auto service = std::make_unique<yarnfit::service::FittingService>(data, o);
  const int port = service->bind();
  std::thread server([&] { service->run(); });
  httplib::Client setup("127.0.0.1", port);
  setup.set_bearer_token_auth(token.c_str());
  if (const auto up = setup.Post("/api/v1/fabrics", zipped("stockinette_demo", "stockinette_demo"), "application/zip");
      !up || up->status != 201) {
    std::fprintf(stderr, "bench_service: the upload failed\n");
    return 1;
  }

  std::printf("bench_service starve: %d polling clients, %d silent connections, %d s a phase\n", pollers, silent, seconds);
  std::printf("%-22s %-10s %7s %6s %9s %9s %9s\n", "phase", "request", "count", "errors", "p50 ms", "p99 ms", "max ms");
  std::vector<double> worst_healthz, list_p99;
  for (const bool with_silent : {false, true}) {
    std::atomic<bool> stop{false};
    std::vector<std::thread> attackers;
    std::atomic<long> reconnects{0};
    if (with_silent)
      for (int i = 0; i < silent; ++i)
        attackers.emplace_back([&, i] {
          // Send nothing; when the server closes, come back at once.
          const std::string from = "127.0.2." + std::to_string(1 + i % 50);
          while (!stop) {
            const int s = connect_from(port, from);
            if (s < 0) {
              std::this_thread::sleep_for(std::chrono::milliseconds(100));
              continue;
            }
            timeval tv{0, 200000};
            ::setsockopt(s, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
            char c;
            while (!stop) {
              const ssize_t n = ::recv(s, &c, 1, 0);
              if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK)) break;
            }
            ::close(s);
            ++reconnects;
          }
        });
    std::this_thread::sleep_for(std::chrono::milliseconds(with_silent ? 500 : 0));  // the silent ones are in
    std::mutex mutex;
    std::vector<double> list_ms, health_ms;
    int list_errors = 0, health_errors = 0;
    const auto until = Clock::now() + std::chrono::seconds(seconds);
    std::vector<std::thread> threads;
    for (int c = 0; c < pollers; ++c)
      threads.emplace_back([&] {
        httplib::Client client("127.0.0.1", port);
        client.set_bearer_token_auth(token.c_str());
        client.set_keep_alive(true);
        client.set_read_timeout(60, 0);
        std::vector<double> mine;
        int errors = 0;
        while (Clock::now() < until) {
          const auto t0 = Clock::now();
          const auto r = client.Get("/api/v1/jobs");
          mine.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
          errors += !r || r->status != 200;
          std::this_thread::sleep_for(std::chrono::milliseconds(100));  // a page polls, it does not hammer
        }
        const std::lock_guard lock(mutex);
        list_ms.insert(list_ms.end(), mine.begin(), mine.end());
        list_errors += errors;
      });
    threads.emplace_back([&] {
      while (Clock::now() < until) {
        const auto [ms, ok] = probe_healthz(port);
        const std::lock_guard lock(mutex);
        health_ms.push_back(ms);
        health_errors += !ok;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
    });
    for (auto& t : threads) t.join();
    stop = true;
    for (auto& t : attackers) t.join();
    const char* phase = with_silent ? "beside silent conns" : "pollers alone";
    print_row(phase, "job list", list_ms, list_errors);
    print_row(phase, "/healthz", health_ms, health_errors);
    if (with_silent) std::printf("%-22s silent connections closed by the server and reopened: %ld\n", "", reconnects.load());
    worst_healthz.push_back(percentile(health_ms, 100));
    list_p99.push_back(percentile(list_ms, 99));
  }
  const bool met = worst_healthz.back() <= 1000 && list_p99.front() <= 100 && list_p99.back() <= 100;
  std::printf("goal: /healthz within 1 s beside %d silent connections (max %.1f ms), job list p99 <= 100 ms with %d clients "
              "(%.1f ms alone, %.1f ms beside): %s\n",
              silent, worst_healthz.back(), pollers, list_p99.front(), list_p99.back(), met ? "met" : "MISSED");
  service->stop();
  server.join();
  service.reset();
  fs::remove_all(data);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && std::string(argv[1]) == "starve")
    return starve(argc > 2 ? std::stoi(argv[2]) : 50, argc > 3 ? std::stoi(argv[3]) : 200, argc > 4 ? std::stoi(argv[4]) : 10);
  const int clients = argc > 1 ? std::stoi(argv[1]) : 16;
  const int requests = argc > 2 ? std::stoi(argv[2]) : 2000;
  const int uploads = 20;
  std::string token;
  const fs::path data = fresh_data("yarnfit_bench_service", token);
  yarnfit::service::ServiceOptions o;
  o.port = 0;
  o.jobs.jobs = 2;
  o.jobs.threads_per_job = 1;
  o.jobs.active_per_user = 4;
  auto service = std::make_unique<yarnfit::service::FittingService>(data, o);
  const int port = service->bind();
  std::thread server([&] { service->run(); });

  httplib::Client setup("127.0.0.1", port);
  setup.set_bearer_token_auth(token.c_str());
  const std::vector<std::string> fitted{"stockinette_demo", "interlock_demo"};
  for (const auto& id : fitted) {
    const auto up = setup.Post("/api/v1/fabrics", zipped(id, id), "application/zip");
    const auto fit = setup.Post("/api/v1/fabrics/" + id + "/fits", R"({"budget": "quick"})", "application/json");
    if (!up || up->status != 201 || !fit || fit->status != 202) {
      std::fprintf(stderr, "bench_service: could not start the fit of %s\n", id.c_str());
      return 1;
    }
  }
  // The two fits are running before the load starts.
  for (int i = 0; i < 600; ++i) {
    const json jobs = json::parse(setup.Get("/api/v1/jobs")->body);
    int running = 0;
    for (const auto& j : jobs["jobs"]) running += j["state"] == "running";
    if (running == 2) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }

  std::atomic<int> next{0};
  std::mutex mutex;
  std::vector<Sample> samples;
  const auto deadline = Clock::now() + std::chrono::seconds(300);
  const auto start = Clock::now();
  std::vector<std::thread> threads;
  for (int c = 0; c < clients; ++c)
    threads.emplace_back([&, c] {
      httplib::Client client("127.0.0.1", port);
      client.set_bearer_token_auth(token.c_str());
      client.set_keep_alive(true);
      client.set_tcp_nodelay(true);
      std::vector<Sample> mine;
      for (int n; (n = next++) < requests && Clock::now() < deadline;) {
        // Every 100th request is an upload (20 of 2,000), a third of the rest listings, the
        // others status polls of the two fits.
        Sample s;
        const bool upload = n % (requests / uploads) == 0;
        const std::string archive = upload ? zipped("stockinette_light", "load_" + std::to_string(n)) : "";
        const auto t0 = Clock::now();
        int expected = 200;
        s.kind = upload ? "upload" : n % 3 == 0 ? "listing" : "status";
        if (upload) expected = 201;
        const httplib::Result r =
            upload ? client.Post("/api/v1/fabrics", archive, "application/zip")
            : s.kind == "listing" ? client.Get(n % 2 ? "/api/v1/fabrics" : "/api/v1/jobs")
                                  : client.Get("/api/v1/jobs/" + fitted[static_cast<std::size_t>(n + c) % 2]);
        s.ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        s.error = !r || r->status != expected;
        if (s.error)
          std::fprintf(stderr, "error: %s %s\n", s.kind.c_str(), r ? std::to_string(r->status).c_str() : httplib::to_string(r.error()).c_str());
        mine.push_back(s);
      }
      const std::lock_guard lock(mutex);
      samples.insert(samples.end(), mine.begin(), mine.end());
    });
  for (auto& t : threads) t.join();
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();

  int running = 0;
  const json jobs_after = json::parse(setup.Get("/api/v1/jobs")->body);
  for (const auto& j : jobs_after["jobs"]) {
    running += j["state"] == "running";
    if (j["state"] != "running") std::printf("fit of %s: %s %s\n", j["id"].get<std::string>().c_str(), j["state"].get<std::string>().c_str(), j["error"].get<std::string>().c_str());
  }
  std::map<std::string, std::vector<double>> by_kind;
  std::map<std::string, int> errors;
  for (const auto& s : samples) {
    by_kind[s.kind].push_back(s.ms);
    errors[s.kind] += s.error;
  }
  std::printf("bench_service: %d clients, %zu requests in %.1f s (%.0f/s), fits running at the end: %d\n", clients,
              samples.size(), seconds, static_cast<double>(samples.size()) / seconds, running);
  std::printf("%-8s %6s %6s %8s %8s %8s %8s\n", "kind", "count", "errors", "p50 ms", "p90 ms", "p99 ms", "max ms");
  int total_errors = 0;
  for (const auto& [kind, ms] : by_kind) {
    std::printf("%-8s %6zu %6d %8.2f %8.2f %8.2f %8.2f\n", kind.c_str(), ms.size(), errors[kind], percentile(ms, 50),
                percentile(ms, 90), percentile(ms, 99), percentile(ms, 100));
    total_errors += errors[kind];
  }
  const double status_p99 = percentile(by_kind["status"], 99);
  std::printf("goal: 0 errors (%d), status p99 <= 50 ms (%.2f ms): %s\n", total_errors, status_p99,
              total_errors == 0 && status_p99 <= 50 ? "met" : "MISSED");

  service->stop();
  server.join();
  service.reset();
  fs::remove_all(data);
  return total_errors == 0 ? 0 : 1;
}
