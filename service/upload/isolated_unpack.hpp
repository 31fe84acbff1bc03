#pragma once
// unpack_upload (archive_upload.hpp) in a child process under resource limits. libarchive
// does some of its work before any check of ours can refuse an entry — a GNU sparse-1.0 tar
// entry's map is read inside its header reader, gzip data is inflated to be skipped — so a
// hostile archive could cost the server memory and time. In a forked child under RLIMIT_AS
// (address space), RLIMIT_CPU and RLIMIT_FSIZE, with a wall-clock deadline, that cost is the
// child's: past a limit the child dies and the upload is refused, the server goes on.

#include <filesystem>
#include <string_view>

#include "service/upload/archive_upload.hpp"

namespace yarnfit::service {

struct UnpackIsolation {
  std::uintmax_t extra_memory_bytes = 512u << 20;  // address space beyond what the server maps
  int cpu_seconds = 30;
  int wall_seconds = 60;
};

// As unpack_upload; a child that exceeds a limit, crashes or says nothing gives a refusal (413
// for memory, time or file size; 500 otherwise), `destination` removed.
[[nodiscard]] UnpackedUpload unpack_upload_isolated(std::string_view archive, const std::filesystem::path& destination,
                                                    const UploadLimits& limits = {}, const UnpackIsolation& isolation = {});

}  // namespace yarnfit::service
