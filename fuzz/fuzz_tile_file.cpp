// tile.json as read back by report, export, resume and the service: JSON that does not
// parse is refused before the reader; the reader throws std::runtime_error naming the file and
// the field (results/json_fields.hpp). Any other exception is a finding.
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "fuzz/fuzz_support.hpp"
#include "results/tile_file.hpp"

YARNFIT_FUZZ_TARGET(tile_file) {
  using namespace yarnfit;
  const nlohmann::json j = nlohmann::json::parse(fuzz::as_text(data, size), nullptr, false);
  if (j.is_discarded()) return 0;
  try {
    (void)results::tile_file_from_json(j);
  } catch (const std::runtime_error&) {
  }
  return 0;
}
