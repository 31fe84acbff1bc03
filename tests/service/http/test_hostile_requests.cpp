// The hostile table of issue 35, one test per row, against a running service: each request is
// refused with the right 4xx and a message, nothing is written outside DATA_DIR (nor kept
// inside it from a refused upload), and the server goes on serving.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <set>
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


// A raw connection to the server from 127.0.0.1.
int connect_to(int port) { return connect_from(port); }

class Hostile : public ServedTest {
 protected:
  void SetUp() override {
    ServedTest::SetUp();
    ServiceOptions o;
    o.read_timeout_s = 2;
    o.upload_timeout_s = 3;  // the slow client's row
    serve(o);
  }
  void TearDown() override {
    // Still serving, and nothing beside DATA_DIR nor left in its staging folder.
    const auto health = client().Get("/healthz");
    EXPECT_TRUE(health && health->status == 200);
    std::set<std::string> beside;
    for (const auto& e : fs::directory_iterator(m_root.path())) beside.insert(e.path().filename().string());
    EXPECT_EQ(beside, std::set<std::string>{"data"});
    EXPECT_TRUE(fs::is_empty(data() / "uploads"));
    ServedTest::TearDown();
  }
  // Posts `body` as ana's upload and expects `status` with `message` in the error.
  void expect_upload_refused(const std::string& body, const char* type, int status, const std::string& message) {
    const auto r = client(m_ana).Post("/api/v1/fabrics", body, type);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, status) << r->body;
    const json j = json::parse(r->body, nullptr, false);
    ASSERT_TRUE(j.is_object()) << r->body;
    EXPECT_NE(j["error"].get<std::string>().find(message), std::string::npos) << j.dump();
    EXPECT_FALSE(fs::exists(data() / "fabrics" / "ana"));
  }
  // The escape target a hostile name aims at: beside DATA_DIR.
  [[nodiscard]] std::string outside() const { return (m_root.path() / "escaped.csv").string(); }
};

TEST_F(Hostile, PathTraversalInAZip) {
  auto items = example_record_items("swatch/");
  items.push_back(file("swatch/../../escaped.csv", "a\n"));
  expect_upload_refused(make_archive(items, Kind::zip), "application/zip", 422, "..");
}

TEST_F(Hostile, PathTraversalInATarGz) {
  auto items = example_record_items("swatch/");
  items.push_back(file("../escaped.csv", "a\n"));
  expect_upload_refused(make_archive(items, Kind::tar_gz), "application/gzip", 422, "..");
}

TEST_F(Hostile, AbsoluteNamesInAZip) {
  auto items = example_record_items("swatch/");
  items.push_back(file(outside(), "a\n"));
  expect_upload_refused(make_archive(items, Kind::zip), "application/zip", 422, "absolute");
}

TEST_F(Hostile, AbsoluteNamesInATarGz) {
  auto items = example_record_items("swatch/");
  items.push_back(file(outside(), "a\n"));
  expect_upload_refused(make_archive(items, Kind::tar_gz), "application/gzip", 422, "absolute");
}

TEST_F(Hostile, SymbolicAndHardLinks) {
  auto soft = example_record_items("swatch/");
  soft.push_back({"swatch/notes.csv", "", AE_IFLNK, "/etc/passwd", false});
  expect_upload_refused(make_archive(soft, Kind::tar_gz), "application/gzip", 422, "link");
  auto hard = example_record_items("swatch/");
  hard.push_back({"swatch/notes.csv", "", AE_IFREG, "swatch/fabric.yaml", true});
  expect_upload_refused(make_archive(hard, Kind::tar_gz), "application/gzip", 422, "link");
}

TEST_F(Hostile, AZipBomb) {
  auto items = example_record_items("swatch/");
  items.push_back(file("swatch/stretch_bias.csv", std::string(80u << 20, '0')));  // 80 MiB of one byte
  const std::string bomb = make_archive(items, Kind::zip);
  ASSERT_LT(bomb.size(), 1u << 20);  // well under the archive limit: only unpacking finds it
  expect_upload_refused(bomb, "application/zip", 413, "larger than");
}

TEST_F(Hostile, AnOversizeBody) {
  // Declared: refused from its Content-Length, before a byte of the body is read.
  const int s = connect_to(m_port);
  const std::string head = "POST /api/v1/fabrics HTTP/1.1\r\nHost: x\r\nAuthorization: Bearer " + m_ana +
                           "\r\nContent-Type: application/zip\r\nContent-Length: " + std::to_string((32u << 20) + 1) +
                           "\r\n\r\n";
  ::send(s, head.data(), head.size(), MSG_NOSIGNAL);
  const std::string answer = read_all(s);
  ::close(s);
  EXPECT_EQ(answer.rfind("HTTP/1.1 413", 0), 0u) << answer.substr(0, 300);
  EXPECT_NE(answer.find("larger than 33554432 bytes"), std::string::npos) << answer;
}

TEST_F(Hostile, WhatIsNotAnArchive) {
  expect_upload_refused("just some text, not an archive", "text/plain", 415, "");
}

