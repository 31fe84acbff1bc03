// Fits through the service's API (service/jobs/fit_jobs.hpp behind service/http): a synthetic
// knit uploaded, its fit started, followed on the event stream to its end, its results and
// reports downloaded; bad requests refused with the field named; the per-user limit; cancel;
// and `kill -9` of a `yarnfit serve` inside a swarm, restarted, ending with bitwise the results
// of an uninterrupted run.
#include <gtest/gtest.h>

#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <functional>
#include <map>
#include <set>
#include <memory>
#include <thread>

#include <nlohmann/json.hpp>

#include "batch/batch.hpp"
#include "batch/ledger.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"
#include "service/accounts/accounts.hpp"
#include "service/http/fitting_service.hpp"
#include "tests/fabrics_db/fabric_fixture.hpp"
#include "tests/service/served_fixture.hpp"
#include "tests/service/test_archives.hpp"
#include "tests/test_support.hpp"
#include "yarn_fit/model/yarn_params.hpp"

// After the project's headers: <httplib.h> brings <resolv.h>, whose `_res` macro breaks Eigen.
#include <httplib.h>

namespace yarnfit::service {
namespace {

using namespace yarnfit::testing;  // fs, json, the served fixture
using namespace yarnfit::testing::archives;


// A fit small enough for a test, with a swarm (and its checkpoint) and a local step.
const json k_small{{"global_method", "swarm"}, {"local_method", "implicit-filtering"},
                   {"particles", 3},           {"iterations", 3},
                   {"samples", 2},             {"local_samples", 3},
                   {"local_evaluations", 3},   {"no_profile", true},
                   {"no_rest_shape", true}};

// Synthetic knit records (their curves simulated from known yarn parameters), zipped.
class Records {
 public:
  static Records& get() {
    static Records r;
    return r;
  }
  std::string zipped(const std::string& id) {
    if (!m_zips.count(id)) {
      const fs::path src = m_dir / ("src_" + id);
      const auto r = run_cli("synth yarn --pattern " + quoted(shared_stockinette()) + " --params " +
                             quoted(m_dir / "params.yaml") + " --out " + quoted(src) + " --id " + id +
                             " --family soft --max-stretch 0.15 --directions weft --points 4 -q");
      EXPECT_EQ(r.exit_code, 0) << r.err;
      std::vector<Item> items;
      for (const auto& e : fs::directory_iterator(src / "fabric"))
        items.push_back(file(id + "/" + e.path().filename().string(), read_file(e.path())));
      m_zips[id] = make_archive(items, Kind::zip);
    }
    return m_zips[id];
  }

