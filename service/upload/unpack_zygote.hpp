#pragma once
// Where the server's uploads are unpacked: a helper process forked when the service starts,
// while it is small and has no threads, which forks one child per upload under the limits of
// isolated_unpack.hpp. Forking the running server itself for each upload would copy its page
// tables and make every page it writes afterwards a copy-on-write fault in all its threads:
// measured on the load bench, that doubled the status polls' p99.
//
// Thread-safe: uploads are handed to the helper one at a time.

#include <filesystem>
#include <mutex>
#include <string_view>

#include "service/upload/archive_upload.hpp"
#include "service/upload/isolated_unpack.hpp"

namespace yarnfit::service {

class UnpackZygote {
 public:
  // Forks the helper now; it unpacks with `limits` under `isolation`. Throws an Error
  // when it cannot.
  UnpackZygote(UploadLimits limits, UnpackIsolation isolation);
  // Closes the channel (the helper exits) and reaps the helper.
  ~UnpackZygote();
  UnpackZygote(const UnpackZygote&) = delete;
  UnpackZygote& operator=(const UnpackZygote&) = delete;

  // As unpack_upload_isolated; a helper that is gone gives a 500 refusal.
  [[nodiscard]] UnpackedUpload unpack(std::string_view archive, const std::filesystem::path& destination);

 private:
  std::mutex m_mutex;
  int m_fd = -1;  // the parent's end of the socket pair
  int m_pid = -1;
};

}  // namespace yarnfit::service
