#include "service/upload/archive_upload.hpp"

#include <archive.h>
#include <archive_entry.h>
#include <fcntl.h>
#include <stdio.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <functional>
#include <memory>
#include <optional>
#include <random>
#include <set>
#include <system_error>

#include "numerics/util/whole_file.hpp"

namespace yarnfit::service {

namespace fs = std::filesystem;

namespace {

constexpr int k_too_large = 413;
constexpr int k_not_an_archive = 415;
constexpr int k_refused_entry = 422;
constexpr int k_disk = 500;
constexpr const char* k_staging_mark = ".upload-";

struct ReadDeleter {
  void operator()(archive* a) const { archive_read_free(a); }
};
struct WriteDeleter {
  void operator()(archive* a) const { archive_write_free(a); }
};
using Reader = std::unique_ptr<archive, ReadDeleter>;
using DiskWriter = std::unique_ptr<archive, WriteDeleter>;

// A reader of zip and tar (plain or gzip) on the upload's bytes; nothing else is accepted. Zip
// files are read from their central directory (the seekable reader), so that one cut short is
// refused rather than read up to where it stops.
Reader open_reader(std::string_view bytes) {
  Reader a(archive_read_new());
  archive_read_support_filter_gzip(a.get());
  archive_read_support_filter_none(a.get());
  archive_read_support_format_zip_seekable(a.get());
  archive_read_support_format_tar(a.get());
  if (archive_read_open_memory(a.get(), bytes.data(), bytes.size()) != ARCHIVE_OK) return nullptr;
  return a;
}

// The magic numbers of a zip, a gzip stream and a tar: an upload that has one and cannot be read
// is a damaged archive, not some other kind of file.
bool starts_like_an_archive(std::string_view b) {
  return b.substr(0, 4) == std::string_view("PK\x03\x04", 4) || b.substr(0, 2) == "\x1f\x8b" ||
         (b.size() > 262 && b.substr(257, 5) == "ustar");
}

std::string error_of(archive* a) {
  const char* e = archive_error_string(a);
  return e != nullptr ? e : "unknown error";
}

std::vector<std::string> components(std::string_view name) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= name.size()) {
    const std::size_t slash = name.find('/', start);
    const std::size_t end = slash == std::string_view::npos ? name.size() : slash;
    out.emplace_back(name.substr(start, end - start));
    if (slash == std::string_view::npos) break;
    start = slash + 1;
  }
  if (!out.empty() && out.back().empty()) out.pop_back();  // "dir/"
  return out;
}

// What a macOS zip adds beside the folder: passed over, not refused.
bool platform_litter(const std::vector<std::string>& parts) {
  return (!parts.empty() && parts.front() == "__MACOSX") || (!parts.empty() && parts.back() == ".DS_Store");
}


// ASCII lower case: names that differ only in case are one name on some file systems.
std::string lower(std::string s) {
  for (char& c : s)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return s;
}

// The first `n` parts of a name, joined by '/'.
std::string joined(const std::vector<std::string>& parts, std::size_t n) {
  std::string out;
  for (std::size_t k = 0; k < n && k < parts.size(); ++k) out += (k ? "/" : "") + parts[k];
  return out;
}

std::string extension_of(const std::string& file) {
  const std::size_t dot = file.rfind('.');
  if (dot == std::string::npos || dot == 0) return "";
  return lower(file.substr(dot));
}

// One entry as the first pass saw it.
struct Entry {
  std::vector<std::string> parts;
  bool directory = false;
};

// A header read: anything but OK (or a warning about the header itself) is a damaged archive —
// ARCHIVE_RETRY (a tar header with a bad checksum) included.
bool header_read(int r) { return r == ARCHIVE_OK || r == ARCHIVE_WARN; }

// The entry's name as libarchive settled it; "" when it has none it can convert.
std::string name_of(archive_entry* e) {
  const char* raw = archive_entry_pathname_utf8(e);
  if (raw == nullptr) raw = archive_entry_pathname(e);
  return raw != nullptr ? raw : "";
}

