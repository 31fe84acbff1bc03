// The nine defects a hostile test of the service found (issue 47), one test each, tried as an
// attacker with two ordinary accounts would: each failed on the service before the fix.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <thread>

#include <nlohmann/json.hpp>

#include "tests/service/raw_connection.hpp"
#include "tests/service/served_fixture.hpp"
#include "tests/service/test_archives.hpp"

// After the project's headers: <httplib.h> brings <resolv.h>, whose `_res` macro breaks Eigen.
#include <httplib.h>

namespace yarnfit::service {
namespace {

using namespace yarnfit::testing;  // fs, json, the served fixture
using namespace yarnfit::testing::archives;
using Clock = std::chrono::steady_clock;

const std::string k_id = "stockinette_demo";

void replace(std::string& text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  ASSERT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
}

// GET /healthz over a raw connection from `from`: the answer and how long it took.
std::pair<std::string, double> healthz(int port, const char* from) {
  const auto t = Clock::now();
  const int s = connect_from(port, from, 5);
  const std::string request = "GET /healthz HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n";
  ::send(s, request.data(), request.size(), MSG_NOSIGNAL);
  std::string answer = read_all(s);
  ::close(s);
  return {answer, std::chrono::duration<double>(Clock::now() - t).count()};
}

class Defects : public ServedTest {
 protected:
  void SetUp() override {
    ServedTest::SetUp();
    ServiceOptions o;
    o.read_timeout_s = 2;
    customise(o);
    serve(o);
  }
  virtual void customise(ServiceOptions&) {}
  httplib::Result upload(const std::string& token, const std::vector<Item>& items) {
    return client(token).Post("/api/v1/fabrics", make_archive(items, Kind::zip), "application/zip");
  }
  std::string error_of(const httplib::Result& r) {
    const json j = json::parse(r->body, nullptr, false);
    return j.is_object() ? j.value("error", std::string()) + "\n" + j.value("problems", json::array()).dump() : r->body;
  }
};

// 1 (critical). A record's `file:` reads only inside the record: an absolute path, `..` and
// another user's files under DATA_DIR are refused, naming the field and nothing of the file.
TEST_F(Defects, ARecordReadsOnlyItsOwnFolder) {
  ASSERT_EQ(upload(m_bob, example_record_items("swatch/"))->status, 201);
  const fs::path bobs = data() / "fabrics" / "bob" / k_id / "stretch_weft.csv";
  ASSERT_TRUE(fs::exists(bobs));
  for (const std::string& name : {std::string("/etc/passwd"), std::string("/proc/self/environ"), bobs.string(),
                                  "../../bob/" + k_id + "/stretch_weft.csv"}) {
    const auto r = upload(m_ana, example_record_items("swatch/", [&](std::string& y) { replace(y, "file: stretch_weft.csv", "file: '" + name + "'"); }));
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 422) << name << ": " << r->body;
    EXPECT_NE(r->body.find("stretch_tests.weft.file: "), std::string::npos) << r->body;
    // Strings, not pointers: a pointer into data().string() would dangle before the loop ran.
    for (const std::string& leak : {std::string("root:"), std::string("PATH="), std::string("HOME="),
                                    std::string("stretch,force_N"), data().string()})
      EXPECT_EQ(r->body.find(leak), std::string::npos) << leak << " in " << r->body;
    EXPECT_FALSE(fs::exists(data() / "fabrics" / "ana" / k_id));
  }
}

// 2. A field that is not UTF-8 is refused with 422 naming it, nothing kept; a record stored
// before with such a byte (an older server) breaks no listing and can be deleted.
TEST_F(Defects, ABytePastUtf8BreaksNoListing) {
  const auto r = upload(m_ana, example_record_items("swatch/", [](std::string& y) { replace(y, "family: ", "family: caf\xe9-"); }));
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 422) << r->body;
  EXPECT_NE(r->body.find("family: not valid UTF-8 text"), std::string::npos) << r->body;
  EXPECT_FALSE(fs::exists(data() / "fabrics" / "ana"));
  // As an older server kept it.
  const fs::path kept = data() / "fabrics" / "ana" / k_id;
  fs::create_directories(kept);
  for (const auto& e : fs::directory_iterator(k_example_record)) fs::copy_file(e.path(), kept / e.path().filename());
  std::string yaml = read_file(kept / "fabric.yaml");
  replace(yaml, "family: ", "family: \xff\xfe");
  write_file(kept / "fabric.yaml", yaml);
  for (const auto& [token, path] : std::vector<std::pair<std::string, std::string>>{
           {m_ana, "/api/v1/fabrics"}, {m_ana, "/api/v1/fabrics/" + k_id}, {m_ana, "/api/v1/report"}, {m_admin, "/api/v1/fabrics"}}) {
    const auto got = client(token).Get(path);
    ASSERT_TRUE(got);
    EXPECT_EQ(got->status, 200) << path << ": " << got->body;
    EXPECT_TRUE(json::accept(got->body) || got->get_header_value("Content-Type").find("html") != std::string::npos) << got->body;
  }
  const auto gone = client(m_ana).Delete("/api/v1/fabrics/" + k_id);
  ASSERT_TRUE(gone);
  EXPECT_EQ(gone->status, 200) << gone->body;
  EXPECT_FALSE(fs::exists(kept));
  EXPECT_EQ(json::parse(client(m_ana).Get("/api/v1/fabrics")->body)["fabrics"].size(), 0u);
}

