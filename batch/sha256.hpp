#pragma once
// SHA-256 (FIPS 180-4), for the batch ledger's fingerprints of fabric records: a changed byte
// in a record, its curves, its tile or the fit options gives a different hash, so the fabric is
// fitted again. Not used for anything secret.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace yarnfit::batch {

class Sha256 {
 public:
  Sha256();
  void update(std::string_view bytes);
  // The digest as 64 lower-case hex digits; the object must not be updated afterwards.
  [[nodiscard]] std::string hex_digest();

 private:
  void compress(const std::uint8_t* block);
  std::array<std::uint32_t, 8> m_state{};
  std::array<std::uint8_t, 64> m_block{};
  std::size_t m_used = 0;       // bytes in m_block
  std::uint64_t m_length = 0;   // message bytes so far
};

[[nodiscard]] std::string sha256_hex(std::string_view bytes);

}  // namespace yarnfit::batch
