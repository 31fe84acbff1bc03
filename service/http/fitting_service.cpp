#include "service/http/fitting_service.hpp"

#include <httplib.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <mutex>
#include <thread>
#include <type_traits>
#include <optional>
#include <random>
#include <stdexcept>

#include <nlohmann/json.hpp>
#include <openssl/evp.h>

#include "fabrics_db/csv/csv_table.hpp"
#include "fabrics_db/fab/fab_import.hpp"
#include "fabrics_db/records/fabric_reader.hpp"
#include "fabrics_db/text_util.hpp"
#include "numerics/util/error.hpp"
#include "service/accounts/accounts.hpp"
#include "service/http/gated_server.hpp"
#include "service/http/page_html.hpp"
#include "service/http/request_metrics.hpp"
#include "service/upload/unpack_zygote.hpp"
#include "service/jobs/fit_jobs.hpp"

namespace yarnfit::service {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// JSON text of `j`; a byte that is not UTF-8 (in a record stored before records were checked
// for it, or quoted from a refused one) becomes U+FFFD instead of failing the answer.
std::string json_text(const json& j) { return j.dump(-1, ' ', false, json::error_handler_t::replace); }

void reply(httplib::Response& res, int status, const json& body) {
  res.status = status;
  res.set_content(json_text(body) + "\n", "application/json");
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

// The page's Content-Security-Policy: its one inline script allowed by its SHA-256 (CSP level 2),
// no other script; it talks to this server only. Inline styles stay allowed: the reports the
// page opens (blob: windows, which inherit this policy) are styled inline, and a style runs nothing.
std::string page_policy() {
  const std::string page = page_html();
  const auto hash_of = [&](const std::string& open, const std::string& close) {
    const std::size_t from = page.find(open);
    const std::size_t to = page.find(close, from);
    if (from == std::string::npos || to == std::string::npos) throw std::logic_error("the page has no " + open);
    const std::string body = page.substr(from + open.size(), to - from - open.size());
    unsigned char digest[EVP_MAX_MD_SIZE];
    unsigned int length = 0;
    if (EVP_Digest(body.data(), body.size(), digest, &length, EVP_sha256(), nullptr) != 1)
      throw Error(ErrorCategory::system, "cannot hash the page's script (OpenSSL)");
    std::string base64(4 * ((length + 2) / 3) + 1, '\0');
    base64.resize(static_cast<std::size_t>(EVP_EncodeBlock(reinterpret_cast<unsigned char*>(base64.data()), digest, static_cast<int>(length))));
    return "'sha256-" + base64 + "'";
  };
  return "default-src 'none'; script-src " + hash_of("<script>", "</script>") +
         "; style-src 'unsafe-inline'; connect-src 'self'; img-src 'self' data:; frame-ancestors 'none'; base-uri 'none'; "
         "form-action 'none'";
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
  GatedServer http;
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
        jobs(data, options.jobs),
        http(options.connections, options.read_timeout_s, options.write_timeout_s) {
    fs::create_directories(data / "fabrics");
    // DATA_DIR/uploads holds only what is being unpacked or deleted now; what is there at start
    // (this service holds DATA_DIR/runs: no other one is using it) a crash left behind.
    std::error_code ec;
    fs::remove_all(data / "uploads", ec);
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

  // The owner and folder of fabric `id` as `who` may address it: a user their own; an admin the
  // one of `?owner=NAME`, else their own, else the only one of that id. None (after a 404, or a
  // 409 when an admin's id names several users' fabrics) otherwise; another user's fabric
  // answers 404, as a missing one does.
  std::optional<std::pair<std::string, fs::path>> fabric(const Account& who, const httplib::Request& req,
                                                         const std::string& id, httplib::Response& res,
                                                         const std::string& what = "fabric") {
    const std::string owner = req.get_param_value("owner");
    std::vector<std::pair<std::string, fs::path>> found;
    if (usable_id(id))
      for (auto& [o, folder] : visible(who))
        if (folder.filename() == id && (owner.empty() || o == owner)) found.emplace_back(o, folder);
    const auto own = std::find_if(found.begin(), found.end(), [&](const auto& f) { return f.first == who.name; });
    if (own != found.end()) return *own;
    if (found.size() == 1) return found.front();
    if (found.empty()) {
      refuse(res, 404, (what == "fabric" ? "no fabric '" : "no fit of '") + id + "'");
      return std::nullopt;
    }
    std::vector<std::string> owners;
    for (const auto& f : found) owners.push_back(f.first);
    refuse(res, 409, "'" + id + "' names fabrics of several users (" + join(owners) + "): add ?owner=NAME");
    return std::nullopt;
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
    const bool whole = reader([&](const char* bytes, std::size_t n) {
      large = body.size() + n > limit;
      if (!large) body.append(bytes, n);
      late = std::chrono::steady_clock::now() > until;
      return !late && !large;
    });
    if (large) return refuse(res, 413, too_large), std::nullopt;
    if (late) return refuse(res, 408, "the upload did not arrive within " + std::to_string(options.upload_timeout_s) + " s"), std::nullopt;
    // Only a body that arrived whole is unpacked: one cut short (the client went silent past the
    // read timeout, or closed its side) could be an archive cut at an entry's end, which reads
    // as a smaller record.
    const bool declared = req.has_header("Content-Length");
    if (!whole || (declared && body.size() != req.get_header_value<uint64_t>("Content-Length")))
      return refuse(res, 400, "the upload stopped after " + std::to_string(body.size()) + " bytes, before its end; nothing was kept"),
             std::nullopt;
    res.headers.erase("Connection");
    return body;
  }

  // A fabric record, uploaded as an archive of its folder, or (?format=fab) a FAB measurement
  // as the FAB wrote it: a U3M 1.1 physics JSON, imported as `yarnfit db import-fab` imports
  // it, with ?denier= (required) and ?id=, ?family= (docs/service.md).
  void upload(const Account& who, const httplib::Request& req, const httplib::ContentReader& reader,
              httplib::Response& res) {
    const std::string format = req.get_param_value("format");
    if (!format.empty() && format != "fab" && format != "archive")
      return refuse(res, 400, "format: '" + format + "' is not an upload format (archive, the default, or fab)");
    // A FAB upload's words are checked before its body is read.
    db::FabImportOptions fab;
    if (format == "fab" && !fab_options(req, fab, res)) return;
    const std::optional<std::string> body = upload_body(req, reader, res);
    if (!body) return;
    std::random_device rd;
    const fs::path staging = data / "uploads" / (who.name + "-" + std::to_string(rd()) + std::to_string(rd()));
    if (format == "fab") return upload_fab(who, fab, *body, staging, res);
    const UnpackedUpload unpacked = unpacker.unpack(*body, staging);
    if (!unpacked.ok && unpacked.refusal.status >= 500) {
      // The server's own trouble (its disk, its helper): said in its log, not to the client,
      // whom the folder's place does not concern.
      std::fprintf(stderr, "yarnfit serve: an upload of %s could not be unpacked: %s\n", who.name.c_str(),
                   unpacked.refusal.message.c_str());
      return refuse(res, 500, "the server cannot store the upload now; try again later");
    }
    if (!unpacked.ok) return refuse(res, unpacked.refusal.status, unpacked.refusal.message);
    place_record(who, staging, staging, unpacked.files, res);
  }

  // The import's options from the query (?id=, ?denier=, ?family=); false after a refusal.
  static bool fab_options(const httplib::Request& req, db::FabImportOptions& o, httplib::Response& res) {
    o.id = req.get_param_value("id");
    o.family = req.get_param_value("family");
    if (o.id.empty()) return refuse(res, 422, "id: give the fabric's id (?id=NAME; A-Z a-z 0-9 . _ -)"), false;
    if (!usable_id(o.id)) return refuse(res, 422, "id: '" + o.id + "' cannot name a folder (A-Z a-z 0-9 . _ -)"), false;
    const std::string denier = req.get_param_value("denier");
    if (denier.empty())
      return refuse(res, 422, "denier: give the yarn's linear density (?denier=D): the FAB does not measure it"), false;
    std::string why;
    o.denier = db::parse_finite_number(denier, why);
    if (!o.denier || !(*o.denier > 0.0))
      return refuse(res, 422, "denier: '" + denier + "' is not a positive number"), false;
    return true;
  }

  // A FAB physics file imported into staging/record; the staging folder goes either way.
  void upload_fab(const Account& who, db::FabImportOptions o, const std::string& body, const fs::path& staging,
                  httplib::Response& res) {
    std::error_code ec;
    const auto cleanup = [&] { fs::remove_all(staging, ec); };
    o.input = staging / "physics.json";
    o.output = staging / "record";
    bool stored = fs::create_directories(staging, ec);
    try {
      if (stored) db::write_text_file_atomically(o.input, body);
    } catch (const std::exception&) {
      stored = false;
    }
    if (!stored) {
      cleanup();
      std::fprintf(stderr, "yarnfit serve: a FAB upload of %s could not be stored in %s\n", who.name.c_str(),
                   staging.c_str());
      return refuse(res, 500, "the server cannot store the upload now; try again later");
    }
    db::FabImportResult imported;
    try {
      imported = db::import_fab(o);
    } catch (const std::exception& e) {
      cleanup();
      std::fprintf(stderr, "yarnfit serve: a FAB upload of %s could not be imported: %s\n", who.name.c_str(), e.what());
      return refuse(res, 500, "the server cannot store the upload now; try again later");
    }
    if (!imported.written) {
      json problems = json::array();
      for (auto p : imported.problems.items()) {
        // The server's folders are not the client's concern.
        if (p.file == o.input.string()) p.file = "the upload";
        else if (!p.file.empty()) p.file = fs::path(p.file).lexically_relative(o.output).generic_string();
        problems.push_back(p.to_string());
      }
      cleanup();
      return refuse(res, 422, "the FAB file cannot be imported", problems);
    }
    std::vector<std::string> files;
    for (const auto& e : fs::recursive_directory_iterator(o.output, ec))
      if (e.is_regular_file()) files.push_back(fs::relative(e.path(), o.output, ec).generic_string());
    std::sort(files.begin(), files.end());
    place_record(who, o.output, staging, files, res);
  }

  // Validates the record in `folder` (inside `staging`) and renames it into the user's fabrics
  // unless one of its id is there; `staging` is removed either way.
  void place_record(const Account& who, const fs::path& folder, const fs::path& staging,
                    const std::vector<std::string>& files, httplib::Response& res) {
    std::error_code ec;
    const db::FabricLoad load = db::load_fabric(folder);
    if (!load.ok()) {
      json problems = json::array();
      for (auto p : load.problems.items()) {
        p.file = fs::relative(p.file, folder, ec).generic_string();  // as the user's folder names it
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
    fs::create_directories(home, ec);
    const fs::path target = home / load.fabric->id;
    if (::renameat2(AT_FDCWD, folder.c_str(), AT_FDCWD, target.c_str(), RENAME_NOREPLACE) != 0) {
      fs::remove_all(staging, ec);
      return refuse(res, 409, "a fabric with id '" + load.fabric->id + "' exists");
    }
    fs::remove_all(staging, ec);
    reply(res, 201, {{"id", load.fabric->id}, {"family", load.fabric->family}, {"files", files}});
  }

  void start_fit(const Account& who, const httplib::Request& req, httplib::Response& res) {
    const auto f = fabric(who, req, req.matches[1], res);
    if (!f) return;
    const json body = req.body.empty() ? json::object() : json::parse(req.body, nullptr, false);
    if (body.is_discarded()) return refuse(res, 400, "the body is not JSON");
    const JobAnswer a = jobs.start(f->first, f->second.filename().string(), f->second, body);
    reply(res, a.status, a.body);
  }

  // The job of fabric `id` as `who` may address it, with its owner; none after a refusal.
  std::optional<std::pair<std::string, json>> job(const Account& who, const httplib::Request& req, const std::string& id,
                                                  httplib::Response& res) {
    const auto f = fabric(who, req, id, res, "fit");
    if (!f) return std::nullopt;
    auto j = jobs.job(f->first, id);
    if (!j) {
      refuse(res, 404, "no fit of '" + id + "'");
      return std::nullopt;
    }
    return std::make_pair(f->first, std::move(*j));
  }

  // text/event-stream: the job (an event "job" with its JSON) whenever its state, step or
  // progress changes, and every 5 s for its time figures, until it has ended; a comment line
  // every 15 s of a queued job keeps proxies from closing a quiet stream.
  void events(const Account& who, const httplib::Request& req, httplib::Response& res) {
    const std::string id = req.matches[1];
    const auto j = job(who, req, id, res);
    if (!j) return;
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
      if (json_text(changes) != stream->last || (state == "running" && t - stream->sent > std::chrono::seconds(5))) {
        const std::string event = "event: job\ndata: " + json_text(*now) + "\n\n";
        if (!sink.write(event.data(), event.size())) return false;
        stream->last = json_text(changes);
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
    const auto j = job(who, req, id, res);
    if (!j) return;
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
    // A report is a page of the user's own names: it may show itself, run nothing and load nothing.
    if (ext == ".html")
      res.set_header("Content-Security-Policy",
                     "default-src 'none'; style-src 'unsafe-inline'; img-src data:; frame-ancestors 'none'; "
                     "base-uri 'none'; form-action 'none'; sandbox");
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
        (void)this;  // used by one branch of the if constexpr below only
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
    http.set_tcp_nodelay(true);  // small JSON answers: Nagle's wait for an ACK costs 40 ms each
    http.set_payload_max_length(options.upload.max_archive_bytes);
    // Every answer, the gate's and httplib's own refusals included: a browser takes a body for
    // what its Content-Type says, never for what it looks like.
    http.set_default_headers({{"X-Content-Type-Options", "nosniff"}});
    on(get, "/healthz", "/healthz", [this](const httplib::Request&, httplib::Response& res) {
      const std::string why = jobs.engine_problem();
      if (why.empty()) return res.set_content("ok\n", "text/plain");
      res.status = 503;
      res.set_content("fits cannot run: " + why + "\n", "text/plain");
    });
    on(get, "/", "/", [](const httplib::Request&, httplib::Response& res) {
      // Everything the page needs is in it; it talks to this server only.
      static const std::string policy = page_policy();
      res.set_header("Content-Security-Policy", policy);
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
         const auto f = fabric(who, req, id, res);
         if (!f) return;
         const db::FabricLoad load = db::load_fabric(f->second);
         reply(res, 200, {{"id", id}, {"family", load.family}, {"owner", f->first}, {"files", files_of(f->second)}});
       });
    on(del, R"(/api/v1/fabrics/([^/]+))", "/api/v1/fabrics/{id}",
       [this](const Account& who, const httplib::Request& req, httplib::Response& res) {
         const auto f = fabric(who, req, req.matches[1], res);
         if (!f) return;
         const JobAnswer a = jobs.delete_fabric(f->first, f->second.filename().string(), f->second);
         reply(res, a.status, a.body);
       });
    on(post, R"(/api/v1/fabrics/([^/]+)/fits)", "/api/v1/fabrics/{id}/fits",
       [this](const Account& who, const httplib::Request& req, httplib::Response& res) { start_fit(who, req, res); });
    on(get, "/api/v1/jobs", "/api/v1/jobs", [this](const Account& who, const httplib::Request&, httplib::Response& res) {
      reply(res, 200, {{"jobs", jobs.jobs(who.admin ? "" : who.name)}});
    });
    on(get, R"(/api/v1/jobs/([^/]+))", "/api/v1/jobs/{id}",
       [this](const Account& who, const httplib::Request& req, httplib::Response& res) {
         const auto j = job(who, req, req.matches[1], res);
         if (!j) return;
         reply(res, 200, j->second);
       });
    on(del, R"(/api/v1/jobs/([^/]+))", "/api/v1/jobs/{id}",
       [this](const Account& who, const httplib::Request& req, httplib::Response& res) {
         const std::string id = req.matches[1];
         const auto j = job(who, req, id, res);
         if (!j) return;
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
         const auto j = job(who, req, id, res);
         if (!j) return;
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
    http.set_error_handler([this](const httplib::Request& req, httplib::Response& res) {
      // httplib's own refusals (a route that does not exist, a body over the limit, a request it
      // cannot read) get a JSON body that says why too.
      if (!res.body.empty()) return;
      // httplib reads a form body (application/x-www-form-urlencoded) only up to 8 KiB.
      const bool form = req.get_header_value("Content-Type").find("application/x-www-form-urlencoded") == 0;
      const std::string why = res.status == 400   ? "the request cannot be read (malformed, or a header line over 8 KiB)"
                              : res.status == 404 ? "no such route (the API is under /api/v1; docs/openapi.yaml)"
                              : res.status == 413 && form
                                  ? "a form body is read up to 8 KiB; send fit options as application/json"
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
  if (port <= 0)
    throw Error(ErrorCategory::system,
                m_impl->options.host + ":" + std::to_string(m_impl->options.port) + ": cannot listen");
  m_impl->http.size_backlog();
  return m_impl->port = port;
}

void FittingService::run() { m_impl->http.listen_after_bind(); }

void FittingService::stop() { m_impl->http.shut_down(); }

}  // namespace yarnfit::service
