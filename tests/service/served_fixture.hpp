#pragma once
// A fitting service started in the test's process on 127.0.0.1:<any free port>, over a fresh
// DATA_DIR (ROOT/data, so that a test can see that nothing was written beside it) with users
// ana and bob and an admin, lab.
#include <gtest/gtest.h>


#include <memory>
#include <thread>

#include "service/accounts/accounts.hpp"
#include "service/http/fitting_service.hpp"
#include "tests/test_support.hpp"

// After the project's headers: <httplib.h> brings <resolv.h>, whose `_res` macro breaks Eigen.
#include <httplib.h>

namespace yarnfit::testing {

// The service tests' vocabulary, with `using namespace yarnfit::testing`: fs (test_support.hpp),
// json, and the service's types.
using nlohmann::json;
using service::Accounts;
using service::FittingService;
using service::ServiceOptions;

class ServedTest : public ::testing::Test {
 protected:
  void SetUp() override {
    Accounts accounts(data() / "accounts.db");
    m_ana = accounts.add_user("ana", false).token;
    m_bob = accounts.add_user("bob", false).token;
    m_admin = accounts.add_user("lab", true).token;
  }
  void serve(ServiceOptions o = {}) {
    o.port = 0;
    m_service = std::make_unique<FittingService>(data(), o);
    m_port = m_service->bind();
    m_thread = std::thread([this] { m_service->run(); });
  }
  void stop() {
    if (!m_service) return;
    m_service->stop();
    m_thread.join();
    m_service.reset();
  }
  void TearDown() override { stop(); }
  [[nodiscard]] std::filesystem::path data() const {
    std::filesystem::create_directories(m_root / "data");
    return m_root / "data";
  }
  [[nodiscard]] httplib::Client client(const std::string& token = "") const {
    httplib::Client c("127.0.0.1", m_port);
    if (!token.empty()) c.set_bearer_token_auth(token.c_str());
    c.set_read_timeout(60, 0);
    return c;
  }

  ScratchDir m_root{"served"};
  std::string m_ana, m_bob, m_admin;
  std::unique_ptr<FittingService> m_service;
  int m_port = 0;
  std::thread m_thread;
};

}  // namespace yarnfit::testing
