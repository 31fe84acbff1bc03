// A fabric record uploaded as an archive (service/upload/archive_upload.hpp): a zipped record
// folder and a .tar.gz of its files unpack to the same bytes; every hostile archive (names that
// leave the folder, absolute names, links, devices, a zip bomb, too many files, too large an
// upload, what is not an archive, a kind of file no record holds) is refused with its status
// and leaves nothing behind, beside the folder or outside it.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "tests/test_support.hpp"

#include "service/upload/archive_upload.hpp"
#include "service/upload/isolated_unpack.hpp"
#include "tests/service/test_archives.hpp"

namespace yarnfit::service {
namespace {

namespace fs = std::filesystem;
using namespace yarnfit::testing;
using namespace yarnfit::testing::archives;


// The record's files by name, as a client zips its folder (under `prefix`).
std::vector<Item> record_folder_items(const std::string& prefix) {
  std::vector<Item> items;
  if (!prefix.empty()) items.push_back(folder(prefix));
  for (auto& item : example_record_items(prefix)) items.push_back(std::move(item));
  return items;
}

// Everything below `dir`, names relative to it: what a refusal must leave as it found it.
std::set<std::string> listing(const fs::path& dir) {
  std::set<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) out.insert(fs::relative(e.path(), dir).generic_string());
  return out;
}

// Unpacks into DIR/data/fabric and expects a refusal with `status`, DIR unchanged (nothing
// written there or beside it, no half-unpacked folder), and no file written outside DIR/data.
void expect_refused(const std::string& bytes, int status, const std::string& says, const UploadLimits& limits = {}) {
  ScratchDir dir("upload_refused");
  fs::create_directories(dir / "data");
  const std::set<std::string> before = listing(dir.path());
  const UnpackedUpload r = unpack_upload(bytes, dir / "data" / "fabric", limits);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.refusal.status, status) << r.refusal.message;
  EXPECT_NE(r.refusal.message.find(says), std::string::npos) << r.refusal.message;
  EXPECT_EQ(listing(dir.path()), before);
  EXPECT_FALSE(fs::exists("/tmp/yarnfit_evil.csv"));
}

TEST(ArchiveUpload, AZippedRecordFolderUnpacksToTheSameBytes) {
  for (const Kind kind : {Kind::zip, Kind::tar_gz}) {
    ScratchDir dir("upload_ok");
    // A zipped folder (its top folder taken off) and a .tar.gz of the files themselves.
    const std::string prefix = kind == Kind::zip ? "stockinette_demo/" : "";
    const UnpackedUpload r = unpack_upload(make_archive(record_folder_items(prefix), kind), dir / "fabric");
    ASSERT_TRUE(r.ok) << r.refusal.message;
    std::vector<std::string> expected;
    for (const auto& e : fs::directory_iterator(k_example_record)) {
      expected.push_back(e.path().filename().string());
      EXPECT_EQ(read_file(dir / "fabric" / e.path().filename()), read_file(e.path())) << e.path();
    }
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(r.files, expected);
    EXPECT_EQ(listing(dir.path()).size(), expected.size() + 1);  // the folder and its files, no staging left
  }
}

TEST(ArchiveUpload, AMacZipsLitterIsPassedOver) {
  ScratchDir dir("upload_mac");
  std::vector<Item> items = record_folder_items("swatch/");
  items.push_back(file("__MACOSX/swatch/._fabric.yaml", std::string("\x00\x05\x16\x07", 4)));
  items.push_back(file("swatch/.DS_Store", "bud1"));
  const UnpackedUpload r = unpack_upload(make_archive(items, Kind::zip), dir / "fabric");
  ASSERT_TRUE(r.ok) << r.refusal.message;
  EXPECT_FALSE(fs::exists(dir / "fabric" / ".DS_Store"));
  EXPECT_FALSE(fs::exists(dir / "fabric" / "__MACOSX"));
  EXPECT_TRUE(fs::exists(dir / "fabric" / "fabric.yaml"));
}

TEST(ArchiveUpload, NamesThatLeaveTheFolderAreRefusedInBothKinds) {
  for (const Kind kind : {Kind::zip, Kind::tar_gz}) {
    std::vector<Item> items = record_folder_items("");
    items.push_back(file("../yarnfit_evil.csv", "a,b\n"));
    expect_refused(make_archive(items, kind), 422, "../yarnfit_evil.csv: a name may not leave the folder");
    items.back().name = "sub/../../yarnfit_evil.csv";
    expect_refused(make_archive(items, kind), 422, "may not leave the folder");
    items.back().name = "/tmp/yarnfit_evil.csv";
    expect_refused(make_archive(items, kind), 422, "/tmp/yarnfit_evil.csv: an absolute name");
  }
}

