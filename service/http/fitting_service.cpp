#include "service/http/fitting_service.hpp"

#include <httplib.h>

#include <mutex>
#include <optional>
#include <random>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "fabrics_db/records/fabric_reader.hpp"
#include "service/accounts/accounts.hpp"

namespace yarnfit::service {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

void reply(httplib::Response& res, int status, const json& body) {
  res.status = status;
  res.set_content(body.dump() + "\n", "application/json");
}

void refuse(httplib::Response& res, int status, const std::string& error, const json& problems = json::array()) {
  reply(res, status, {{"error", error}, {"problems", problems}});
}

// A name that can be a folder of DATA_DIR/fabrics/<user>/ (the record's id, as validation allows).
bool usable_id(const std::string& id) {
  if (id.empty() || id.size() > 128 || id == "." || id == "..") return false;
  for (const char c : id)
    if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' || c == '_' || c == '-'))
      return false;
  return true;
}

std::vector<std::string> files_of(const fs::path& folder) {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(folder))
    if (e.is_regular_file()) out.push_back(fs::relative(e.path(), folder).generic_string());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

struct FittingService::Impl {
  fs::path data;
  ServiceOptions options;
  Accounts accounts;
  std::mutex accounts_mutex;  // one SQLite connection, handlers on many threads
  httplib::Server http;
  int port = 0;

  Impl(fs::path data_dir, ServiceOptions o)
      : data(std::move(data_dir)), options(std::move(o)), accounts((fs::create_directories(data), data / "accounts.db")) {
    fs::create_directories(data / "fabrics");
    fs::create_directories(data / "uploads");
    routes();
  }

  std::optional<Account> caller(const httplib::Request& req) {
    const std::string header = req.get_header_value("Authorization");
    constexpr std::string_view bearer = "Bearer ";
    if (header.compare(0, bearer.size(), bearer) != 0) return std::nullopt;
    const std::lock_guard lock(accounts_mutex);
    return accounts.authenticate(std::string_view(header).substr(bearer.size()));
  }

  // Folders of the fabrics `who` may see: their own, or everyone's for an admin.
  std::vector<std::pair<std::string, fs::path>> visible(const Account& who) {
    std::vector<std::pair<std::string, fs::path>> out;
    for (const auto& owner : fs::directory_iterator(data / "fabrics")) {
      const std::string name = owner.path().filename().string();
      if (!who.admin && name != who.name) continue;
      for (const auto& f : fs::directory_iterator(owner.path()))
        if (f.is_directory()) out.emplace_back(name, f.path());
    }
    std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.second.filename() < b.second.filename(); });
    return out;
  }

  void upload(const Account& who, const httplib::Request& req, httplib::Response& res) {
    std::random_device rd;
    const fs::path staging = data / "uploads" / (who.name + "-" + std::to_string(rd()) + std::to_string(rd()));
    const UnpackedUpload unpacked = unpack_upload(req.body, staging, options.upload);
    if (!unpacked.ok) return refuse(res, unpacked.refusal.status, unpacked.refusal.message);
    std::error_code ec;
    const db::FabricLoad load = db::load_fabric(staging);
    if (!load.ok()) {
      json problems = json::array();
      for (auto p : load.problems.items()) {
        p.file = fs::relative(p.file, staging, ec).generic_string();  // as the user's folder names it
        problems.push_back(p.to_string());
      }
      fs::remove_all(staging, ec);
      return refuse(res, 422, "the record is not valid", problems);
    }
    if (!usable_id(load.fabric->id)) {
      fs::remove_all(staging, ec);
      return refuse(res, 422, "fabric.yaml: id: '" + load.fabric->id + "' cannot name a folder (A-Z a-z 0-9 . _ -)");
    }
    const fs::path home = data / "fabrics" / who.name;
    fs::create_directories(home);
    const fs::path target = home / load.fabric->id;
    if (::renameat2(AT_FDCWD, staging.c_str(), AT_FDCWD, target.c_str(), RENAME_NOREPLACE) != 0) {
      fs::remove_all(staging, ec);
      return refuse(res, 409, "a fabric with id '" + load.fabric->id + "' exists");
    }
    reply(res, 201, {{"id", load.fabric->id}, {"family", load.fabric->family}, {"files", unpacked.files}});
  }

  void routes() {
    http.set_read_timeout(options.read_timeout_s, 0);
    http.set_write_timeout(options.write_timeout_s, 0);
    http.set_payload_max_length(options.upload.max_archive_bytes);
    http.Get("/healthz", [](const httplib::Request&, httplib::Response& res) { res.set_content("ok\n", "text/plain"); });
    const auto authed = [this](auto handler) {
      return [this, handler](const httplib::Request& req, httplib::Response& res) {
        const std::optional<Account> who = caller(req);
        if (!who) return refuse(res, 401, "a valid 'Authorization: Bearer <token>' header is required");
        handler(*who, req, res);
      };
    };
    http.Post("/api/v1/fabrics", authed([this](const Account& who, const httplib::Request& req, httplib::Response& res) {
                upload(who, req, res);
              }));
    http.Get("/api/v1/fabrics", authed([this](const Account& who, const httplib::Request&, httplib::Response& res) {
               json list = json::array();
               for (const auto& [owner, folder] : visible(who)) {
                 const db::FabricLoad load = db::load_fabric(folder);
                 list.push_back({{"id", folder.filename().string()}, {"family", load.family}, {"owner", owner}});
               }
               reply(res, 200, {{"fabrics", list}});
             }));
    http.Get(R"(/api/v1/fabrics/([^/]+))", authed([this](const Account& who, const httplib::Request& req, httplib::Response& res) {
               const std::string id = req.matches[1];
               for (const auto& [owner, folder] : visible(who))
                 if (usable_id(id) && folder.filename() == id) {
                   const db::FabricLoad load = db::load_fabric(folder);
                   return reply(res, 200, {{"id", id}, {"family", load.family}, {"owner", owner}, {"files", files_of(folder)}});
                 }
               refuse(res, 404, "no fabric '" + id + "'");
             }));
    http.set_error_handler([](const httplib::Request&, httplib::Response& res) {
      // httplib's own refusals (a route that does not exist, a body over the limit, a header too
      // long) get a JSON body too.
      if (res.body.empty()) refuse(res, res.status, "HTTP " + std::to_string(res.status) + " for this request");
    });
    http.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
      refuse(res, 500, "internal error");
    });
  }
};

FittingService::FittingService(fs::path data_dir, ServiceOptions options)
    : m_impl(std::make_unique<Impl>(std::move(data_dir), std::move(options))) {}

FittingService::~FittingService() { stop(); }

int FittingService::bind() {
  const int port = m_impl->options.port == 0 ? m_impl->http.bind_to_any_port(m_impl->options.host)
                                             : (m_impl->http.bind_to_port(m_impl->options.host, m_impl->options.port)
                                                    ? m_impl->options.port
                                                    : -1);
  if (port <= 0) throw std::runtime_error(m_impl->options.host + ":" + std::to_string(m_impl->options.port) + ": cannot listen");
  return m_impl->port = port;
}

void FittingService::run() { m_impl->http.listen_after_bind(); }

void FittingService::stop() { m_impl->http.stop(); }

}  // namespace yarnfit::service
