#include "fabrics_db/records/database.hpp"

#include <algorithm>
#include <map>

namespace yarnfit::db {

namespace fs = std::filesystem;

std::size_t DatabaseLoad::valid_count() const {
  return static_cast<std::size_t>(
      std::count_if(fabrics.begin(), fabrics.end(), [](const FabricLoad& f) { return f.ok(); }));
}

Problems DatabaseLoad::all_problems() const {
  Problems all = problems;
  for (const auto& f : fabrics) all.append(f.problems);
  return all;
}

namespace {

void mark_duplicate_ids(DatabaseLoad& db) {
  std::map<std::string, std::vector<std::size_t>> by_id;
  for (std::size_t i = 0; i < db.fabrics.size(); ++i) {
    if (!db.fabrics[i].id.empty()) by_id[db.fabrics[i].id].push_back(i);
  }
  for (const auto& [id, users] : by_id) {
    if (users.size() < 2) continue;
    for (std::size_t i : users) {
      std::vector<std::string> others;
      for (std::size_t j : users) {
        if (j != i) others.push_back((db.fabrics[j].folder / k_fabric_file_name).string());
      }
      FabricLoad& f = db.fabrics[i];
      const fs::path yaml = f.folder / k_fabric_file_name;
      std::string list;
      for (const auto& o : others) list += (list.empty() ? "" : ", ") + o;
      f.problems.add(yaml.string(), f.id_line, "id",
                     "duplicate id '" + id + "' in the database (also used by " + list + ")");
      f.fabric.reset();
    }
  }
}

}  // namespace

DatabaseLoad load_database(const fs::path& root) {
  DatabaseLoad db;
  db.root = root;
  std::error_code ec;
  if (!fs::is_directory(root, ec)) {
    db.problems.add(root.string(), 0, "file",
                    fs::exists(root, ec) ? "not a folder" : "no such folder");
    return db;
  }
  std::vector<fs::path> folders;
  for (const auto& entry : fs::directory_iterator(root, ec)) {
    if (!entry.is_directory()) continue;
    const std::string name = entry.path().filename().string();
    if (name.empty() || name.front() == '.') continue;
    if (is_fabric_folder(entry.path())) {
      folders.push_back(entry.path());
    } else {
      db.notes.push_back("skipped " + entry.path().string() + ": no " + k_fabric_file_name);
    }
  }
  if (ec) db.problems.add(root.string(), 0, "file", "cannot list folder: " + ec.message());
  std::sort(folders.begin(), folders.end());
  std::sort(db.notes.begin(), db.notes.end());
  for (const auto& folder : folders) db.fabrics.push_back(load_fabric(folder));
  if (folders.empty() && db.problems.empty()) {
    db.problems.add(root.string(), 0, "file",
                    std::string("no fabric found: neither this folder nor any sub-folder holds a ") +
                        k_fabric_file_name);
  }
  mark_duplicate_ids(db);
  return db;
}

DatabaseLoad load_fabric_or_database(const fs::path& path) {
  if (is_fabric_folder(path)) {
    DatabaseLoad db;
    db.root = path;
    db.fabrics.push_back(load_fabric(path));
    return db;
  }
  return load_database(path);
}

}  // namespace yarnfit::db