 private:
  Records() {
    db::Problems problems;
    const auto tile = db::read_pyp(shared_stockinette(), problems);
    EXPECT_TRUE(tile) << problems.to_string();
    if (tile)
      write_file(m_dir / "params.yaml",
                 yarn::to_json(yarn::default_params({400.0, db::compute_tile_facts(*tile).r_est})).dump(2) + "\n");
  }
  ScratchDir m_dir{"service_records"};
  std::map<std::string, std::string> m_zips;
};

httplib::Client client_on(int port, const std::string& token) {
  httplib::Client c("127.0.0.1", port);
  c.set_bearer_token_auth(token.c_str());
  c.set_read_timeout(60, 0);
  return c;
}

json body_of(const httplib::Result& r) {
  EXPECT_TRUE(r);
  return r ? json::parse(r->body, nullptr, false) : json();
}

// Polls the job until `pred` holds or `seconds` pass; returns the last state seen.
json wait_for(httplib::Client& c, const std::string& id, const std::function<bool(const json&)>& pred, double seconds) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds * k_wait_scale);
  json j;
  while (std::chrono::steady_clock::now() < until) {
    j = body_of(c.Get("/api/v1/jobs/" + id));
    if (pred(j)) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return j;
}
bool ended(const json& j) { return j.value("state", "") == "done" || j.value("state", "") == "failed" || j.value("state", "") == "cancelled"; }

// What must not depend on how a fit ran: its ledger rows without the time, and its files
// without what holds times or paths.
std::map<std::string, std::string> results_of(const fs::path& data, const std::string& key) {
  std::map<std::string, std::string> r;
  const auto ledger = batch::Ledger::open_read_only(data / "runs" / "batch.db");
  const auto& columns = batch::result_columns();
  for (const auto& row : ledger.results()) {
    if (row.fabric_id != key) continue;
    std::string values;
    for (std::size_t i = 0; i < columns.size(); ++i)
      if (columns[i] != "seconds") values += std::to_string(row.values[i]) + ",";  // NaN prints as nan
    r[row.stage + " row"] = values;
    r[row.stage + " params"] = row.params;
  }
  const fs::path folder = data / "runs" / "fabrics" / key;
  for (const char* f : {"uniform_targets.csv", "shell_curves.csv", "yarn_curves.csv"}) r[f] = read_file(folder / f);
  const json y = json::parse(read_file(folder / "yarn_fit.json"));
  r["yarn_fit.json"] = json{{"params", y["params"]}, {"errors", y["errors"]}, {"evaluations", y["evaluations"]}}.dump();
  return r;
}

// The service in this process, fits one at a time on one thread each.
class ServedFits : public ServedTest {
 protected:
  void SetUp() override {
    YARNFIT_REQUIRE_SHARED(shared_stockinette());
    ServedTest::SetUp();
  }
  void serve_fits(FitJobsOptions jobs = {}, ServiceOptions o = {}) {
    jobs.threads_per_job = 1;
    o.jobs = jobs;
    serve(o);
  }
  httplib::Client as(const std::string& token) const { return client(token); }
  std::string upload(const std::string& token, const std::string& id) {
    const auto r = as(token).Post("/api/v1/fabrics", Records::get().zipped(id), "application/zip");
    EXPECT_TRUE(r && r->status == 201) << (r ? r->body : "no answer");
    return id;
  }
  // The results of knit_a fitted with k_small by the service in this process, uninterrupted
  // (empty when that fit did not end done); the service is stopped afterwards.
  std::map<std::string, std::string> uninterrupted_reference() {
    serve_fits();
    upload(m_ana, "knit_a");
    auto ana = as(m_ana);
    const bool done = ana.Post("/api/v1/fabrics/knit_a/fits", k_small.dump(), "application/json")->status == 202 &&
                      wait_for(ana, "knit_a", ended, 600)["state"] == "done";
    stop();
    return done ? results_of(m_dir, "ana/knit_a") : std::map<std::string, std::string>{};
  }
  // A user ana in another data folder; her token.
  static std::string add_ana(const fs::path& data_dir) {
    Accounts accounts(data_dir / "accounts.db");
    return accounts.add_user("ana", false).token;
  }
  fs::path m_dir = data();
};

TEST_F(ServedFits, AFitIsFollowedOnItsEventStreamAndItsResultsAndReportsDownloaded) {
  serve_fits();
  const std::string id = upload(m_ana, "knit_a");
  auto ana = as(m_ana);
  json with_exports = k_small;
  with_exports["export"] = {"table", "u3m"};
  const auto started = ana.Post("/api/v1/fabrics/" + id + "/fits", with_exports.dump(), "application/json");
  ASSERT_EQ(started->status, 202) << started->body;
  EXPECT_EQ(body_of(started)["state"], "queued");
  EXPECT_EQ(ana.Post("/api/v1/fabrics/" + id + "/fits", k_small.dump(), "application/json")->status, 409);
  EXPECT_EQ(as(m_bob).Get("/api/v1/jobs/" + id)->status, 404);  // another's job: as a missing one
  EXPECT_EQ(as(m_bob).Get("/api/v1/jobs/" + id + "/events")->status, 404);

  // The stream: one "job" event per change, until the job has ended.
  std::vector<json> events;
  std::string buffer;
  auto stream = as(m_ana);
  stream.set_read_timeout(600, 0);
  const auto streamed = stream.Get("/api/v1/jobs/" + id + "/events", [&](const char* data, std::size_t n) {
    buffer.append(data, n);
    for (std::size_t end; (end = buffer.find("\n\n")) != std::string::npos;) {
      const std::string block = buffer.substr(0, end);
      buffer.erase(0, end + 2);
      const auto data_at = block.find("data: ");
      if (block.rfind("event: job", 0) == 0 && data_at != std::string::npos)
        events.push_back(json::parse(block.substr(data_at + 6)));
    }
    return true;
  });
  ASSERT_TRUE(streamed);
  EXPECT_EQ(streamed->status, 200);
  EXPECT_EQ(streamed->get_header_value("Content-Type"), "text/event-stream");
  ASSERT_GE(events.size(), 3u);
  EXPECT_EQ(events.back()["state"], "done") << events.back().dump();
  bool saw_swarm = false;
  std::set<double> progress;  // while running
  double before = 0.0;
  for (const auto& e : events) {
    saw_swarm |= e["stage"] == "swarm";
    if (e["state"] == "running") {
      EXPECT_GE(e["progress"].get<double>(), before) << "a progress bar never goes back";
      EXPECT_LT(e["progress"].get<double>(), 1.0);
      before = e["progress"].get<double>();
      progress.insert(before);
    }
  }
  EXPECT_TRUE(saw_swarm);
  EXPECT_GE(progress.size(), 3u) << "the stream showed the fit moving";

  const json done = body_of(ana.Get("/api/v1/jobs/" + id));
  EXPECT_EQ(done["progress"], 1.0);
  EXPECT_TRUE(done["report"].get<bool>());
  // The fit's six files, the U3M material and the table's four.
  EXPECT_EQ(done["files"].size(), 11u) << done.dump();
  // Every result file as the fit wrote it.
  const fs::path folder = m_dir / "runs" / "fabrics" / "ana" / id;
  for (const auto& f : done["files"]) {
    const std::string name = f.get<std::string>();
    const auto got = ana.Get("/api/v1/jobs/" + id + "/files/" + name);
    ASSERT_EQ(got->status, 200) << f;
    const fs::path file = name == id + ".u3ma" ? folder / "exports" / name
                          : fs::exists(folder / name) ? folder / name
                                                      : folder / "exports" / "table" / name;
    EXPECT_EQ(got->body, read_file(file)) << f;
  }
  EXPECT_EQ(ana.Get("/api/v1/jobs/" + id + "/files/" + id + ".u3ma")->get_header_value("Content-Type"), "application/zip");
  EXPECT_EQ(ana.Get("/api/v1/jobs/" + id + "/files/batch.db")->status, 404);
  EXPECT_EQ(ana.Get("/api/v1/jobs/" + id + "/files/..%2F..%2Fbatch.db")->status, 404);
  const auto report = ana.Get("/api/v1/jobs/" + id + "/report");
  ASSERT_EQ(report->status, 200);
  EXPECT_TRUE(contains(report->get_header_value("Content-Type"), "text/html"));
  EXPECT_TRUE(contains(report->body, id));
  const auto family = ana.Get("/api/v1/report");
  ASSERT_EQ(family->status, 200);
  EXPECT_TRUE(contains(family->body, "soft"));  // the family
  EXPECT_FALSE(contains(as(m_bob).Get("/api/v1/report")->body, id));

  // The jobs list: ana's one job; bob none; the admin all.
  EXPECT_EQ(body_of(ana.Get("/api/v1/jobs"))["jobs"].size(), 1u);
  EXPECT_EQ(body_of(as(m_bob).Get("/api/v1/jobs"))["jobs"].size(), 0u);
  EXPECT_EQ(body_of(as(m_admin).Get("/api/v1/jobs"))["jobs"].size(), 1u);
  // Metrics: an admin's; jobs by state and requests by route.
  EXPECT_EQ(ana.Get("/metrics")->status, 403);
  const auto metrics = as(m_admin).Get("/metrics");
  ASSERT_EQ(metrics->status, 200);
  EXPECT_TRUE(contains(metrics->body, "yarnfit_jobs{state=\"done\"} 1")) << metrics->body;
  EXPECT_TRUE(contains(metrics->body, "yarnfit_http_requests_total{route=\"/api/v1/jobs/{id}\",status=\"200\"}"));
  EXPECT_TRUE(contains(metrics->body, "yarnfit_http_request_seconds_bucket{route=\"/api/v1/fabrics\",le=\"+Inf\"}"));
}

// A FAB measurement uploaded as the FAB wrote it (issue 51): imported, shell-fitted with two
// bends held out (the service's fab_held_out), its tests in shell_fit.json and in the report.
TEST_F(ServedFits, AFabFileUploadedAsItIsIsImportedFittedAndReported) {
  serve_fits();
  auto ana = as(m_ana);
  const std::string physics = read_file(fs::path(YARNFIT_SOURCE_DIR) / "tests/data/fab/cupro_physics.json");
  // Refused, and nothing kept: no id, no denier, a denier that is no number, a broken file.
  const auto refused = [&](const std::string& query, const std::string& body, const std::string& says) {
    const auto r = ana.Post("/api/v1/fabrics?format=fab" + query, body, "application/json");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 422) << r->body;
    EXPECT_TRUE(contains(r->body, says)) << r->body;
    EXPECT_FALSE(contains(r->body, m_dir.string())) << "a server path in " << r->body;
  };
  refused("&denier=100", physics, "id: give the fabric's id");
  refused("&id=cupro", physics, "denier: give the yarn's linear density");
  refused("&id=cupro&denier=1e2x", physics, "'1e2x' is not a positive number");
  refused("&id=cupro&denier=inf", physics, "'inf' is not a positive number");
  refused("&id=cupro&denier=-3", physics, "'-3' is not a positive number");
  refused("&id=../cupro&denier=100", physics, "cannot name a folder");
  json broken = json::parse(physics);
  broken["raw_data"]["W"].erase("S1");
  refused("&id=cupro&denier=100", broken.dump(), "/raw_data/W/S1");
  refused("&id=cupro&denier=100", physics.substr(0, physics.size() / 2), "the upload");
  EXPECT_EQ(ana.Post("/api/v1/fabrics?format=tar", physics, "application/json")->status, 400);
  EXPECT_EQ(client().Post("/api/v1/fabrics?format=fab&id=cupro&denier=100", physics, "application/json")->status, 401);
  EXPECT_EQ(client("not even a token").Post("/api/v1/fabrics?format=fab&id=cupro&denier=100", physics,
                                            "application/json")->status, 401);
  EXPECT_TRUE(body_of(ana.Get("/api/v1/fabrics"))["fabrics"].empty());
  EXPECT_TRUE(fs::is_empty(m_dir / "uploads"));

