#include "swarm/checkpoint_json.hpp"
#include "numerics/util/error.hpp"

#include <fstream>
#include <stdexcept>
#include <string>

namespace yarnfit::swarm {

nlohmann::json checkpoint_preamble(const CheckpointKind& kind) {
  return {{"format", kind.format}, {"version", kind.version}};
}

nlohmann::json read_checkpoint_json(const std::filesystem::path& path, const CheckpointKind& kind) {
  const auto fail = [&](const std::string& reason, ErrorCategory category = ErrorCategory::input) {
    throw Error(category, std::string(kind.label) + " " + path.string() + ": " + reason);
  };
  std::ifstream in(path, std::ios::binary);
  if (!in) fail("cannot open", ErrorCategory::io);
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {  // a syntax error, or a number past a double's range
    fail(std::string("not valid JSON (") + e.what() + ")");
  }
  const auto format = doc.find("format");  // end() for anything but an object
  if (format == doc.end() || *format != kind.format)
    fail(std::string("format: expected \"") + kind.format + "\"");
  const auto version = doc.find("version");
  if (version == doc.end() || !version->is_number_integer() || *version != kind.version)
    fail("version: this build reads version " + std::to_string(kind.version));
  return doc;
}

}  // namespace yarnfit::swarm
