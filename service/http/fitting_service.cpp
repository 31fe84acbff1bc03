#include "service/http/fitting_service.hpp"

#include <httplib.h>

#include <chrono>
#include <map>
#include <mutex>
#include <thread>
#include <type_traits>
#include <optional>
#include <random>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "fabrics_db/records/fabric_reader.hpp"
#include "fabrics_db/text_util.hpp"
#include "service/accounts/accounts.hpp"
#include "service/http/page_html.hpp"
#include "service/http/request_metrics.hpp"
#include "service/upload/unpack_zygote.hpp"
#include "service/jobs/fit_jobs.hpp"

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

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

std::vector<std::string> files_of(const fs::path& folder) {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(folder))
    if (e.is_regular_file()) out.push_back(fs::relative(e.path(), folder).generic_string());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

// The route a request took, for the metrics: set by the handler's wrapper on the thread that
// runs it, read by the post-routing handler on the same thread.
thread_local std::string t_route;
thread_local std::chrono::steady_clock::time_point t_start;

struct FittingService::Impl {
  fs::path data;
  ServiceOptions options;
  UnpackZygote unpacker;  // first: forked while this process is small and has no threads of its own
  Accounts accounts;
  std::mutex accounts_mutex;  // one SQLite connection, handlers on many threads
  FitJobs jobs;
  RequestMetrics metrics;
  httplib::Server http;
  std::vector<Route> registered;
  std::mutex streams_mutex;  // the event streams open, by user and in all
  std::map<std::string, int> streams_of;
  int streams_open = 0;
  int port = 0;

