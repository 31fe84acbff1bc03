#pragma once
// Archives for the service's tests, written by libarchive as a client's zip or tar -z would be:
// well-formed ones of a record folder and hostile ones (names, links, devices, sizes).
#include <archive.h>
#include <archive_entry.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "tests/example_fabric.hpp"
#include "tests/test_support.hpp"

namespace yarnfit::testing::archives {

enum class Kind { zip, tar_gz };

struct Item {
  std::string name;
  std::string data;
  unsigned type = AE_IFREG;
  std::string link = {};  // symbolic or hard link target
  bool hard = false;
};

inline Item file(const std::string& name, const std::string& data) { return {name, data, AE_IFREG, "", false}; }
inline Item folder(const std::string& name) { return {name, "", AE_IFDIR, "", false}; }

inline la_ssize_t append(archive*, void* out, const void* buffer, size_t size) {
  static_cast<std::string*>(out)->append(static_cast<const char*>(buffer), size);
  return static_cast<la_ssize_t>(size);
}

// An archive of `items` written by libarchive, as a client would send it.
inline std::string make_archive(const std::vector<Item>& items, Kind kind) {
  std::string out;
  archive* a = archive_write_new();
  if (kind == Kind::zip) {
    archive_write_set_format_zip(a);
  } else {
    archive_write_set_format_pax_restricted(a);
    archive_write_add_filter_gzip(a);
  }
  archive_write_set_bytes_in_last_block(a, 1);  // no padding after the archive, as zip and tar -z write
  archive_write_open(a, &out, nullptr, append, nullptr);
  for (const auto& item : items) {
    archive_entry* e = archive_entry_new();
    archive_entry_set_pathname(e, item.name.c_str());
    archive_entry_set_filetype(e, item.type);
    archive_entry_set_perm(e, 0644);
    if (!item.link.empty()) {
      if (item.hard) archive_entry_set_hardlink(e, item.link.c_str());
      else archive_entry_set_symlink(e, item.link.c_str());
    }
    if (item.type == AE_IFCHR) archive_entry_set_rdev(e, 0x0103);
    archive_entry_set_size(e, item.type == AE_IFREG && !item.hard ? static_cast<la_int64_t>(item.data.size()) : 0);
    // A warning: a name the C locale cannot translate (written as its bytes).
    EXPECT_GE(archive_write_header(a, e), ARCHIVE_WARN) << item.name << ": " << archive_error_string(a);
    if (item.type == AE_IFREG && !item.data.empty()) archive_write_data(a, item.data.data(), item.data.size());
    archive_entry_free(e);
  }
  archive_write_close(a);
  archive_write_free(a);
  return out;
}

// The bundled example's record, the one the upload tests send.
inline const std::filesystem::path k_example_record = bundled_example_folder();

// Its files as the items of an archive, as a client zips the folder: named under `prefix`, and
// fabric.yaml first edited by `edit` when one is given.
inline std::vector<Item> example_record_items(const std::string& prefix,
                                              const std::function<void(std::string&)>& edit = {}) {
  std::vector<Item> items;
  for (const auto& e : std::filesystem::directory_iterator(k_example_record)) {
    std::string text = read_file(e.path());
    if (e.path().filename() == "fabric.yaml" && edit) edit(text);
    items.push_back(file(prefix + e.path().filename().string(), text));
  }
  return items;
}

}  // namespace yarnfit::testing::archives
