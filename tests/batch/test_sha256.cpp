// SHA-256 (OpenSSL underneath) against the FIPS 180-2 examples, incremental updates against
// the one-shot digest, a file against `sha256sum`, and misuse that must throw rather than
// return a digest.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>

#include "fabrics_db/records/sha256.hpp"
#include "tests/test_support.hpp"
#include "tests/expect_error.hpp"

namespace yarnfit::testing {
namespace {

TEST(Sha256, MatchesTheFips180Examples) {
  EXPECT_EQ(db::sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(db::sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(db::sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(db::sha256_hex(std::string(1000000, 'a')),
            "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Sha256, IncrementalUpdatesGiveTheOneShotDigest) {
  // A million 'a' in uneven pieces: block boundaries fall inside update calls.
  db::Sha256 h;
  const std::string piece(997, 'a');
  std::size_t left = 1000000;
  while (left > 0) {
    const std::size_t n = std::min(left, piece.size());
    h.update(std::string_view(piece.data(), n));
    left -= n;
  }
  EXPECT_EQ(h.hex_digest(), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
  // Arbitrary bytes (NULs included) split at every length from 0 to 130 around the 64-byte block.
  std::mt19937 rng(7);
  std::string bytes(300, '\0');
  for (char& c : bytes) c = static_cast<char>(rng() & 0xff);
  const std::string whole = db::sha256_hex(bytes);
  for (std::size_t cut = 0; cut <= 130; ++cut) {
    db::Sha256 parts;
    parts.update(std::string_view(bytes).substr(0, cut));
    parts.update("");
    parts.update(std::string_view(bytes).substr(cut));
    EXPECT_EQ(parts.hex_digest(), whole) << "cut at " << cut;
  }
}

TEST(Sha256, DigestOfAFileIsTheOneSha256sumPrints) {
  if (std::system("command -v sha256sum >/dev/null 2>&1") != 0) GTEST_SKIP() << "sha256sum is not installed";
  ScratchDir dir("sha256");
  const fs::path file = dir / "bytes.bin";
  std::mt19937 rng(11);
  std::string bytes(200003, '\0');
  for (char& c : bytes) c = static_cast<char>(rng() & 0xff);
  write_file(file, bytes);

  db::Sha256 h;
  const std::string text = read_file(file);
  ASSERT_EQ(text, bytes);
  for (std::size_t at = 0; at < text.size(); at += 4096) h.update(std::string_view(text).substr(at, 4096));
  const std::string ours = h.hex_digest();

  const std::string command = "sha256sum " + quoted(file);
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
  ASSERT_TRUE(pipe) << command;
  std::string line;
  std::array<char, 256> buf{};
  while (std::fgets(buf.data(), static_cast<int>(buf.size()), pipe.get())) line += buf.data();
  ASSERT_GE(line.size(), 64u) << command << " printed: " << line;
  EXPECT_EQ(ours, line.substr(0, 64)) << command << " printed: " << line;
}

TEST(Sha256, UseAfterTheDigestThrows) {
  db::Sha256 h;
  h.update("abc");
  EXPECT_EQ(h.hex_digest(), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_ERROR(h.update("d"), yarnfit::ErrorCategory::system);
  EXPECT_ERROR((void)h.hex_digest(), yarnfit::ErrorCategory::system);
}

}  // namespace
}  // namespace yarnfit::testing