  const auto up = ana.Post("/api/v1/fabrics?format=fab&id=cupro&denier=100", physics, "application/json");
  ASSERT_EQ(up->status, 201) << up->body;
  EXPECT_EQ(body_of(up)["family"], "weaves");
  const json files = body_of(up)["files"];  // the record as made, not the upload
  for (const char* f : {"fabric.yaml", "fab/physics.json", "fab/weft_S2.csv", "stretch_weft.csv"})
    EXPECT_NE(std::find(files.begin(), files.end(), f), files.end()) << f << " in " << files.dump();
  EXPECT_EQ(read_file(m_dir / "fabrics" / "ana" / "cupro" / "fab" / "physics.json"), physics);  // kept byte for byte
  EXPECT_EQ(ana.Post("/api/v1/fabrics?format=fab&id=cupro&denier=100", physics, "application/json")->status, 409);
  // Another user's fabric of the same id is theirs alone; nothing lands outside the data folder.
  EXPECT_EQ(as(m_bob).Post("/api/v1/fabrics?format=fab&id=cupro&denier=100", physics, "application/json")->status, 201);
  EXPECT_TRUE(fs::exists(m_dir / "fabrics" / "bob" / "cupro" / "fabric.yaml"));
  EXPECT_EQ(as(m_bob).Get("/api/v1/fabrics/cupro?owner=ana")->status, 404);
  for (const auto& e : fs::directory_iterator(m_root.path()))
    EXPECT_EQ(e.path().filename(), "data") << "written beside the data folder: " << e.path();
  const json request = {{"stages", "shell"}, {"fab_held_out", {"S1", "U1", "D1"}}};
  ASSERT_EQ(ana.Post("/api/v1/fabrics/cupro/fits", request.dump(), "application/json")->status, 202);
  const json done = wait_for(ana, "cupro", ended, 900);
  ASSERT_EQ(done["state"], "done") << done.dump();
  const json shell = json::parse(ana.Get("/api/v1/jobs/cupro/files/shell_fit.json")->body);
  EXPECT_EQ(shell["fab"]["held_out"], json::array({"S1", "U1", "D1"}));
  EXPECT_EQ(shell["fab"]["tests"].size(), 15u);
  for (const char* d : {"weft", "bias", "warp"}) {
    // The fitted tests under errors_by_direction, the held-out ones apart.
    EXPECT_TRUE(shell["errors_by_direction"][d]["stretch_force_pct"].is_number()) << d;
    EXPECT_TRUE(shell["errors_by_direction"][d]["bending_pct"].is_number()) << d;
    for (const char* t : {"S1", "U1", "D1"})
      EXPECT_TRUE(shell["held_out_errors_by_direction"][d][t].is_object()) << d << " " << t;
    EXPECT_FALSE(shell["held_out_errors_by_direction"][d].contains("S2")) << d;
    EXPECT_GT(shell["params"][std::string("ktheta_") + d].get<double>(), 0.0) << d;
  }
  const auto report = ana.Get("/api/v1/jobs/cupro/report");
  ASSERT_EQ(report->status, 200);
  EXPECT_TRUE(contains(report->body, "FAB tests"));
  EXPECT_TRUE(contains(report->body, "held out, predicted"));
}

