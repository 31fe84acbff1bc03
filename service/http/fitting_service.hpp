#pragma once
// The fitting service's HTTP API (issue 35), on cpp-httplib: so far health, bearer-token
// authentication and the fabrics (upload, list, show). Every request but /healthz carries
// `Authorization: Bearer <token>` (service/accounts); a user sees only their own fabrics (another
// user's id answers 404, as a missing one does), an admin sees all.
//
//   GET  /healthz                  200 "ok"
//   POST /api/v1/fabrics           body: a .zip or .tar.gz of a record folder (service/upload);
//                                  201 {"id", "family", "files"} or 4xx {"error", "problems"}
//   GET  /api/v1/fabrics           200 {"fabrics": [{"id", "family", "owner"}]}
//   GET  /api/v1/fabrics/{id}      200 {"id", "family", "owner", "files"} or 404
//
// DATA_DIR/accounts.db holds the users, DATA_DIR/fabrics/<user>/<id>/ the accepted records
// (unpacked whole, validated, then renamed into place before 201 is sent).

#include <filesystem>
#include <memory>
#include <string>

#include "service/upload/archive_upload.hpp"

namespace yarnfit::service {

struct ServiceOptions {
  std::string host = "127.0.0.1";
  int port = 8080;  // 0: any free port (tests)
  UploadLimits upload;
  int read_timeout_s = 10;   // a client that sends slowly is cut off
  int write_timeout_s = 10;
};

class FittingService {
 public:
  FittingService(std::filesystem::path data_dir, ServiceOptions options);
  ~FittingService();
  FittingService(const FittingService&) = delete;
  FittingService& operator=(const FittingService&) = delete;

  // Binds the listening socket; returns the port (the chosen one when options.port is 0).
  // Throws std::runtime_error when it cannot.
  int bind();
  // Serves until stop() (from another thread or a signal handler).
  void run();
  void stop();

 private:
  struct Impl;
  std::unique_ptr<Impl> m_impl;
};

}  // namespace yarnfit::service
