#pragma once
// The fitting service's HTTP API (issue 35, docs/service.md, docs/openapi.yaml), on cpp-httplib.
// Every request but /healthz carries `Authorization: Bearer <token>` (service/accounts); a user
// sees only their own fabrics and jobs (another user's id answers 404, as a missing one does),
// an admin sees all.
//
//   GET    /healthz                          200 "ok"; 503 when fits cannot run
//   GET    /metrics                          Prometheus text (an admin's token)
//   POST   /api/v1/fabrics                   a .zip or .tar.gz of a record folder (service/upload):
//                                            201 {"id", "family", "files"} or 4xx {"error", "problems"}
//   GET    /api/v1/fabrics                   {"fabrics": [{"id", "family", "owner"}]}
//   GET    /api/v1/fabrics/{id}              {"id", "family", "owner", "files"}
//   DELETE /api/v1/fabrics/{id}              the fabric, its fit and its results (409 while a fit runs)
//   POST   /api/v1/fabrics/{id}/fits         fit options (service/jobs/fit_request_json.hpp): 202 job
//   GET    /api/v1/jobs                      {"jobs": [job…]}
//   GET    /api/v1/jobs/{id}                 job (service/jobs/fit_jobs.hpp)
//   DELETE /api/v1/jobs/{id}                 cancels it
//   GET    /api/v1/jobs/{id}/events          text/event-stream of the job until it ends
//   GET    /api/v1/jobs/{id}/files/{name}    a result file
//   GET    /api/v1/jobs/{id}/report          the fabric's HTML report
//   GET    /api/v1/report                    the report over the caller's fabrics, by family
//
// An admin sees every user's fabrics: where two users have a fabric of one id, `?owner=NAME` on
// any {id} route says whose (without it the admin's own, else the only one, else 409).
// Every response carries X-Content-Type-Options: nosniff; the page and the reports a
// Content-Security-Policy. Connections are gated (service/http/gated_server.hpp).
//
// DATA_DIR/accounts.db holds the users, DATA_DIR/fabrics/<user>/<id>/ the accepted records
// (unpacked whole, validated, then renamed into place before 201 is sent), DATA_DIR/runs/ the
// fits (a batch folder).

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "service/http/connection_limits.hpp"
#include "service/jobs/fit_jobs.hpp"
#include "service/upload/archive_upload.hpp"
#include "service/upload/isolated_unpack.hpp"

namespace yarnfit::service {

struct ServiceOptions {
  std::string host = "127.0.0.1";
  int port = 8080;  // 0: any free port (tests)
  UploadLimits upload;
  UnpackIsolation isolation;  // an upload is unpacked in a child process under these limits
  FitJobsOptions jobs;
  ConnectionLimits connections;  // deadlines and bounds of connections before a worker takes them
  int read_timeout_s = 10;   // a client silent this long in the middle of a request is cut off
  int write_timeout_s = 10;
  // An upload's whole body must arrive within this (408 otherwise): a client that trickles its
  // body a byte at a time never trips the read timeout above, which counts one silence.
  int upload_timeout_s = 120;
  // Event streams open at once, a user's and everyone's (each holds one of 32 server threads).
  int streams_per_user = 4;
  int streams = 16;
};

// A route the server answers: its method and its path as docs/openapi.yaml writes it.
struct Route {
  std::string method;
  std::string path;
  bool operator==(const Route&) const = default;
};

class FittingService {
 public:
  FittingService(std::filesystem::path data_dir, ServiceOptions options);
  ~FittingService();
  FittingService(const FittingService&) = delete;
  FittingService& operator=(const FittingService&) = delete;

  // Binds the listening socket; returns the port (the chosen one when options.port is 0).
  // Throws an Error when it cannot.
  int bind();
  // Every route registered, in registration order.
  [[nodiscard]] const std::vector<Route>& routes() const;
  // Serves until stop() (from another thread or a signal handler).
  void run();
  void stop();

 private:
  struct Impl;
  std::unique_ptr<Impl> m_impl;
};

}  // namespace yarnfit::service
