#pragma once
// What the fuzz targets of the result files (shell_fit.json, yarn_fit.json, tile.json, as read
// back by report, export, resume and the service) share: JSON that does not parse is refused
// before the reader; the reader may refuse the rest only with yarnfit::Error of category input,
// naming the file and the field (results/json_fields.hpp). Any other exception is a finding.

#include <cstddef>
#include <cstdint>

#include <nlohmann/json.hpp>

#include "fuzz/fuzz_support.hpp"
#include "numerics/util/error.hpp"

namespace yarnfit::fuzz {

template <class Read>
int read_result_json(const std::uint8_t* data, std::size_t size, Read read) {
  const nlohmann::json j = nlohmann::json::parse(as_text(data, size), nullptr, false);
  if (j.is_discarded()) return 0;
  try {
    (void)read(j);
  } catch (const Error& e) {
    if (e.category() != ErrorCategory::input) finding(e.what());
  }
  return 0;
}

}  // namespace yarnfit::fuzz
