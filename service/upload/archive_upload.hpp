#pragma once
// A fabric record uploaded as an archive (issue 35: `POST /api/v1/fabrics` takes a .zip or a
// .tar.gz of the record's folder), unpacked into a new folder all at once or not at all.
//
// Read and written with libarchive: the reader accepts zip and tar (plain or gzip) by their
// content, whatever the upload is called; the disk writer runs with libarchive's secure-
// extraction flags (no symlink on the way, no "..", no overwrite). Before any byte reaches the
// disk every entry is checked here as well, and the limits hold while the data streams:
// - names: relative, no "..", no "." or empty component, no backslash or control character,
//   short enough; one common top folder (a zipped folder) is taken off;
// - types: regular files and folders only (no symlink, hard link, device, FIFO or socket);
// - what: the file kinds a record holds (.yaml/.yml, .csv, .pyp, .json, .txt, .md); a macOS
//   zip's __MACOSX/ folder and .DS_Store files are passed over;
// - how much: the archive's size, the number of files, each file's and the total unpacked
//   size (a zip bomb stops at the limit, whatever its headers claim).
// The folder is built beside `destination` under a hidden name and renamed into place when
// every entry passed; a refused upload leaves nothing behind, and the hidden folder of a
// process killed before its rename is removed by the next upload into the same folder.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace yarnfit::service {

struct UploadLimits {
  std::uintmax_t max_archive_bytes = 32u << 20;   // the upload itself
  std::uintmax_t max_unpacked_bytes = 64u << 20;  // all files together, unpacked
  std::uintmax_t max_file_bytes = 32u << 20;      // one file, unpacked
  int max_files = 200;
  int max_entries = 1000;  // every header: files, folders and what is passed over
  int max_depth = 8;       // folders within folders
  std::size_t max_name_length = 255;  // the whole relative name, in bytes
  std::vector<std::string> extensions = {".yaml", ".yml", ".csv", ".pyp", ".json", ".txt", ".md"};
};

// Why an upload was refused, with the HTTP status the service answers: 413 (a size or count
// limit), 415 (not a zip or tar archive), 422 (an entry that may not be unpacked: its name, its
// type or its kind), 500 (the disk).
struct UploadRefusal {
  int status = 0;
  std::string message;  // names the entry: "../x.csv: a name may not leave the folder"
};

struct UnpackedUpload {
  bool ok = false;
  UploadRefusal refusal;           // when not ok
  std::vector<std::string> files;  // relative names written, sorted
  std::uintmax_t unpacked_bytes = 0;
};

// Unpacks `archive` (the upload's bytes) into the folder `destination`, which must not exist
// and whose parent must. Never throws for bad input; the result says why it refused.
[[nodiscard]] UnpackedUpload unpack_upload(std::string_view archive, const std::filesystem::path& destination,
                                           const UploadLimits& limits = {});

// Why `name` (an entry's name, top folder included) may not be unpacked; empty when it may.
[[nodiscard]] std::string entry_name_problem(std::string_view name, std::size_t max_length);

namespace detail {
// Fault injection for tests (issue 52): called with the staging folder once every file is in it
// and flushed, just before it is renamed into place; it may end the process (a kill between the
// staging and the rename). Empty: nothing is called.
void set_before_move_hook(std::function<void(const std::filesystem::path& staging)> hook);
}  // namespace detail

}  // namespace yarnfit::service
