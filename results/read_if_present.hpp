#pragma once
// A result file read as its type when it is there: none when it is absent, and none with the
// reason in `why` when it cannot be read (the readers name the file and the field).

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>

namespace yarnfit::results {

template <class File, class Read>
std::optional<File> read_if_present(const std::filesystem::path& file, Read read, std::string* why = nullptr) {
  if (!std::filesystem::exists(file)) return std::nullopt;
  try {
    return read(file);
  } catch (const std::runtime_error& e) {
    if (why) *why = e.what();
    return std::nullopt;
  }
}

}  // namespace yarnfit::results