// What may not be unpacked of an entry's type (a link, a device, a sparse file); "" for a plain
// file or folder.
std::string type_problem(archive_entry* e) {
  if (archive_entry_hardlink(e) != nullptr) return "a hard link (only files and folders are unpacked)";
  switch (archive_entry_filetype(e)) {
    case AE_IFDIR: return "";
    case AE_IFREG: break;
    case AE_IFLNK: return "a symbolic link (only files and folders are unpacked)";
    default: return "a device, FIFO or socket (only files and folders are unpacked)";
  }
  if (archive_entry_sparse_count(e) > 0) return "a sparse file (only plain files are unpacked)";
  return "";
}

// The first pass: every entry's name, type, kind and declared size, and the counts, before
// anything is written. Names are kept to find duplicates and clashes that differ only in case.
std::optional<UploadRefusal> check_entries(std::string_view bytes, const UploadLimits& limits,
                                           std::vector<Entry>& entries) {
  Reader a = open_reader(bytes);
  if (!a && starts_like_an_archive(bytes)) return UploadRefusal{k_refused_entry, "damaged archive: cannot be opened"};
  if (!a) return UploadRefusal{k_not_an_archive, "not a .zip or .tar.gz archive"};
  archive_entry* e = nullptr;
  int files = 0;
  int headers = 0;
  std::uintmax_t declared = 0;
  std::set<std::string> names;  // lower-cased
  for (bool first = true;; first = false) {
    const int r = archive_read_next_header(a.get(), &e);
    if (r == ARCHIVE_EOF) break;
    if (!header_read(r)) {
      if (first && !starts_like_an_archive(bytes)) return UploadRefusal{k_not_an_archive, "not a .zip or .tar.gz archive"};
      return UploadRefusal{k_refused_entry, "damaged archive: " + error_of(a.get())};
    }
    // Every header counts, folders and passed-over litter included, and so does what it declares.
    if (++headers > limits.max_entries)
      return UploadRefusal{k_too_large, "more than " + std::to_string(limits.max_entries) + " entries"};
    const std::string name = name_of(e);
    if (const std::string why = entry_name_problem(name, limits.max_name_length); !why.empty())
      return UploadRefusal{k_refused_entry, (name.empty() ? "(an entry without a name)" : name) + ": " + why};
    if (components(name).size() > static_cast<std::size_t>(limits.max_depth) + 1)
      return UploadRefusal{k_refused_entry, name + ": folders deeper than " + std::to_string(limits.max_depth)};
    const std::uintmax_t size = archive_entry_size_is_set(e) ? static_cast<std::uintmax_t>(archive_entry_size(e)) : 0;
    if (size > limits.max_file_bytes)
      return UploadRefusal{k_too_large, name + ": larger than " + std::to_string(limits.max_file_bytes) + " bytes"};
    if ((declared += size) > limits.max_unpacked_bytes)
      return UploadRefusal{k_too_large, "more than " + std::to_string(limits.max_unpacked_bytes) + " bytes unpacked"};
    Entry entry{components(name), archive_entry_filetype(e) == AE_IFDIR};
    if (platform_litter(entry.parts)) continue;
    if (const std::string why = type_problem(e); !why.empty()) return UploadRefusal{k_refused_entry, name + ": " + why};
    if (!names.insert(lower(joined(entry.parts, entry.parts.size()))).second)
      return UploadRefusal{k_refused_entry, name + ": a second entry of that name (names may not differ only in case)"};
    if (!entry.directory) {
      if (++files > limits.max_files)
        return UploadRefusal{k_too_large, "more than " + std::to_string(limits.max_files) + " files"};
      const std::string ext = extension_of(entry.parts.back());
      if (std::find(limits.extensions.begin(), limits.extensions.end(), ext) == limits.extensions.end())
        return UploadRefusal{k_refused_entry, name + ": not a kind of file a fabric record holds (.yaml, .csv, .pyp, "
                                                     ".json, .txt, .md)"};
    }
    entries.push_back(std::move(entry));
    archive_read_data_skip(a.get());
  }
  if (files == 0) return UploadRefusal{k_refused_entry, "the archive holds no files"};
  // A file inside a folder whose name a file has taken.
  std::set<std::string> file_names;
  for (const auto& entry : entries)
    if (!entry.directory) file_names.insert(lower(joined(entry.parts, entry.parts.size())));
  for (const auto& entry : entries)
    for (std::size_t k = 1; k < entry.parts.size(); ++k)
      if (file_names.count(lower(joined(entry.parts, k))))
        return UploadRefusal{k_refused_entry, joined(entry.parts, k) + ": both a file and a folder"};
  return std::nullopt;
}