TEST_F(ServedFits, BadFitRequestsNameTheFieldAndStartNothing) {
  serve_fits();
  const std::string id = upload(m_ana, "knit_a");
  auto ana = as(m_ana);
  const auto post = [&](const std::string& body) { return ana.Post("/api/v1/fabrics/" + id + "/fits", body, "application/json"); };
  const auto unknown = post(R"({"budget": "quick", "colour": "red"})");
  ASSERT_EQ(unknown->status, 422);
  EXPECT_TRUE(contains(unknown->body, "colour: unknown field")) << unknown->body;
  const auto typed = post(R"({"particles": "many"})");
  ASSERT_EQ(typed->status, 422);
  EXPECT_TRUE(contains(typed->body, "particles: wrong type")) << typed->body;
  EXPECT_TRUE(contains(post(R"({"budget": "lavish"})")->body, "budget"));
  EXPECT_EQ(post(R"({"stages": "yarn"})")->status, 422);
  EXPECT_EQ(post(R"({"particles": 0})")->status, 422);  // the fit's own range check
  const auto malformed = post("{\"budget\": ");
  EXPECT_EQ(malformed->status, 400);
  EXPECT_EQ(post("[1, 2]")->status, 422);
  EXPECT_EQ(ana.Post("/api/v1/fabrics/nope/fits", "{}", "application/json")->status, 404);
  EXPECT_EQ(as(m_bob).Post("/api/v1/fabrics/" + id + "/fits", "{}", "application/json")->status, 404);
  EXPECT_EQ(ana.Get("/api/v1/jobs/" + id)->status, 404);  // nothing started
  EXPECT_FALSE(fs::exists(m_dir / "runs" / "requests" / "ana"));
}

