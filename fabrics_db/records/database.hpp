#pragma once
// A fabric database: a folder whose sub-folders are fabrics (each with a fabric.yaml).
// Loading never stops at a broken fabric: each fabric carries its own problems, and
// database-wide problems (duplicate ids, no fabrics at all) are reported beside them.

#include <filesystem>
#include <string>
#include <vector>

#include "fabrics_db/records/fabric_reader.hpp"

namespace yarnfit::db {

struct DatabaseLoad {
  std::filesystem::path root;
  std::vector<FabricLoad> fabrics;  // sorted by folder name
  Problems problems;                // problems of the database as a whole
  std::vector<std::string> notes;   // e.g. sub-folders skipped because they hold no fabric

  [[nodiscard]] std::size_t valid_count() const;
  // Every problem: the database's, then each fabric's in folder order.
  [[nodiscard]] Problems all_problems() const;
};

// Loads every fabric folder directly under `root`. Duplicate ids are problems of every
// fabric that shares the id (so none of them is used), naming the other files.
DatabaseLoad load_database(const std::filesystem::path& root);

// Loads `path` whether it is one fabric folder or a database folder.
DatabaseLoad load_fabric_or_database(const std::filesystem::path& path);

}  // namespace yarnfit::db