// The one folder every entry is in (a zipped folder), or "" when there is none.
std::string common_top_folder(const std::vector<Entry>& entries) {
  std::string top;
  for (const auto& e : entries) {
    if (e.parts.size() < (e.directory ? 1u : 2u)) return "";
    if (top.empty()) top = e.parts.front();
    else if (e.parts.front() != top) return "";
  }
  return top;
}

// Flushes a folder's own entries (a rename into it) to the disk.
void sync_folder(const fs::path& folder) {
  const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

// Flushes what the folder holds to the disk, files first, then the folders themselves.
bool sync_tree(const fs::path& root) {
  std::error_code ec;
  std::vector<fs::path> dirs{root};
  for (fs::recursive_directory_iterator it(root, ec), end; !ec && it != end; it.increment(ec)) {
    if (it->is_directory(ec)) dirs.push_back(it->path());
    const int fd = ::open(it->path().c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return false;
    const bool ok = ::fsync(fd) == 0;
    ::close(fd);
    if (!ok) return false;
  }
  if (ec) return false;
  for (const auto& d : dirs) sync_folder(d);
  return true;
}

// A fresh hidden folder beside `destination` to unpack into: ".NAME.upload-PID-RANDOM", so that
// the folder of a process killed before its rename can be told from one still being written.
std::optional<fs::path> make_staging(const fs::path& destination) {
  std::random_device rd;
  for (int attempt = 0; attempt < 8; ++attempt) {
    const fs::path p = destination.parent_path() / ("." + destination.filename().string() + k_staging_mark +
                                                    std::to_string(::getpid()) + "-" + std::to_string(rd()));
    std::error_code ec;
    if (fs::create_directory(p, ec) && !ec) return p;
  }
  return std::nullopt;
}

// Staging folders in `folder` of processes that are gone (killed between unpacking and the
// rename): whatever upload they were for, nobody will move them into place.
void remove_stale_staging(const fs::path& folder) {
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const std::string name = entry.path().filename().string();
    const auto mark = name.find(k_staging_mark);
    if (name.empty() || name[0] != '.' || mark == std::string::npos) continue;
    const char* first = name.data() + mark + std::string_view(k_staging_mark).size();
    const char* last = name.data() + name.size();
    long pid = 0;
    const auto [end, err] = std::from_chars(first, last, pid);
    if (err != std::errc() || end == last || *end != '-' || pid <= 0 || pid == ::getpid()) continue;
    std::error_code gone;
    if (numerics::process_is_gone(pid)) fs::remove_all(entry.path(), gone);
  }
}

std::function<void(const fs::path&)>& before_move_hook() {
  static std::function<void(const fs::path&)> hook;
  return hook;
}

// The second pass: every entry written under `staging`, the limits held while the data streams.
// It sees the entries the first pass checked, in the same order (anything else is refused).
std::optional<UploadRefusal> write_entries(std::string_view bytes, const UploadLimits& limits,
                                           const std::vector<Entry>& checked, const std::string& top,
                                           const fs::path& staging, UnpackedUpload& out) {
  Reader a = open_reader(bytes);
  if (!a) return UploadRefusal{k_refused_entry, "damaged archive: cannot be opened again"};
  DiskWriter disk(archive_write_disk_new());
  archive_write_disk_set_options(disk.get(), ARCHIVE_EXTRACT_SECURE_SYMLINKS | ARCHIVE_EXTRACT_SECURE_NODOTDOT |
                                                 ARCHIVE_EXTRACT_NO_OVERWRITE | ARCHIVE_EXTRACT_PERM);
  archive_entry* e = nullptr;
  std::size_t next = 0;
  while (true) {
    const int r = archive_read_next_header(a.get(), &e);
    if (r == ARCHIVE_EOF) break;
    if (!header_read(r)) return UploadRefusal{k_refused_entry, "damaged archive: " + error_of(a.get())};
    const std::string name = name_of(e);
    std::vector<std::string> parts = components(name);
    if (platform_litter(parts)) continue;
    const bool directory = archive_entry_filetype(e) == AE_IFDIR;
    if (next >= checked.size() || checked[next].parts != parts || checked[next].directory != directory ||
        !type_problem(e).empty())
      return UploadRefusal{k_refused_entry, "damaged archive: " + name + " read differently the second time"};
    ++next;
    if (!top.empty()) parts.erase(parts.begin());
    if (parts.empty()) continue;  // the top folder itself
    fs::path relative;
    for (const auto& p : parts) relative /= p;
    archive_entry_set_pathname(e, (staging / relative).c_str());
    archive_entry_set_perm(e, directory ? 0755 : 0644);
    if (archive_write_header(disk.get(), e) != ARCHIVE_OK)
      return UploadRefusal{k_disk, name + ": " + error_of(disk.get())};
    if (!directory) {
      std::uintmax_t file_bytes = 0;
      const void* block = nullptr;
      std::size_t size = 0;
      la_int64_t offset = 0;
      while (true) {
        const int d = archive_read_data_block(a.get(), &block, &size, &offset);
        if (d == ARCHIVE_EOF) break;
        // A warning here is a wrong size or checksum: damaged data, not a file to keep.
        if (d != ARCHIVE_OK) return UploadRefusal{k_refused_entry, name + ": damaged data: " + error_of(a.get())};
        file_bytes = std::max<std::uintmax_t>(file_bytes, static_cast<std::uintmax_t>(offset) + size);
        if (file_bytes > limits.max_file_bytes)
          return UploadRefusal{k_too_large, name + ": larger than " + std::to_string(limits.max_file_bytes) + " bytes unpacked"};
        if (out.unpacked_bytes + file_bytes > limits.max_unpacked_bytes)
          return UploadRefusal{k_too_large, "more than " + std::to_string(limits.max_unpacked_bytes) + " bytes unpacked"};
        // More data than the header declared (a zip whose header understates the size): the disk
        // writer would refuse it as its own error; it is the archive's.
        if (archive_entry_size_is_set(e) && file_bytes > static_cast<std::uintmax_t>(archive_entry_size(e)))
          return UploadRefusal{k_refused_entry, name + ": damaged data: more bytes than the header's " +
                                                    std::to_string(archive_entry_size(e))};
        if (archive_write_data_block(disk.get(), block, size, offset) != ARCHIVE_OK)
          return UploadRefusal{k_disk, name + ": " + error_of(disk.get())};
      }
      // The data must be what the header declared: the disk writer would pad a short file out.
      if (archive_entry_size_is_set(e) && static_cast<std::uintmax_t>(archive_entry_size(e)) != file_bytes)
        return UploadRefusal{k_refused_entry, name + ": damaged data: " + std::to_string(file_bytes) + " bytes, the header says " +
                                                  std::to_string(archive_entry_size(e))};
      out.unpacked_bytes += file_bytes;
      out.files.push_back(relative.generic_string());
    }
    if (archive_write_finish_entry(disk.get()) != ARCHIVE_OK)
      return UploadRefusal{k_disk, name + ": " + error_of(disk.get())};
  }
  if (next != checked.size()) return UploadRefusal{k_refused_entry, "damaged archive: fewer entries the second time"};
  if (archive_write_close(disk.get()) != ARCHIVE_OK) return UploadRefusal{k_disk, error_of(disk.get())};
  return std::nullopt;
}

UnpackedUpload refused(const UploadRefusal& why) {
  UnpackedUpload out;
  out.refusal = why;
  return out;
}

}  // namespace