TEST_F(Hostile, MalformedJson) {
  ASSERT_EQ(client(m_ana).Post("/api/v1/fabrics", make_archive(example_record_items("swatch/"), Kind::zip), "application/zip")->status, 201);
  const auto r = client(m_ana).Post("/api/v1/fabrics/stockinette_demo/fits", "{\"budget\": \"quick\"", "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400);
  EXPECT_NE(r->body.find("not JSON"), std::string::npos) << r->body;
  EXPECT_EQ(client(m_ana).Get("/api/v1/jobs/stockinette_demo")->status, 404);
  fs::remove_all(data() / "fabrics");  // the accepted upload is not the teardown's concern
}

TEST_F(Hostile, UnknownFields) {
  ASSERT_EQ(client(m_ana).Post("/api/v1/fabrics", make_archive(example_record_items("swatch/"), Kind::zip), "application/zip")->status, 201);
  const auto r = client(m_ana).Post("/api/v1/fabrics/stockinette_demo/fits", R"({"stages": "all", "rm": "-rf /"})",
                                    "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 422);
  EXPECT_NE(r->body.find("request: rm: unknown field"), std::string::npos) << r->body;
  EXPECT_EQ(client(m_ana).Get("/api/v1/jobs/stockinette_demo")->status, 404);
  fs::remove_all(data() / "fabrics");
}

TEST_F(Hostile, MissingWrongAndRevokedTokens) {
  for (const char* path : {"/api/v1/fabrics", "/api/v1/jobs", "/api/v1/report", "/metrics"}) {
    EXPECT_EQ(client().Get(path)->status, 401) << path;
    EXPECT_EQ(client("yft_0123456789abcdef_" + std::string(43, 'x')).Get(path)->status, 401) << path;
    EXPECT_EQ(client("not even a token").Get(path)->status, 401) << path;
  }
  httplib::Client basic("127.0.0.1", m_port);
  basic.set_basic_auth("ana", m_ana.c_str());
  EXPECT_EQ(basic.Get("/api/v1/fabrics")->status, 401);
  Accounts(data() / "accounts.db").revoke("bob");
  const auto revoked = client(m_bob).Post("/api/v1/fabrics", make_archive(example_record_items("swatch/"), Kind::zip), "application/zip");
  EXPECT_EQ(revoked->status, 401);
  EXPECT_NE(revoked->body.find("Bearer"), std::string::npos);
  EXPECT_FALSE(fs::exists(data() / "fabrics" / "bob"));
}

TEST_F(Hostile, AnotherUsersIds) {
  ASSERT_EQ(client(m_ana).Post("/api/v1/fabrics", make_archive(example_record_items("swatch/"), Kind::zip), "application/zip")->status, 201);
  auto bob = client(m_bob);
  const std::string id = "stockinette_demo";
  for (const std::string& path : std::vector<std::string>{"/api/v1/fabrics/" + id, "/api/v1/jobs/" + id, "/api/v1/jobs/" + id + "/events",
                                 "/api/v1/jobs/" + id + "/report", "/api/v1/jobs/" + id + "/files/shell_fit.json"}) {
    const auto r = bob.Get(path);
    EXPECT_EQ(r->status, 404) << path;
    // As a missing one: "no fabric '…'" or "no fit of '…'", nothing of ana's.
    EXPECT_EQ(json::parse(r->body)["error"].get<std::string>().rfind("no ", 0), 0u) << r->body;
  }
  EXPECT_EQ(bob.Post("/api/v1/fabrics/" + id + "/fits", "{}", "application/json")->status, 404);
  EXPECT_EQ(bob.Delete("/api/v1/jobs/" + id)->status, 404);
  EXPECT_EQ(json::parse(bob.Get("/api/v1/fabrics")->body)["fabrics"].size(), 0u);
  EXPECT_EQ(client(m_admin).Get("/api/v1/fabrics/" + id)->status, 200);
  fs::remove_all(data() / "fabrics");
}

TEST_F(Hostile, HugeHeaders) {
  const int s = connect_to(m_port);
  const std::string request = "GET /api/v1/fabrics HTTP/1.1\r\nHost: x\r\nAuthorization: Bearer " + m_ana +
                              "\r\nX-Padding: " + std::string(64 << 10, 'a') + "\r\n\r\n";
  ::send(s, request.data(), request.size(), MSG_NOSIGNAL);
  const std::string answer = read_all(s);
  ::close(s);
  // Refused with 400 and why, never answered as a request.
  EXPECT_EQ(answer.rfind("HTTP/1.1 400", 0), 0u) << answer.substr(0, 200);
  EXPECT_NE(answer.find("a header line over 8 KiB"), std::string::npos) << answer;
  EXPECT_EQ(answer.find("\"fabrics\""), std::string::npos);
}

TEST_F(Hostile, AClientThatSendsSlowly) {
  // A body promised and trickled a byte every half second, never silent long enough for the
  // read timeout: the upload's deadline (3 s here) ends it with 408, and others are answered
  // meanwhile.
  const int s = connect_to(m_port);
  const std::string head = "POST /api/v1/fabrics HTTP/1.1\r\nHost: x\r\nAuthorization: Bearer " + m_ana +
                           "\r\nContent-Type: application/zip\r\nContent-Length: 100000\r\n\r\n";
  ::send(s, head.data(), head.size(), MSG_NOSIGNAL);
  const auto start = std::chrono::steady_clock::now();
  std::string answer;
  timeval tv{0, 500000};
  ::setsockopt(s, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  for (int i = 0; i < 30 && answer.empty(); ++i) {
    if (::send(s, "P", 1, MSG_NOSIGNAL) != 1) break;
    if (i % 4 == 0) {
      const auto h = client().Get("/healthz");
      EXPECT_TRUE(h && h->status == 200);
    }
    char buf[4096];
    const ssize_t n = ::recv(s, buf, sizeof buf, 0);
    if (n > 0) answer.append(buf, static_cast<std::size_t>(n));
    if (n == 0) break;
  }
  // The head and the body may come in two segments: read on to the server's close (or the
  // half-second receive timeout).
  if (!answer.empty()) answer += read_all(s);
  ::close(s);
  const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(answer.rfind("HTTP/1.1 408", 0), 0u) << answer.substr(0, 300);
  EXPECT_NE(answer.find("did not arrive within 3 s"), std::string::npos) << answer;
  EXPECT_LT(waited, 8.0);
}

}  // namespace
}  // namespace yarnfit::service
