// An uploaded record archive (POST /api/v1/fabrics): unpack_upload in this process (the
// service runs it in a child under limits too, which the fuzzer must not hide). It never
// throws; whatever it writes stays inside the destination.
#include "fuzz/fuzz_support.hpp"
#include "service/upload/archive_upload.hpp"

YARNFIT_FUZZ_TARGET(archive_upload) {
  using namespace yarnfit;
  const std::filesystem::path parent = fuzz::fresh_folder("upload");
  service::UploadLimits limits;
  limits.max_unpacked_bytes = 4u << 20;  // keeps each run fast; the checks are the same
  limits.max_file_bytes = 2u << 20;
  const service::UnpackedUpload r = service::unpack_upload(fuzz::as_text(data, size), parent / "record", limits);
  for (const auto& entry : std::filesystem::recursive_directory_iterator(parent)) {
    const auto rel = entry.path().lexically_relative(parent / "record");
    if (rel.empty() || *rel.begin() == "..") fuzz::finding("written outside the destination");
  }
  if (!r.ok && std::filesystem::exists(parent / "record")) fuzz::finding("refused: nothing kept");
  return 0;
}