std::string entry_name_problem(std::string_view name, std::size_t max_length) {
  if (name.empty()) return "an entry without a name";
  if (name.size() > max_length) return "a name longer than " + std::to_string(max_length) + " bytes";
  if (name.front() == '/') return "an absolute name (names are taken inside the folder)";
  if (name.size() >= 2 && name[1] == ':') return "an absolute name (a drive letter)";
  for (const unsigned char c : name) {
    if (c < 0x20 || c == 0x7f) return "a control character in the name";
    if (c == '\\') return "a backslash in the name (folders are separated by /)";
    // Plain ASCII names: nothing another system could read as a different name.
    const bool plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' ||
                       c == '_' || c == '-' || c == ' ' || c == '/';
    if (!plain) return "a character other than A-Z, a-z, 0-9, '.', '_', '-' and space in the name";
  }
  const std::vector<std::string> parts = components(name);
  for (std::size_t i = 0; i < parts.size(); ++i) {
    if (parts[i] == "..") return "a name may not leave the folder (..)";
    if (parts[i] == "." || parts[i].empty()) return "an empty or '.' part of the name";
  }
  return "";
}

namespace {

// Removes the staging folder when it goes out of scope, unless it was moved into place: a
// refusal or an exception leaves nothing behind.
struct StagingGuard {
  fs::path folder;
  bool moved = false;
  ~StagingGuard() {
    std::error_code ec;
    if (!moved && !folder.empty()) fs::remove_all(folder, ec);
  }
};

UnpackedUpload unpack(std::string_view archive, const fs::path& given, const UploadLimits& limits) {
  // libarchive's symlink check walks the whole path: resolve the links the caller's path has.
  std::error_code ec;
  const fs::path destination = fs::weakly_canonical(fs::absolute(given, ec), ec);
  if (archive.size() > limits.max_archive_bytes)
    return refused({k_too_large, "the upload is larger than " + std::to_string(limits.max_archive_bytes) + " bytes"});
  if (ec || fs::exists(destination, ec) || !fs::is_directory(destination.parent_path(), ec))
    return refused({k_disk, destination.string() + ": exists, or its folder does not"});
  std::vector<Entry> entries;
  if (const auto why = check_entries(archive, limits, entries)) return refused(*why);
  const std::optional<fs::path> staging = make_staging(destination);
  if (!staging) return refused({k_disk, destination.parent_path().string() + ": cannot create a folder"});
  StagingGuard guard{*staging};
  UnpackedUpload out;
  auto why = write_entries(archive, limits, entries, common_top_folder(entries), *staging, out);
  if (!why && !sync_tree(*staging)) why = UploadRefusal{k_disk, "cannot flush the unpacked files to the disk"};
  if (!why && before_move_hook()) before_move_hook()(*staging);
  // Into place only when whole, and never over a folder that appeared meanwhile.
  if (!why && ::renameat2(AT_FDCWD, staging->c_str(), AT_FDCWD, destination.c_str(), RENAME_NOREPLACE) != 0)
    why = UploadRefusal{k_disk, destination.string() + ": cannot move the unpacked folder into place"};
  if (why) return refused(*why);
  guard.moved = true;
  sync_folder(destination.parent_path());  // the rename itself
  remove_stale_staging(destination.parent_path());
  std::sort(out.files.begin(), out.files.end());
  out.ok = true;
  return out;
}

}  // namespace

UnpackedUpload unpack_upload(std::string_view archive, const fs::path& destination, const UploadLimits& limits) {
  try {
    return unpack(archive, destination, limits);
  } catch (const std::exception& e) {  // out of memory, a file system error: the staging folder is gone
    return refused({k_disk, destination.string() + ": " + e.what()});
  }
}

namespace detail {
void set_before_move_hook(std::function<void(const fs::path& staging)> hook) { before_move_hook() = std::move(hook); }
}  // namespace detail

}  // namespace yarnfit::service
