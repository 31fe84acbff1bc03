#include "fabrics_db/records/fabric_hash.hpp"

#include <algorithm>
#include <filesystem>
#include <vector>

#include "fabrics_db/records/sha256.hpp"
#include "fabrics_db/text_util.hpp"

namespace yarnfit::db {

namespace fs = std::filesystem;

namespace {

// The files of a valid record: fabric.yaml first, then the others in path order (a map of
// tests iterates in direction order already; sorting makes the order independent of it).
std::vector<fs::path> record_files(const db::FabricLoad& load) {
  std::vector<fs::path> files;
  if (load.fabric) {
    const db::Fabric& f = *load.fabric;
    for (const auto& [d, t] : f.stretch_tests) files.push_back(t.file);
    for (const auto& [d, t] : f.bending_tests) files.push_back(t.file);
    for (const auto& [d, tests] : f.fab_tests)
      for (const auto& t : tests) files.push_back(t.file);
    if (f.fab_source && !f.fab_source->file.empty()) files.push_back(f.fab_source->file);
    if (f.pattern && !f.pattern->knit) files.push_back(f.pattern->file);  // a knit is in fabric.yaml
  } else {
    std::error_code ec;
    for (fs::recursive_directory_iterator it(load.folder, ec), end; !ec && it != end; it.increment(ec))
      if (it->is_regular_file() && it->path().filename() != db::k_fabric_file_name) files.push_back(it->path());
  }
  std::sort(files.begin(), files.end());
  files.erase(std::unique(files.begin(), files.end()), files.end());
  files.insert(files.begin(), load.folder / db::k_fabric_file_name);
  return files;
}

// A file's name as the hash sees it: relative to the record's folder when inside it, so that
// a database moved elsewhere keeps its hashes.
std::string hashed_name(const fs::path& file, const fs::path& folder) {
  const fs::path rel = file.lexically_relative(folder);
  return (rel.empty() || *rel.begin() == "..") ? fs::weakly_canonical(file).string() : rel.generic_string();
}

}  // namespace

std::string fabric_hash(const db::FabricLoad& load, const nlohmann::json& options) {
  Sha256 h;
  const auto field = [&h](const std::string& text) {
    // Length-prefixed, so that no two sequences of fields hash alike.
    h.update(std::to_string(text.size()));
    h.update(":");
    h.update(text);
  };
  field("yarnfit-batch-job-v1");
  field(options.dump());
  for (const auto& file : record_files(load)) {
    field(hashed_name(file, load.folder));
    std::string text, why;
    if (db::read_text_file(file, text, why)) field(text);
    else field("unreadable: " + why);
  }
  return h.hex_digest();
}

}  // namespace yarnfit::db
