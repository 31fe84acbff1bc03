#pragma once
// SHA-256 (FIPS 180-4) through OpenSSL's EVP interface: fingerprints of fabric records
// (fabric_hash.hpp: the batch ledger's, an export's provenance) and the service's stored
// token hashes (of 256-bit random secrets).

#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>

#include "numerics/util/error.hpp"

struct evp_md_ctx_st;  // OpenSSL's EVP_MD_CTX, kept out of the includers of this header

namespace yarnfit::db {

class Sha256 {
 public:
  Sha256();
  void update(std::string_view bytes);
  // The digest as 64 lower-case hex digits; the object must not be updated afterwards (that,
  // or a second call, throws an Error).
  [[nodiscard]] std::string hex_digest();

 private:
  struct FreeContext {
    void operator()(evp_md_ctx_st* ctx) const;
  };
  std::unique_ptr<evp_md_ctx_st, FreeContext> m_ctx;
  bool m_finished = false;
};

[[nodiscard]] std::string sha256_hex(std::string_view bytes);

}  // namespace yarnfit::db