// 3. A body that stops before its Content-Length (the client closes its side, or goes silent
// past the read timeout) is discarded: nothing stored, a 400 to a client that still listens.
TEST_F(Defects, ACutOffUploadIsNotKept) {
  const std::string archive = make_archive(example_record_items("swatch/"), Kind::zip);
  for (const bool silent : {false, true}) {
    const int s = connect_from(m_port);
    const std::string head = "POST /api/v1/fabrics HTTP/1.1\r\nHost: x\r\nAuthorization: Bearer " + m_ana +
                             "\r\nContent-Type: application/zip\r\nContent-Length: " + std::to_string(archive.size() + 4096) +
                             "\r\n\r\n";
    ::send(s, head.data(), head.size(), MSG_NOSIGNAL);
    ::send(s, archive.data(), archive.size(), MSG_NOSIGNAL);  // a whole archive, short of what was declared
    if (!silent) ::shutdown(s, SHUT_WR);
    const std::string answer = read_all(s);
    ::close(s);
    // A client that closed its side is taken as gone (httplib's rule): it gets no answer.
    if (silent || !answer.empty()) {
      EXPECT_EQ(answer.rfind("HTTP/1.1 400", 0), 0u) << answer.substr(0, 300);
      EXPECT_NE(answer.find("before its end"), std::string::npos) << answer;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // a late store would show by now
    EXPECT_FALSE(fs::exists(data() / "fabrics" / "ana" / k_id)) << (silent ? "silent" : "closed");
    EXPECT_TRUE(fs::is_empty(data() / "uploads"));
  }
  // The same bytes, whole, are accepted.
  EXPECT_EQ(client(m_ana).Post("/api/v1/fabrics", archive, "application/zip")->status, 201);
}

class Gated : public Defects {
 protected:
  void customise(ServiceOptions& o) override {
    o.connections.head_deadline_ms = 3000;
    o.connections.per_client = 4;
    o.connections.total = 12;
  }
};

// 4. Connections that send nothing hold no worker: each is closed at its head deadline, an
// address holds at most `per_client` and the server `total`; others are served meanwhile.
TEST_F(Gated, SilentConnectionsAreBoundedAndClosedAtTheirDeadline) {
  // At its deadline a silent connection is closed (no answer: it asked nothing).
  const auto t = Clock::now();
  const int silent = connect_from(m_port, "127.0.0.1", 5);
  char c;
  EXPECT_EQ(::recv(silent, &c, 1, 0), 0);  // the server's close
  const double held = std::chrono::duration<double>(Clock::now() - t).count();
  EXPECT_GT(held, 2.5);
  EXPECT_LT(held, 5.0);
  ::close(silent);
  // One address: four held, the fifth refused at once with 503.
  std::vector<int> held_open;
  for (int i = 0; i < 4; ++i) held_open.push_back(connect_from(m_port, "127.0.0.2", 5));
  const auto [fifth, fifth_s] = healthz(m_port, "127.0.0.2");
  EXPECT_EQ(fifth.rfind("HTTP/1.1 503", 0), 0u) << fifth;
  EXPECT_NE(fifth.find("your address holds 4 connections"), std::string::npos) << fifth;
  EXPECT_NE(fifth.find("X-Content-Type-Options: nosniff"), std::string::npos) << fifth;
  // Other addresses up to the total (12: 4 + 7 silent + this one's requests) are served at once.
  for (int k = 3; k < 10; ++k) held_open.push_back(connect_from(m_port, ("127.0.0." + std::to_string(k)).c_str(), 5));
  const auto [served, served_s] = healthz(m_port, "127.0.0.10");
  EXPECT_EQ(served.rfind("HTTP/1.1 200", 0), 0u) << served;
  EXPECT_LT(served_s, 1.0);
  // The thirteenth open connection is refused.
  held_open.push_back(connect_from(m_port, "127.0.0.11", 5));
  const auto [over, over_s] = healthz(m_port, "127.0.0.12");
  EXPECT_EQ(over.rfind("HTTP/1.1 503", 0), 0u) << over;
  EXPECT_NE(over.find("the server holds 12 connections"), std::string::npos) << over;
  for (const int s : held_open) ::close(s);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // the gate sees them close
  // A head begun and never finished is answered 408 at the deadline.
  const int partial = connect_from(m_port, "127.0.0.13", 5);
  ::send(partial, "GET /healthz HT", 15, MSG_NOSIGNAL);
  const std::string late = read_all(partial);
  ::close(partial);
  EXPECT_EQ(late.rfind("HTTP/1.1 408", 0), 0u) << late;
}

// 4 (the mechanism at scale): 200 silent connections from 50 addresses do not slow /healthz.
class ManySilent : public Defects {
 protected:
  void customise(ServiceOptions& o) override { o.connections.head_deadline_ms = 20000; }
};

TEST_F(ManySilent, TwoHundredSilentConnectionsHoldNoWorker) {
  std::vector<int> silent;
  for (int i = 0; i < 200; ++i) silent.push_back(connect_from(m_port, ("127.0.1." + std::to_string(1 + i % 50)).c_str(), 5));
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // all accepted
  double worst = 0;
  for (int i = 0; i < 10; ++i) {
    const auto [answer, seconds] = healthz(m_port, "127.0.0.1");
    EXPECT_EQ(answer.rfind("HTTP/1.1 200", 0), 0u) << answer;
    worst = std::max(worst, seconds);
  }
  EXPECT_LT(worst, 1.0);
  for (const int s : silent) ::close(s);
}

// 5. A fit request is bounded, field by field (422 naming it, no job); the listening socket's
// backlog is sized for load, not httplib's 5.
TEST_F(Defects, AFitRequestIsBoundedAndTheBacklogIsSized) {
  ASSERT_EQ(upload(m_ana, example_record_items("swatch/"))->status, 201);
  for (const char* field : {"particles", "iterations", "samples", "local_samples", "local_evaluations", "starts", "max_iterations"}) {
    for (const long long n : {2147483647LL, 0LL, -5LL}) {
      const auto r = client(m_ana).Post("/api/v1/fabrics/" + k_id + "/fits", json{{field, n}}.dump(), "application/json");
      ASSERT_TRUE(r);
      EXPECT_EQ(r->status, 422) << field << " " << n << ": " << r->body;
      EXPECT_NE(r->body.find(std::string("request: ") + field + ": "), std::string::npos) << r->body;
    }
  }
  EXPECT_EQ(client(m_ana).Get("/api/v1/jobs/" + k_id)->status, 404);
  // ss prints a listening socket's backlog as its Send-Q.
  FILE* ss = ::popen(("ss -ltnH 'sport = :" + std::to_string(m_port) + "'").c_str(), "r");
  ASSERT_NE(ss, nullptr);
  char line[512] = {};
  const bool read = std::fgets(line, sizeof line, ss) != nullptr;
  ::pclose(ss);
  ASSERT_TRUE(read) << "ss printed nothing";
  int recv_q = 0, send_q = 0;
  char state[32] = {};
  ASSERT_EQ(std::sscanf(line, "%31s %d %d", state, &recv_q, &send_q), 3) << line;
  EXPECT_GE(send_q, 1024) << line;
}

// 6. Staging folders a crash left in DATA_DIR/uploads are removed when the service starts.
TEST_F(Defects, StagingLeftByACrashIsRemovedAtStart) {
  stop();
  write_file(data() / "uploads" / "ana-1234" / ".swatch.upload-5" / "fabric.yaml", "id: half\n");
  write_file(data() / "uploads" / ".deleted-77-8" / "stretch_weft.csv", "x\n");
  serve();
  EXPECT_TRUE(fs::is_empty(data() / "uploads"));
  EXPECT_EQ(client().Get("/healthz")->status, 200);
}

// 7. The admin addresses a job by its owner and id when two users have a fabric of one id.
TEST_F(Defects, TheAdminAddressesJobsByOwner) {
  ASSERT_EQ(upload(m_ana, example_record_items("swatch/"))->status, 201);
  ASSERT_EQ(upload(m_bob, example_record_items("swatch/"))->status, 201);
  ASSERT_EQ(client(m_bob).Post("/api/v1/fabrics/" + k_id + "/fits", R"({"stages": "shell"})", "application/json")->status, 202);
  auto admin = client(m_admin);
  const auto bobs = admin.Get("/api/v1/jobs/" + k_id + "?owner=bob");
  ASSERT_TRUE(bobs);
  EXPECT_EQ(bobs->status, 200) << bobs->body;
  EXPECT_EQ(json::parse(bobs->body).value("owner", ""), "bob");
  EXPECT_EQ(admin.Get("/api/v1/jobs/" + k_id + "?owner=ana")->status, 404);  // ana has none
  const auto either = admin.Get("/api/v1/fabrics/" + k_id);
  EXPECT_EQ(either->status, 409) << either->body;
  EXPECT_NE(either->body.find("?owner=NAME"), std::string::npos) << either->body;
  EXPECT_EQ(json::parse(admin.Get("/api/v1/fabrics/" + k_id + "?owner=ana")->body).value("owner", ""), "ana");
  // An ordinary user's owner= names no one else's.
  EXPECT_EQ(client(m_ana).Get("/api/v1/jobs/" + k_id + "?owner=bob")->status, 404);
  // Bob's fabric is not deleted under its running fit.
  EXPECT_EQ(client(m_bob).Delete("/api/v1/fabrics/" + k_id)->status, 409);
  const int cancelled = admin.Delete("/api/v1/jobs/" + k_id + "?owner=bob")->status;
  EXPECT_TRUE(cancelled == 200 || cancelled == 202 || cancelled == 409) << cancelled;
}

// 8. What the client did wrong is a 4xx: a zip whose header understates a file's size, a form
// body over httplib's 8 KiB, and the server's own trouble is a 500 that names no path.
TEST_F(Defects, ClientErrorsAreClientErrors) {
  // A zip whose central directory understates notes.txt's size (the data inflates to more).
  auto items = example_record_items("swatch/");
  items.push_back(file("swatch/notes.txt", std::string(5000, 'n')));
  std::string zip = make_archive(items, Kind::zip);
  const std::string name = "swatch/notes.txt";
  const auto u16 = [&](std::size_t at) {
    return static_cast<std::size_t>(static_cast<unsigned char>(zip[at]) | static_cast<unsigned char>(zip[at + 1]) << 8);
  };
  const auto understate = [&](std::size_t at) { zip[at] = 100, zip[at + 1] = 0, zip[at + 2] = 0, zip[at + 3] = 0; };
  // Its uncompressed size in the central directory (offset 24) and its local header (22), and
  // in the data descriptor after its data, where libarchive's writer puts one.
  for (std::size_t at = zip.find("PK\x01\x02"); at != std::string::npos; at = zip.find("PK\x01\x02", at + 4))
    if (zip.compare(at + 46, u16(at + 28), name) == 0) understate(at + 24);
  for (std::size_t at = zip.find("PK\x03\x04"); at != std::string::npos; at = zip.find("PK\x03\x04", at + 4))
    if (zip.compare(at + 30, u16(at + 26), name) == 0) {
      understate(at + 22);
      const std::size_t descriptor = zip.find("PK\x07\x08", at + 30);
      if (descriptor != std::string::npos) understate(descriptor + 12);
    }
  const auto understated = client(m_ana).Post("/api/v1/fabrics", zip, "application/zip");
  ASSERT_TRUE(understated);
  EXPECT_EQ(understated->status / 100, 4) << understated->body;
  EXPECT_FALSE(fs::exists(data() / "fabrics" / "ana"));
  // A fit request as a form, over 8 KiB.
  ASSERT_EQ(upload(m_ana, example_record_items("swatch/"))->status, 201);
  const auto form = client(m_ana).Post("/api/v1/fabrics/" + k_id + "/fits", std::string(9000, 'a'), "application/x-www-form-urlencoded");
  ASSERT_TRUE(form);
  EXPECT_EQ(form->status, 413);
  EXPECT_EQ(form->body.find("33554432"), std::string::npos) << form->body;
  EXPECT_NE(form->body.find("application/json"), std::string::npos) << form->body;
  // The server cannot write its uploads: 500, and nothing of where.
  fs::remove_all(data() / "uploads");
  write_file(data() / "uploads", "not a folder");
  const auto disk = upload(m_bob, example_record_items("swatch/"));
  ASSERT_TRUE(disk);
  EXPECT_EQ(disk->status, 500) << disk->body;
  EXPECT_EQ(disk->body.find(data().string()), std::string::npos) << disk->body;
  EXPECT_EQ(disk->body.find("uploads"), std::string::npos) << disk->body;
  fs::remove(data() / "uploads");
  fs::create_directories(data() / "uploads");
}

// 9. Every response says nosniff; the page runs only its own script; reports run none.
TEST_F(Defects, SecurityHeadersOnEveryResponse) {
  auto ana = client(m_ana);
  for (const auto& r : {client().Get("/healthz"), client().Get("/"), client().Get("/api/v1/fabrics"), ana.Get("/no/such/route"),
                        ana.Get("/api/v1/fabrics"), ana.Get("/api/v1/jobs/nothing"), ana.Get("/api/v1/report")}) {
    ASSERT_TRUE(r);
    EXPECT_EQ(r->get_header_value("X-Content-Type-Options"), "nosniff") << r->status << " " << r->body.substr(0, 80);
  }
  const auto page = client().Get("/");
  const std::string policy = page->get_header_value("Content-Security-Policy");
  const auto script_src = policy.substr(policy.find("script-src"), policy.find(';', policy.find("script-src")) - policy.find("script-src"));
  EXPECT_EQ(script_src.find("unsafe-inline"), std::string::npos) << policy;
  EXPECT_EQ(script_src.rfind("script-src 'sha256-", 0), 0u) << policy;
  const auto report = ana.Get("/api/v1/report");
  ASSERT_EQ(report->status, 200) << report->body;
  const std::string report_policy = report->get_header_value("Content-Security-Policy");
  EXPECT_NE(report_policy.find("default-src 'none'"), std::string::npos) << report_policy;
  EXPECT_NE(report_policy.find("sandbox"), std::string::npos) << report_policy;
  EXPECT_EQ(report_policy.find("script-src"), std::string::npos) << report_policy;
}

}  // namespace
}  // namespace yarnfit::service