  Impl(fs::path data_dir, ServiceOptions o)
      : data(std::move(data_dir)),
        options(std::move(o)),
        unpacker(options.upload, options.isolation),
        accounts((fs::create_directories(data), data / "accounts.db")),
        jobs(data, options.jobs) {
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

  // The owner and folder of fabric `id` as `who` may see it: their own first, then (an admin)
  // anyone's. None for a name that cannot be an id, a missing fabric or another user's.
  std::optional<std::pair<std::string, fs::path>> fabric(const Account& who, const std::string& id) {
    if (!usable_id(id)) return std::nullopt;
    std::optional<std::pair<std::string, fs::path>> found;
    for (auto& [owner, folder] : visible(who))
      if (folder.filename() == id && (!found || owner == who.name)) found.emplace(owner, folder);
    return found;
  }

  // The upload's body, read after the caller was authenticated (a stranger's 32 MiB are never
  // read), at most the archive limit and within options.upload_timeout_s; none when it is too
  // large (413) or came too slowly (408).
  std::optional<std::string> upload_body(const httplib::Request& req, const httplib::ContentReader& reader,
                                         httplib::Response& res) {
    const std::size_t limit = options.upload.max_archive_bytes;
    const std::string too_large = "the upload is larger than " + std::to_string(limit) + " bytes";
    res.set_header("Connection", "close");  // on a refusal the rest of the body is not read
    if (req.get_header_value<uint64_t>("Content-Length") > limit) return refuse(res, 413, too_large), std::nullopt;
    std::string body;
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(options.upload_timeout_s);
    bool late = false, large = false;
    reader([&](const char* bytes, std::size_t n) {
      large = body.size() + n > limit;
      if (!large) body.append(bytes, n);
      late = std::chrono::steady_clock::now() > until;
      return !late && !large;
    });
    if (large) return refuse(res, 413, too_large), std::nullopt;
    if (late) return refuse(res, 408, "the upload did not arrive within " + std::to_string(options.upload_timeout_s) + " s"), std::nullopt;
    res.headers.erase("Connection");
    return body;
  }

  void upload(const Account& who, const httplib::Request& req, const httplib::ContentReader& reader,
              httplib::Response& res) {
    const std::optional<std::string> body = upload_body(req, reader, res);
    if (!body) return;
    std::random_device rd;
    const fs::path staging = data / "uploads" / (who.name + "-" + std::to_string(rd()) + std::to_string(rd()));
    const UnpackedUpload unpacked = unpacker.unpack(*body, staging);
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

  void start_fit(const Account& who, const httplib::Request& req, httplib::Response& res) {
    const auto f = fabric(who, req.matches[1]);
    if (!f) return refuse(res, 404, "no fabric '" + std::string(req.matches[1]) + "'");
    const json body = req.body.empty() ? json::object() : json::parse(req.body, nullptr, false);
    if (body.is_discarded()) return refuse(res, 400, "the body is not JSON");
    const JobAnswer a = jobs.start(f->first, f->second.filename().string(), f->second, body);
    reply(res, a.status, a.body);
  }

  // The job of fabric `id` as `who` may see it, with its owner.
  std::optional<std::pair<std::string, json>> job(const Account& who, const std::string& id) {
    const auto f = fabric(who, id);
    if (!f) return std::nullopt;
    auto j = jobs.job(f->first, id);
    if (!j) return std::nullopt;
    return std::make_pair(f->first, std::move(*j));
  }

  // text/event-stream: the job (an event "job" with its JSON) whenever its state, step or
  // progress changes, and every 5 s for its time figures, until it has ended; a comment line
  // every 15 s of a queued job keeps proxies from closing a quiet stream.
  void events(const Account& who, const httplib::Request& req, httplib::Response& res) {
    const std::string id = req.matches[1];
    const auto j = job(who, id);
    if (!j) return refuse(res, 404, "no fit of '" + id + "'");
    // A stream holds one of the server's threads until its job ends: a user's and everyone's
    // open streams are bounded below the pool, so that streams cannot starve other requests.
    struct Stream {
      Stream(Impl* s, std::string u) : service(s), user(std::move(u)) {}
      Stream(const Stream&) = delete;
      Stream& operator=(const Stream&) = delete;
      Impl* service;
      std::string user;
      std::string last;  // the job without its time figures, as last sent
      std::chrono::steady_clock::time_point sent{};
      int quiet = 0;
      ~Stream() {
        const std::lock_guard lock(service->streams_mutex);
        --service->streams_of[user];
        --service->streams_open;
      }
    };
    {
      const std::lock_guard lock(streams_mutex);
      if (streams_of[who.name] >= options.streams_per_user || streams_open >= options.streams)
        return refuse(res, 429, "too many event streams open (" + std::to_string(options.streams_per_user) + " a user, " +
                                    std::to_string(options.streams) + " in all); close one or poll the job");
      ++streams_of[who.name];
      ++streams_open;
    }
    auto stream = std::make_shared<Stream>(this, who.name);  // counted down when the stream ends
    res.set_header("Cache-Control", "no-store");
    res.set_chunked_content_provider("text/event-stream", [this, owner = j->first, id, stream](std::size_t, httplib::DataSink& sink) {
      const auto now = jobs.job(owner, id);
      if (!now) {
        sink.done();
        return true;
      }
      json changes = *now;
      changes.erase("seconds");
      changes.erase("seconds_left");
      const std::string state = (*now)["state"];
      const bool ended = state == "done" || state == "failed" || state == "cancelled";
      const auto t = std::chrono::steady_clock::now();
      if (changes.dump() != stream->last || (state == "running" && t - stream->sent > std::chrono::seconds(5))) {
        const std::string event = "event: job\ndata: " + now->dump() + "\n\n";
        if (!sink.write(event.data(), event.size())) return false;
        stream->last = changes.dump();
        stream->sent = t;
        stream->quiet = 0;
      } else if (++stream->quiet % 60 == 0 && !sink.write(": waiting\n\n", 11)) {
        return false;
      }
      if (ended) {
        sink.done();
        return true;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(250));
      return sink.is_writable();
    });
  }

  void result_file(const Account& who, const httplib::Request& req, httplib::Response& res) {
    const std::string id = req.matches[1], name = req.matches[2];
    const auto j = job(who, id);
    if (!j) return refuse(res, 404, "no fit of '" + id + "'");
    std::vector<std::string> names;
    for (const auto& [file, path] : downloadable_files(id)) {
      if (file == name) return serve_file(res, jobs.output_folder(j->first, id) / path, name);
      names.push_back(file);
    }
    refuse(res, 404, "no result file '" + name + "' (there are: " + join(names) + ")");
  }

  void serve_file(httplib::Response& res, const fs::path& file, const std::string& what) {
    std::string text, why;
    if (!fs::is_regular_file(file) || !db::read_text_file(file, text, why))
      return refuse(res, 404, what + " is not there (yet)");
    const std::string ext = file.extension().string();
    const char* type = ext == ".json" ? "application/json"
                       : ext == ".csv" ? "text/csv"
                       : ext == ".html" ? "text/html; charset=utf-8"
                       : ext == ".u3ma" ? "application/zip"
                                        : "text/plain; charset=utf-8";
    res.status = 200;
    res.set_content(text, type);
  }

  // Registers `handler` for METHOD PATTERN (a regular expression) under `route`, the path as
  // docs/openapi.yaml writes it and the metrics name it. A handler that takes the caller's
  // Account is only reached with a valid token (401 otherwise); one without is open to all.
  template <class Handler>
  void on(const std::string& method, const std::string& pattern, const std::string& route, Handler handler) {
    registered.push_back({method, route});
    using httplib::ContentReader, httplib::Request, httplib::Response;
    if constexpr (std::is_invocable_v<Handler, const Account&, const Request&, Response&, const ContentReader&>) {
      // A body read by the handler, after the token was checked.
      if (method != "POST") throw std::logic_error(route + ": a body is read on POST only");
      http.Post(pattern, [this, route, handler](const Request& req, Response& res, const ContentReader& reader) {
        t_route = route;
        const std::optional<Account> who = caller(req);
        if (!who) {
          res.set_header("Connection", "close");  // the body is not read
          return refuse(res, 401, "a valid 'Authorization: Bearer <token>' header is required");
        }
        handler(*who, req, res, reader);
      });
      return;
    } else {
      const httplib::Server::Handler h = [this, route, handler](const Request& req, Response& res) {
        t_route = route;
        if constexpr (std::is_invocable_v<Handler, const Request&, Response&>) {
          handler(req, res);
        } else {
          const std::optional<Account> who = caller(req);
          if (!who) return refuse(res, 401, "a valid 'Authorization: Bearer <token>' header is required");
          handler(*who, req, res);
        }
      };
      if (method == "GET") http.Get(pattern, h);
      else if (method == "POST") http.Post(pattern, h);
      else if (method == "DELETE") http.Delete(pattern, h);
      else throw std::logic_error("no method " + method);
    }
  }

  void routes() {
    const std::string get = "GET", post = "POST", del = "DELETE";
    http.new_task_queue = [] { return new httplib::ThreadPool(32); };  // event streams hold a thread each
    http.set_tcp_nodelay(true);  // small JSON answers: Nagle's wait for an ACK costs 40 ms each
    http.set_read_timeout(options.read_timeout_s, 0);
    http.set_write_timeout(options.write_timeout_s, 0);
    http.set_payload_max_length(options.upload.max_archive_bytes);
    on(get, "/healthz", "/healthz", [this](const httplib::Request&, httplib::Response& res) {
      const std::string why = jobs.engine_problem();
      if (why.empty()) return res.set_content("ok\n", "text/plain");
      res.status = 503;
      res.set_content("fits cannot run: " + why + "\n", "text/plain");
    });
    on(get, "/", "/", [](const httplib::Request&, httplib::Response& res) {
      // Everything the page needs is in it; it talks to this server only.
      res.set_header("Content-Security-Policy",
                     "default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; connect-src 'self'; "
                     "img-src 'self' data:; frame-ancestors 'none'");
      res.set_content(page_html(), "text/html; charset=utf-8");
    });
    on(get, "/metrics", "/metrics", [this](const Account& who, const httplib::Request&, httplib::Response& res) {
      if (!who.admin) return refuse(res, 403, "the metrics are an admin's");
      res.set_content(metrics.prometheus_text(jobs.counts()), "text/plain; version=0.0.4");
    });
    on(post, "/api/v1/fabrics", "/api/v1/fabrics",
       [this](const Account& who, const httplib::Request& req, httplib::Response& res, const httplib::ContentReader& reader) {
         upload(who, req, reader, res);
       });
    on(get, "/api/v1/fabrics", "/api/v1/fabrics", [this](const Account& who, const httplib::Request&, httplib::Response& res) {
      json list = json::array();
      for (const auto& [owner, folder] : visible(who)) {
        const db::FabricLoad load = db::load_fabric(folder);
        list.push_back({{"id", folder.filename().string()}, {"family", load.family}, {"owner", owner}});
      }
      reply(res, 200, {{"fabrics", list}});
    });
    on(get, R"(/api/v1/fabrics/([^/]+))", "/api/v1/fabrics/{id}",
       [this](const Account& who, const httplib::Request& req, httplib::Response& res) {
         const std::string id = req.matches[1];
         const auto f = fabric(who, id);
         if (!f) return refuse(res, 404, "no fabric '" + id + "'");
         const db::FabricLoad load = db::load_fabric(f->second);
         reply(res, 200, {{"id", id}, {"family", load.family}, {"owner", f->first}, {"files", files_of(f->second)}});
       });
    on(post, R"(/api/v1/fabrics/([^/]+)/fits)", "/api/v1/fabrics/{id}/fits",
       [this](const Account& who, const httplib::Request& req, httplib::Response& res) { start_fit(who, req, res); });
    on(get, "/api/v1/jobs", "/api/v1/jobs", [this](const Account& who, const httplib::Request&, httplib::Response& res) {
      reply(res, 200, {{"jobs", jobs.jobs(who.admin ? "" : who.name)}});
    });
    on(get, R"(/api/v1/jobs/([^/]+))", "/api/v1/jobs/{id}",
       [this](const Account& who, const httplib::Request& req, httplib::Response& res) {
         const auto j = job(who, req.matches[1]);
         if (!j) return refuse(res, 404, "no fit of '" + std::string(req.matches[1]) + "'");
         reply(res, 200, j->second);
       });
    on(del, R"(/api/v1/jobs/([^/]+))", "/api/v1/jobs/{id}",
       [this](const Account& who, const httplib::Request& req, httplib::Response& res) {
         const std::string id = req.matches[1];
         const auto j = job(who, id);
         if (!j) return refuse(res, 404, "no fit of '" + id + "'");
         const JobAnswer a = jobs.cancel(j->first, id);
         reply(res, a.status, a.body);
       });
    on(get, R"(/api/v1/jobs/([^/]+)/events)", "/api/v1/jobs/{id}/events",
       [this](const Account& who, const httplib::Request& req, httplib::Response& res) { events(who, req, res); });
    on(get, R"(/api/v1/jobs/([^/]+)/files/([^/]+))", "/api/v1/jobs/{id}/files/{name}",
       [this](const Account& who, const httplib::Request& req, httplib::Response& res) { result_file(who, req, res); });
    on(get, R"(/api/v1/jobs/([^/]+)/report)", "/api/v1/jobs/{id}/report",
       [this](const Account& who, const httplib::Request& req, httplib::Response& res) {
         const std::string id = req.matches[1];
         const auto j = job(who, id);
         if (!j) return refuse(res, 404, "no fit of '" + id + "'");
         serve_file(res, jobs.output_folder(j->first, id) / "report" / "index.html", "the report of '" + id + "'");
       });
    on(get, "/api/v1/report", "/api/v1/report", [this](const Account& who, const httplib::Request&, httplib::Response& res) {
      serve_file(res, jobs.family_report(who.admin ? "" : who.name), "the report");
    });
    http.set_pre_routing_handler([](const httplib::Request&, httplib::Response&) {
      t_start = std::chrono::steady_clock::now();
      t_route = "unmatched";
      return httplib::Server::HandlerResponse::Unhandled;
    });
    http.set_post_routing_handler([this](const httplib::Request&, httplib::Response& res) {
      metrics.record(t_route, res.status, std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count());
    });
    http.set_error_handler([this](const httplib::Request&, httplib::Response& res) {
      // httplib's own refusals (a route that does not exist, a body over the limit, a request it
      // cannot read) get a JSON body that says why too.
      if (!res.body.empty()) return;
      const std::string why = res.status == 400   ? "the request cannot be read (malformed, or a header line over 8 KiB)"
                              : res.status == 404 ? "no such route (the API is under /api/v1; docs/openapi.yaml)"
                              : res.status == 413 ? "the body is larger than " +
                                                        std::to_string(options.upload.max_archive_bytes) + " bytes"
                                                  : "HTTP " + std::to_string(res.status) + " for this request";
      refuse(res, res.status, why);
    });
    http.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
      refuse(res, 500, "internal error");
    });
  }
};

FittingService::FittingService(fs::path data_dir, ServiceOptions options)
    : m_impl(std::make_unique<Impl>(std::move(data_dir), std::move(options))) {}

FittingService::~FittingService() { stop(); }

const std::vector<Route>& FittingService::routes() const { return m_impl->registered; }

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
