// The fitting service's HTTP API (service/http/fitting_service.hpp), started on an ephemeral
// loopback port and driven by an HTTP client: health without a token, every other route only
// with a valid one, uploads accepted whole or refused with the record's problems, and one user's
// fabrics invisible to another (404, as a missing one) but visible to an admin.
#include <gtest/gtest.h>


#include <set>
#include <thread>

#include <yaml-cpp/yaml.h>

#include <nlohmann/json.hpp>

#include "pipeline/fit_request_fields.hpp"
#include "tests/service/served_fixture.hpp"
#include "tests/service/test_archives.hpp"
#include "tests/test_support.hpp"

#include "service/accounts/accounts.hpp"
#include "service/http/fitting_service.hpp"
#include "service/jobs/fit_request_json.hpp"

// After the project's headers: <httplib.h> brings <resolv.h>, whose `_res` macro breaks Eigen.
#include <httplib.h>

namespace yarnfit::service {
namespace {

using namespace yarnfit::testing;  // fs, json, the served fixture
using namespace yarnfit::testing::archives;


std::string zipped_record(const std::string& yaml_override = "") {
  std::vector<Item> items;
  for (const auto& e : fs::directory_iterator(k_example_record)) {
    const std::string name = e.path().filename().string();
    items.push_back(file("swatch/" + name, name == "fabric.yaml" && !yaml_override.empty() ? yaml_override : read_file(e.path())));
  }
  return make_archive(items, Kind::zip);
}

class Served : public yarnfit::testing::ServedTest {
 protected:
  void SetUp() override {
    ServedTest::SetUp();
    serve();
  }
  fs::path m_dir = data();
};

TEST_F(Served, HealthNeedsNoTokenAndEverythingElseAValidOne) {
  auto health = client().Get("/healthz");
  ASSERT_TRUE(health);
  EXPECT_EQ(health->status, 200);
  EXPECT_EQ(health->body, "ok\n");
  EXPECT_EQ(client().Get("/api/v1/fabrics")->status, 401);
  EXPECT_EQ(client("yft_0000000000000000_" + std::string(43, 'A')).Get("/api/v1/fabrics")->status, 401);
  std::string wrong = m_ana;
  wrong.back() = wrong.back() == 'A' ? 'B' : 'A';
  const auto refused = client(wrong).Get("/api/v1/fabrics");
  EXPECT_EQ(refused->status, 401);
  EXPECT_NE(json::parse(refused->body)["error"].get<std::string>().find("Bearer"), std::string::npos);
  EXPECT_EQ(client(m_ana).Get("/api/v1/fabrics")->status, 200);
  Accounts(m_dir / "accounts.db").revoke("ana");
  EXPECT_EQ(client(m_ana).Get("/api/v1/fabrics")->status, 401);
  EXPECT_EQ(client(m_ana).Get("/no/such/route")->status, 404);
}

TEST_F(Served, ThePageIsServedWithoutATokenAndLoadsNothingFromElsewhere) {
  const auto page = client().Get("/");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
  EXPECT_EQ(page->get_header_value("Content-Type"), "text/html; charset=utf-8");
  EXPECT_NE(page->get_header_value("Content-Security-Policy").find("default-src 'none'"), std::string::npos);
  EXPECT_NE(page->body.find("<title>yarnfit service</title>"), std::string::npos);
  for (const char* outside : {"http://", "https://", "src=\"//", "href=\"//", "@import"})
    EXPECT_EQ(page->body.find(outside), std::string::npos) << outside;
}

TEST_F(Served, AnUploadIsAcceptedWholeAndSeenOnlyByItsOwnerAndAdmins) {
  const auto created = client(m_ana).Post("/api/v1/fabrics", zipped_record(), "application/zip");
  ASSERT_TRUE(created);
  ASSERT_EQ(created->status, 201) << created->body;
  const json body = json::parse(created->body);
  const std::string id = body["id"];
  EXPECT_EQ(read_file(m_dir / "fabrics" / "ana" / id / "fabric.yaml"), read_file(k_example_record / "fabric.yaml"));

  const json mine = json::parse(client(m_ana).Get("/api/v1/fabrics")->body);
  ASSERT_EQ(mine["fabrics"].size(), 1u);
  EXPECT_EQ(mine["fabrics"][0]["id"], id);
  EXPECT_EQ(json::parse(client(m_bob).Get("/api/v1/fabrics")->body)["fabrics"].size(), 0u);
  EXPECT_EQ(client(m_bob).Get("/api/v1/fabrics/" + id)->status, 404);       // another's: as missing
  EXPECT_EQ(client(m_ana).Get("/api/v1/fabrics/no_such")->status, 404);
  EXPECT_EQ(client(m_admin).Get("/api/v1/fabrics/" + id)->status, 200);     // an admin sees all
  const json shown = json::parse(client(m_ana).Get("/api/v1/fabrics/" + id)->body);
  EXPECT_EQ(shown["owner"], "ana");
  EXPECT_EQ(shown["files"].size(), body["files"].size());
  // The same record again: its id is taken.
  EXPECT_EQ(client(m_ana).Post("/api/v1/fabrics", zipped_record(), "application/zip")->status, 409);
  EXPECT_TRUE(fs::is_empty(m_dir / "uploads"));
}

TEST_F(Served, RefusedUploadsSayWhyAndLeaveNothing) {
  const auto invalid = client(m_ana).Post("/api/v1/fabrics", zipped_record("id: broken\n"), "application/zip");
  ASSERT_EQ(invalid->status, 422) << invalid->body;
  const json problems = json::parse(invalid->body)["problems"];
  ASSERT_FALSE(problems.empty());
  EXPECT_EQ(problems[0].get<std::string>().rfind("fabric.yaml:", 0), 0u) << problems.dump();

  std::vector<Item> evil{file("../evil.csv", "a\n")};
  const auto traversal = client(m_ana).Post("/api/v1/fabrics", make_archive(evil, Kind::tar_gz), "application/gzip");
  EXPECT_EQ(traversal->status, 422);
  EXPECT_EQ(client(m_ana).Post("/api/v1/fabrics", "not an archive", "text/plain")->status, 415);
  EXPECT_EQ(client(m_ana).Post("/api/v1/fabrics", "{]", "application/json")->status, 415);
  EXPECT_TRUE(fs::is_empty(m_dir / "uploads"));
  EXPECT_FALSE(fs::exists(m_dir / "fabrics" / "ana"));
  EXPECT_FALSE(fs::exists(m_dir.parent_path() / "evil.csv"));
}

}  // namespace
}  // namespace yarnfit::service