TEST(ArchiveUpload, LinksAndDevicesAreRefused) {
  for (const Kind kind : {Kind::zip, Kind::tar_gz}) {
    std::vector<Item> items = record_folder_items("");
    items.push_back({"passwd.csv", "", AE_IFLNK, "/etc/passwd", false});
    expect_refused(make_archive(items, kind), 422, "passwd.csv: a symbolic link");
  }
  std::vector<Item> items = record_folder_items("");
  items.push_back({"copy.csv", "", AE_IFREG, "fabric.yaml", true});
  expect_refused(make_archive(items, Kind::tar_gz), 422, "copy.csv: a hard link");
  items.back() = {"tty.csv", "", AE_IFCHR, "", false};
  expect_refused(make_archive(items, Kind::tar_gz), 422, "tty.csv: a device");
}

TEST(ArchiveUpload, AZipBombStopsAtTheUnpackedLimit) {
  std::vector<Item> items = record_folder_items("");
  items.push_back(file("stretch_bias.csv", std::string(20u << 20, '0')));  // 20 MiB of zeros, ~20 kB zipped
  const std::string bomb = make_archive(items, Kind::zip);
  ASSERT_LT(bomb.size(), 200u << 10);
  UploadLimits limits;
  limits.max_unpacked_bytes = 4u << 20;
  expect_refused(bomb, 413, "more than 4194304 bytes unpacked", limits);
  limits = {};
  limits.max_file_bytes = 1u << 20;
  expect_refused(bomb, 413, "stretch_bias.csv: larger than 1048576 bytes", limits);
}

TEST(ArchiveUpload, CountAndSizeLimitsHold) {
  std::vector<Item> items = record_folder_items("");
  for (int i = 0; i < 12; ++i) items.push_back(file("extra_" + std::to_string(i) + ".txt", "x"));
  UploadLimits limits;
  limits.max_files = 10;
  expect_refused(make_archive(items, Kind::tar_gz), 413, "more than 10 files", limits);
  limits = {};
  limits.max_archive_bytes = 100;
  expect_refused(make_archive(record_folder_items(""), Kind::zip), 413, "the upload is larger than 100 bytes", limits);
}

TEST(ArchiveUpload, WhatIsNotAnArchiveOrNotARecordsFileIsRefused) {
  expect_refused("fabric: {id: x}\n", 415, "not a .zip or .tar.gz archive");
  expect_refused(std::string("\x89PNG\r\n\x1a\n", 8) + std::string(200, '\x01'), 415, "not a .zip or .tar.gz archive");
  expect_refused("", 415, "not a .zip or .tar.gz archive");
  std::vector<Item> items = record_folder_items("");
  items.push_back(file("setup.exe", "MZ"));
  expect_refused(make_archive(items, Kind::zip), 422, "setup.exe: not a kind of file a fabric record holds");
  expect_refused(make_archive({folder("empty/")}, Kind::zip), 422, "the archive holds no files");
  // Damaged archives: each kind cut in half.
  for (const Kind kind : {Kind::zip, Kind::tar_gz}) {
    const std::string whole = make_archive(record_folder_items(""), kind);
    expect_refused(whole.substr(0, whole.size() / 2), 422, "damaged archive");
  }
}

// Names another tool would read as other files: a second entry of one name (unzip keeps the
// last, libarchive the first), names that differ only in case, a file where a folder is, names
// that are not plain ASCII, and folders without end.
TEST(ArchiveUpload, NamesThatCollideOrAreNotPlainAreRefused) {
  for (const Kind kind : {Kind::zip, Kind::tar_gz}) {
    std::vector<Item> items = record_folder_items("");
    items.push_back(file("fabric.yaml", "id: other\n"));
    expect_refused(make_archive(items, kind), 422, "fabric.yaml: a second entry of that name");
    items.back() = file("Fabric.YAML", "id: other\n");
    expect_refused(make_archive(items, kind), 422, "Fabric.YAML: a second entry of that name");
    items.back() = file("tile.pyp/inner.csv", "a\n");
    expect_refused(make_archive(items, kind), 422, "tile.pyp: both a file and a folder");
    items.back() = file("st\xc3\xa4rke.csv", "a\n");
    expect_refused(make_archive(items, kind), 422, "a character other than");
  }
  std::vector<Item> deep = record_folder_items("");
  deep.push_back(file("a/b/c/d/e/f/g/h/i/j.csv", "a\n"));
  expect_refused(make_archive(deep, Kind::tar_gz), 422, "folders deeper than 8");
  std::vector<Item> folders = record_folder_items("");
  for (int i = 0; i < 30; ++i) folders.push_back(folder("d" + std::to_string(i) + "/"));
  UploadLimits limits;
  limits.max_entries = 20;
  expect_refused(make_archive(folders, Kind::tar_gz), 413, "more than 20 entries", limits);
}

