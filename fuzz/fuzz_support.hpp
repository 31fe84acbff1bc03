#pragma once
// What the fuzz targets share: a scratch folder of their own (the readers below take paths,
// so the bytes go to a file first) and the split of one input into the several files of a
// record. Every target states which exceptions its reader may throw by its contract; any
// other exception, like any sanitizer report, is a finding.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <unistd.h>

namespace yarnfit::fuzz {

// A target's entry. Under libFuzzer it is LLVMFuzzerTestOneInput; built with
// YARNFIT_FUZZ_REPLAY (tests/fuzz_replay) every target is registered under its name, so that
// the kept inputs of tests/fuzz_regressions are replayed by the ordinary test suite.
using Target = int (*)(const std::uint8_t* data, std::size_t size);
inline std::map<std::string, Target>& replay_targets() {
  static std::map<std::string, Target> targets;
  return targets;
}
struct RegisterTarget {
  RegisterTarget(const char* name, Target target) { replay_targets()[name] = target; }
};

// A broken promise of a reader (not an exception it documents): a crash under libFuzzer, an
// exception naming it when replayed.
[[noreturn]] inline void finding([[maybe_unused]] const char* what) {
#ifdef YARNFIT_FUZZ_REPLAY
  throw std::logic_error(what);
#else
  __builtin_trap();
#endif
}

// /dev/shm (memory, when present) or TMPDIR, one folder per process: libFuzzer's -jobs and
// -fork run several processes, each with its own folder. Removed when the process exits.
inline const std::filesystem::path& scratch_folder() {
  static const std::filesystem::path folder = [] {
    std::filesystem::path base = std::filesystem::is_directory("/dev/shm") ? std::filesystem::path("/dev/shm")
                                                                          : std::filesystem::temp_directory_path();
    std::filesystem::path f = base / ("yarnfit-fuzz-" + std::to_string(::getpid()));
    std::filesystem::remove_all(f);
    std::filesystem::create_directories(f);
    return f;
  }();
  static const struct Cleanup {
    ~Cleanup() {
      std::error_code ec;
      std::filesystem::remove_all(folder, ec);
    }
  } cleanup;
  return folder;
}

inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

inline void write_bytes(const std::filesystem::path& file, std::string_view bytes) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// The input as a file in the scratch folder, named `name` (the readers dispatch on extensions).
inline std::filesystem::path input_file(std::string_view bytes, const std::string& name) {
  const std::filesystem::path file = scratch_folder() / name;
  write_bytes(file, bytes);
  return file;
}

// One input as several files, in the layout `head` prints them in:
//   ==> fabric.yaml <==
//   …
//   ==> stretch_weft.csv <==
// Names are kept to [A-Za-z0-9._-] (no folders, no "..") so that nothing leaves the folder;
// text before the first marker goes to the first name given.
inline std::vector<std::pair<std::string, std::string>> split_files(std::string_view bytes,
                                                                    const std::string& first_name) {
  std::vector<std::pair<std::string, std::string>> files{{first_name, ""}};
  std::size_t at = 0;
  while (at <= bytes.size()) {
    std::size_t end = bytes.find('\n', at);
    if (end == std::string_view::npos) end = bytes.size();
    const std::string_view line = bytes.substr(at, end - at);
    if (line.size() > 8 && line.substr(0, 4) == "==> " && line.substr(line.size() - 4) == " <==") {
      std::string name;
      for (char c : line.substr(4, line.size() - 8))
        if ((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '.' || c == '_' ||
            c == '-')
          name += c;
      if (name.empty() || name == "." || name == "..") name = "unnamed";
      files.emplace_back(name, "");
    } else if (end < bytes.size()) {
      files.back().second.append(line).append("\n");
    } else {
      files.back().second.append(line);
    }
    at = end + 1;
  }
  return files;
}

// A fresh, empty folder in the scratch folder.
inline std::filesystem::path fresh_folder(const std::string& name) {
  const std::filesystem::path f = scratch_folder() / name;
  std::error_code ec;
  std::filesystem::remove_all(f, ec);
  std::filesystem::create_directories(f);
  return f;
}

}  // namespace yarnfit::fuzz

#ifdef YARNFIT_FUZZ_REPLAY
#define YARNFIT_FUZZ_TARGET(name)                                                                 \
  static int fuzz_##name(const std::uint8_t* data, std::size_t size);                            \
  static const ::yarnfit::fuzz::RegisterTarget register_##name(#name, &fuzz_##name);             \
  static int fuzz_##name(const std::uint8_t* data, std::size_t size)
#else
#define YARNFIT_FUZZ_TARGET(name) extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
#endif