TEST_F(ServedFits, PastTheUsersLimitA429AndACancelledFitMakesRoom) {
  FitJobsOptions limits;
  limits.active_per_user = 1;
  serve_fits(limits);
  const std::string a = upload(m_ana, "knit_a"), b = upload(m_ana, "knit_b");
  upload(m_bob, "knit_a");  // bob's own knit_a: another user's limit and another job
  auto ana = as(m_ana);
  ASSERT_EQ(ana.Post("/api/v1/fabrics/" + a + "/fits", k_small.dump(), "application/json")->status, 202);
  const auto refused = ana.Post("/api/v1/fabrics/" + b + "/fits", k_small.dump(), "application/json");
  ASSERT_EQ(refused->status, 429);
  EXPECT_TRUE(contains(refused->body, "at most 1")) << refused->body;
  EXPECT_EQ(as(m_bob).Post("/api/v1/fabrics/knit_a/fits", k_small.dump(), "application/json")->status, 202);

  const auto cancelled = ana.Delete("/api/v1/jobs/" + a);
  ASSERT_EQ(cancelled->status, 200) << cancelled->body;
  EXPECT_EQ(body_of(cancelled)["state"], "cancelled");
  EXPECT_EQ(ana.Delete("/api/v1/jobs/" + a)->status, 409);  // it has ended
  EXPECT_EQ(as(m_bob).Delete("/api/v1/jobs/" + b)->status, 404);
  ASSERT_EQ(ana.Post("/api/v1/fabrics/" + b + "/fits", k_small.dump(), "application/json")->status, 202);
  // bob's fit was not touched by ana's cancel and ends; ana's second too.
  auto bob = as(m_bob);
  EXPECT_EQ(wait_for(bob, "knit_a", ended, 600)["state"], "done");
  EXPECT_EQ(wait_for(ana, b, ended, 600)["state"], "done");
  EXPECT_EQ(body_of(ana.Get("/api/v1/jobs/" + a))["state"], "cancelled");
}