namespace yarnfit::service {
namespace {

// docs/openapi.yaml describes exactly the routes the server registers: every path and method
// there is served, and every route served is there.
TEST(OpenApi, TheDescriptionHoldsEveryRouteTheServerRegistersAndNoOther) {
  ScratchDir dir("openapi");
  ServiceOptions o;
  o.port = 0;
  const FittingService server(dir.path(), o);
  std::set<std::string> served, described;
  for (const Route& r : server.routes()) served.insert(r.method + " " + r.path);
  const YAML::Node doc = YAML::LoadFile((fs::path(YARNFIT_SOURCE_DIR) / "docs" / "openapi.yaml").string());
  ASSERT_EQ(doc["openapi"].as<std::string>().rfind("3.", 0), 0u);
  for (const auto& path : doc["paths"])
    for (const auto& op : path.second) {
      const std::string method = op.first.as<std::string>();
      if (method == "parameters") continue;
      std::string upper;
      for (const char c : method) upper += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
      described.insert(upper + " " + path.first.as<std::string>());
    }
  EXPECT_EQ(served, described);
  EXPECT_EQ(served.size(), server.routes().size());  // none registered twice
}

// The bounds of a fit request the description states are the ones the service holds.
TEST(OpenApi, TheFitRequestBoundsAreTheServices) {
  const YAML::Node doc = YAML::LoadFile((fs::path(YARNFIT_SOURCE_DIR) / "docs" / "openapi.yaml").string());
  const YAML::Node fields = doc["components"]["schemas"]["FitRequest"]["properties"];
  for (const auto& bound : request_bounds()) {
    ASSERT_TRUE(fields[bound.field]) << bound.field;
    EXPECT_EQ(fields[bound.field]["minimum"].as<int>(), 1) << bound.field;
    EXPECT_EQ(fields[bound.field]["maximum"].as<int>(), bound.most) << bound.field;
  }
}

// Every field a request may set is read back as it was written (the job's request is kept as
// JSON to resume it after a restart); the command line's own fields are refused as unknown, and
// each size past its bound is a problem naming it.
TEST(FitRequestJson, EveryServedFieldRoundTripsAndNoOtherIsRead) {
  ServiceFitRequest given;
  given.report = false;
  int n = 0;
  std::vector<std::string> unserved;
  pipeline::for_each_request_field(given.request, [&](const pipeline::RequestField& f, auto& member) {
    using T = std::decay_t<decltype(member)>;
    ++n;
    if (!f.served) unserved.push_back(f.name);
    if constexpr (std::is_same_v<T, bool>) member = !member;
    else if constexpr (std::is_same_v<T, std::string>) member = std::string("not-") + f.name;
    else if constexpr (std::is_same_v<T, std::vector<std::string>>) member = {f.name, "second"};
    else if constexpr (std::is_same_v<T, std::optional<int>> || std::is_same_v<T, int>) member = n;
    else member = static_cast<T>(1000 + n);
  });
  const json body = to_json(given);
  db::Problems problems;
  const ServiceFitRequest read = fit_request_from_json(body, problems);
  EXPECT_EQ(to_json(read), body);
  EXPECT_FALSE(read.report);
  ASSERT_GE(unserved.size(), 4u);
  for (const auto& name : unserved) EXPECT_FALSE(body.contains(name)) << name;
  // Every served field was read: the only problem is the stages' name ("not-stages").
  EXPECT_EQ(problems.size(), 1u) << problems.to_string();

  for (const auto& name : unserved) {
    db::Problems refused;
    (void)fit_request_from_json(json{{name, 1}}, refused);
    EXPECT_NE(refused.to_string().find(name + ": unknown field"), std::string::npos) << refused.to_string();
  }
  for (const auto& bound : request_bounds()) {
    for (const int value : {0, bound.most + 1}) {
      db::Problems refused;
      (void)fit_request_from_json(json{{bound.field, value}}, refused);
      const std::string said = std::string(bound.field) + ": " + std::to_string(value) + " is outside";
      EXPECT_NE(refused.to_string().find(said), std::string::npos) << refused.to_string();
    }
    db::Problems none;
    (void)fit_request_from_json(json{{bound.field, bound.most}}, none);
    EXPECT_TRUE(none.empty()) << none.to_string();
  }
}

}  // namespace
}  // namespace yarnfit::service
