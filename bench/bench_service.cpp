// Load on the fitting service (issue 35's goal: 16 concurrent clients, 2,000 requests — status
// polls, listings and 20 uploads — while 2 fits run: 0 errors, status p99 ≤ 50 ms). Loopback
// only; bounded in count (REQUESTS) and time (the clients stop after 300 s whatever is left).
//
//   build/bench/bench_service [CLIENTS [REQUESTS]]
//
// Starts the service in this process on 127.0.0.1:<any port> over a fresh data folder (two
// fits of the bundled example records with the quick budget, `--jobs 2`, one thread each),
// runs the clients, prints the latency percentiles by kind of request and the errors, and
// stops the service (the fits are stopped with it).

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

}  // namespace

int main(int argc, char** argv) {
  const int clients = argc > 1 ? std::stoi(argv[1]) : 16;
  const int requests = argc > 2 ? std::stoi(argv[2]) : 2000;
  const int uploads = 20;
  const fs::path data = fs::temp_directory_path() / ("yarnfit_bench_service_" + std::to_string(::getpid()));
  fs::remove_all(data);
  std::string token;
  {
    yarnfit::service::Accounts accounts((fs::create_directories(data), data / "accounts.db"));
    token = accounts.add_user("bench", false).token;
  }
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