TEST_F(ServedFits, EventStreamsAreBoundedSoThatTheyCannotStarveTheServer) {
  ServiceOptions o;
  o.streams_per_user = 1;
  serve_fits({}, o);
  upload(m_ana, "knit_a");
  upload(m_ana, "knit_b");
  auto ana = as(m_ana);
  ASSERT_EQ(ana.Post("/api/v1/fabrics/knit_a/fits", k_small.dump(), "application/json")->status, 202);
  ASSERT_EQ(ana.Post("/api/v1/fabrics/knit_b/fits", k_small.dump(), "application/json")->status, 202);  // queued behind
  // One stream open on knit_b (until it ends).
  std::thread first([&] {
    auto c = as(m_ana);
    c.Get("/api/v1/jobs/knit_b/events", [](const char*, std::size_t) { return true; });
  });
  // A second stream of ana's is refused once the first is counted; the server answers all else.
  int refused = 0;
  for (int i = 0; i < 50 && refused == 0; ++i) {
    int status = 0;
    std::string body;
    ana.Get(
        "/api/v1/jobs/knit_a/events",
        [&](const httplib::Response& r) {
          status = r.status;
          return r.status != 200;  // an accepted stream is left at once
        },
        [&](const char* data, std::size_t n) {
          body.append(data, n);
          return true;
        });
    if (status == 429) {
      ++refused;
      EXPECT_TRUE(contains(body, "too many event streams")) << body;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  EXPECT_EQ(refused, 1);
  EXPECT_EQ(ana.Get("/api/v1/jobs/knit_a")->status, 200);
  EXPECT_EQ(ana.Delete("/api/v1/jobs/knit_b")->status, 200);  // its stream ends with it
  first.join();
  // The count went down: a stream can be opened again.
  EXPECT_EQ(wait_for(ana, "knit_a", ended, 600)["state"], "done");
  EXPECT_EQ(ana.Get("/api/v1/jobs/knit_a/events")->status, 200);
}

// A free loopback port (bound, read, released: a race only with another process taking it).
int free_port() {
  const int s = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ::bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a);
  socklen_t n = sizeof a;
  ::getsockname(s, reinterpret_cast<sockaddr*>(&a), &n);
  ::close(s);
  return ntohs(a.sin_port);
}

// `[PREFIX] yarnfit serve DATA --listen 127.0.0.1:PORT ARGS` as a process of its own, once it
// answers /healthz.
pid_t start_server(const fs::path& data, int port, const fs::path& log, const std::string& prefix = "",
                   const std::string& args = " --jobs 1 --threads-per-job 1") {
  const std::string cmd = "exec " + prefix + quoted(YARNFIT_CLI) + " serve " + quoted(data) + " --listen 127.0.0.1:" +
                          std::to_string(port) + args + " >>" + quoted(log) + " 2>&1";
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  httplib::Client c("127.0.0.1", port);
  for (int i = 0; i < 600; ++i) {
    if (const auto r = c.Get("/healthz"); r && r->status == 200) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return pid;
}

TEST_F(ServedFits, AServerKilledInsideASwarmResumesToBitwiseTheUninterruptedResults) {
  // The reference: an uninterrupted fit in this process.
  const auto reference = uninterrupted_reference();
  ASSERT_FALSE(reference.empty());

  // The same fit on a `yarnfit serve`, killed with SIGKILL once the swarm has checkpointed.
  ScratchDir other("served_killed");
  const std::string token = add_ana(other.path());
  const int port = free_port();
  pid_t server = start_server(other.path(), port, other / "serve.log");
  auto c = client_on(port, token);
  ASSERT_EQ(c.Post("/api/v1/fabrics", Records::get().zipped("knit_a"), "application/zip")->status, 201);
  ASSERT_EQ(c.Post("/api/v1/fabrics/knit_a/fits", k_small.dump(), "application/json")->status, 202);
  const fs::path folder = other / "runs" / "fabrics" / "ana" / "knit_a";
  const json inside = wait_for(
      c, "knit_a",
      [&](const json& j) { return j.value("stage", "") == "swarm" && fs::exists(folder / "swarm_checkpoint.json"); }, 300);
  ASSERT_EQ(inside["stage"], "swarm") << inside.dump() << read_file(other / "serve.log");
  ASSERT_FALSE(fs::exists(folder / "yarn_fit.json"));
  ::kill(server, SIGKILL);
  int status = 0;
  ::waitpid(server, &status, 0);

  server = start_server(other.path(), port, other / "serve.log");
  auto again = client_on(port, token);
  EXPECT_EQ(body_of(again.Get("/api/v1/fabrics"))["fabrics"].size(), 1u);  // the upload is there
  const json after = wait_for(again, "knit_a", ended, 600);
  ::kill(server, SIGTERM);
  ::waitpid(server, &status, 0);
  ASSERT_EQ(after["state"], "done") << after.dump() << read_file(other / "serve.log");
  EXPECT_EQ(after["attempts"], 2);
  EXPECT_EQ(results_of(other.path(), "ana/knit_a"), reference);
  const json y = json::parse(read_file(folder / "yarn_fit.json"));
  EXPECT_TRUE(y["settings"].contains("resumed_from")) << y["settings"].dump();  // inside its swarm
}

}  // namespace
}  // namespace yarnfit::service