TEST(ArchiveUpload, AnExistingFolderIsNeverReplaced) {
  ScratchDir dir("upload_exists");
  fs::create_directories(dir / "fabric");
  yarnfit::testing::write_file(dir / "fabric" / "fabric.yaml", "mine\n");
  const UnpackedUpload r = unpack_upload(make_archive(record_folder_items(""), Kind::zip), dir / "fabric");
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(read_file(dir / "fabric" / "fabric.yaml"), "mine\n");
  EXPECT_EQ(listing(dir.path()).size(), 2u);
}

TEST(ArchiveUpload, EntryNamesAreJudgedOneByOne) {
  EXPECT_EQ(entry_name_problem("fabric.yaml", 255), "");
  EXPECT_EQ(entry_name_problem("swatch/stretch_weft.csv", 255), "");
  EXPECT_NE(entry_name_problem("..", 255), "");
  EXPECT_NE(entry_name_problem("a/./b.csv", 255), "");
  EXPECT_NE(entry_name_problem("a//b.csv", 255), "");
  EXPECT_NE(entry_name_problem("C:/x.csv", 255), "");
  EXPECT_NE(entry_name_problem("a\\..\\b.csv", 255), "");
  EXPECT_NE(entry_name_problem(std::string("a\nb.csv"), 255), "");
  EXPECT_NE(entry_name_problem(std::string(300, 'a'), 255), "");
}

}  // namespace
}  // namespace yarnfit::service

namespace yarnfit::service {
namespace {

// The server unpacks in a child process under resource limits (isolated_unpack.hpp): the same
// folder as in-process when the archive is fair, a refusal and nothing left when it costs more.
TEST(IsolatedUnpack, AFairArchiveUnpacksAsInProcess) {
  ScratchDir dir("isolated");
  const std::string zip = testing::archives::make_archive(
      {testing::archives::file("swatch/fabric.yaml", "id: a\n"), testing::archives::file("swatch/stretch_weft.csv", "1,2\n")},
      testing::archives::Kind::zip);
  const UnpackedUpload in_process = unpack_upload(zip, dir / "a");
  const UnpackedUpload isolated = unpack_upload_isolated(zip, dir / "b");
  ASSERT_TRUE(isolated.ok) << isolated.refusal.message;
  EXPECT_EQ(isolated.files, in_process.files);
  EXPECT_EQ(isolated.unpacked_bytes, in_process.unpacked_bytes);
  EXPECT_EQ(read_file(dir / "b" / "stretch_weft.csv"), "1,2\n");
  // A refusal crosses the process boundary with its status and message.
  const UnpackedUpload evil = unpack_upload_isolated(
      testing::archives::make_archive({testing::archives::file("../x.csv", "1\n")}, testing::archives::Kind::tar_gz), dir / "c");
  EXPECT_EQ(evil.refusal.status, 422);
  EXPECT_EQ(evil.refusal.message, unpack_upload(testing::archives::make_archive({testing::archives::file("../x.csv", "1\n")},
                                                                               testing::archives::Kind::tar_gz),
                                                dir / "d")
                                      .refusal.message);
}

// The wall-clock deadline, the one limit a test can reach on purpose: the child is killed in
// the middle of its work, the upload refused and its half-written folder removed. (Memory, CPU
// and file size are RLIMIT_AS, RLIMIT_CPU and RLIMIT_FSIZE, enforced by the kernel.)
TEST(IsolatedUnpack, PastItsDeadlineTheChildIsStoppedAndNothingIsLeft) {
  ScratchDir dir("isolated_limits");
  std::vector<testing::archives::Item> items{testing::archives::file("swatch/fabric.yaml", "id: a\n")};
  for (int i = 0; i < 150; ++i)
    items.push_back(testing::archives::file("swatch/t" + std::to_string(i) + ".csv", std::string(200u << 10, '0')));
  const std::string zip = testing::archives::make_archive(items, testing::archives::Kind::tar_gz);
  UnpackIsolation hurried;
  hurried.wall_seconds = 0;
  const UnpackedUpload late = unpack_upload_isolated(zip, dir / "b", {}, hurried);
  EXPECT_FALSE(late.ok);
  EXPECT_EQ(late.refusal.status, 413) << late.refusal.message;
  EXPECT_NE(late.refusal.message.find("more than the unpacking may use (0 s)"), std::string::npos) << late.refusal.message;
  EXPECT_TRUE(fs::is_empty(dir.path())) << "left behind in " << dir.path();
  EXPECT_TRUE(unpack_upload_isolated(zip, dir / "c").ok);  // the same archive, given its time
}

}  // namespace
}  // namespace yarnfit::service
