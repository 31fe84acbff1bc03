#include "fabrics_db/records/sha256.hpp"
#include "numerics/util/error.hpp"

#include <openssl/err.h>
#include <openssl/evp.h>

#include <array>

namespace yarnfit::db {

namespace {

// an Error naming the failed step, with OpenSSL's queued reasons (oldest first) appended.
[[noreturn]] void fail(const std::string& step) {
  std::string message = "SHA-256 (OpenSSL): " + step + " failed";
  while (const unsigned long code = ERR_get_error()) {
    std::array<char, 256> text{};
    ERR_error_string_n(code, text.data(), text.size());
    message += std::string(": ") + text.data();
  }
  throw Error(ErrorCategory::system, message);
}

}  // namespace

void Sha256::FreeContext::operator()(evp_md_ctx_st* ctx) const { EVP_MD_CTX_free(ctx); }

Sha256::Sha256() : m_ctx(EVP_MD_CTX_new()) {
  if (!m_ctx) fail("EVP_MD_CTX_new");
  if (EVP_DigestInit_ex(m_ctx.get(), EVP_sha256(), nullptr) != 1) fail("EVP_DigestInit_ex");
}

void Sha256::update(std::string_view bytes) {
  if (m_finished) throw Error(ErrorCategory::system, "SHA-256: update after hex_digest");
  if (EVP_DigestUpdate(m_ctx.get(), bytes.data(), bytes.size()) != 1) fail("EVP_DigestUpdate");
}

std::string Sha256::hex_digest() {
  if (m_finished) throw Error(ErrorCategory::system, "SHA-256: hex_digest called twice");
  std::array<unsigned char, EVP_MAX_MD_SIZE> digest{};
  unsigned int size = 0;
  if (EVP_DigestFinal_ex(m_ctx.get(), digest.data(), &size) != 1) fail("EVP_DigestFinal_ex");
  m_finished = true;
  if (size != 32)
    throw Error(ErrorCategory::system, "SHA-256 (OpenSSL): digest of " + std::to_string(size) + " bytes, not 32");
  constexpr char k_hex[] = "0123456789abcdef";
  std::string hex;
  hex.reserve(2 * size);
  for (unsigned int i = 0; i < size; ++i) {
    hex += k_hex[digest[i] >> 4];
    hex += k_hex[digest[i] & 0xf];
  }
  return hex;
}

std::string sha256_hex(std::string_view bytes) {
  Sha256 h;
  h.update(bytes);
  return h.hex_digest();
}

}  // namespace yarnfit::db