namespace yarnfit::service {
namespace {

// OpenMPI refuses to run as root unless told; CI runs as root.
const std::string k_mpirun =
    "env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1 "
    "mpirun --oversubscribe -np 2 ";

TEST_F(ServedFits, UnderMpirunRankOneFitsWhatRankZeroServesWithTheSameResults) {
  if (!batch::mpi_available()) GTEST_SKIP() << "built without MPI";
  const auto reference = uninterrupted_reference();
  ASSERT_FALSE(reference.empty());

  ScratchDir other("served_mpi");
  const std::string token = add_ana(other.path());
  const int port = free_port();
  const pid_t server = start_server(other.path(), port, other / "serve.log", k_mpirun, " --mpi --threads-per-job 1");
  auto c = client_on(port, token);
  ASSERT_EQ(c.Post("/api/v1/fabrics", Records::get().zipped("knit_a"), "application/zip")->status, 201)
      << read_file(other / "serve.log");
  ASSERT_EQ(c.Post("/api/v1/fabrics/knit_a/fits", k_small.dump(), "application/json")->status, 202);
  const json after = wait_for(c, "knit_a", ended, 600);
  const long worker_pid = batch::Ledger::open_read_only(other / "runs" / "batch.db").job("ana/knit_a")->pid;
  ::kill(server, SIGTERM);  // mpirun passes it on: rank 0 stops serving, then tells rank 1 to stop
  int status = 0;
  ::waitpid(server, &status, 0);
  const std::string log = read_file(other / "serve.log");
  ASSERT_EQ(after["state"], "done") << after.dump() << log;
  EXPECT_TRUE(contains(log, "fits on 1 MPI ranks")) << log;
  EXPECT_NE(worker_pid, static_cast<long>(server));  // run by a rank, not by mpirun
  EXPECT_EQ(results_of(other.path(), "ana/knit_a"), reference);
  // mpirun itself exits 1 after passing a SIGTERM on, whatever its ranks do; they stopped cleanly.
  EXPECT_FALSE(contains(log, "MPI_ABORT") || contains(log, "Signal:") || contains(log, "terminated")) << log;
}

}  // namespace
}  // namespace yarnfit::service
