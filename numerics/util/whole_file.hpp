#pragma once
// Every output file of yarnfit is written whole or not at all (SPEC; issue 52).

#include <filesystem>
#include <functional>
#include <string>

namespace yarnfit::numerics {

// Writes `text` to `file` through a temporary file in the same folder (".NAME.tmpPID"), synced,
// then renamed over it, so a reader never sees a half-written file, and the previous file stays
// whole when the write fails. Throws an Error naming the file and the system's
// reason ("No space left on device"); the temporary file is removed then. Temporary files of
// the same name left by a process that is gone (killed before its rename) are removed after a
// write succeeds.
void write_file_whole(const std::filesystem::path& file, const std::string& text);
// Whether the process `pid` no longer runs (what a file named after its writer's pid needs to
// know before it may be removed as left behind).
[[nodiscard]] bool process_is_gone(long pid);
namespace detail {
// Fault injection for tests (issue 52): called with the temporary file once it is written,
// just before the rename; it may throw (a failing write) or end the process (a kill between
// the temporary file and the rename). Empty: nothing is called.
void set_before_rename_hook(std::function<void(const std::filesystem::path& temporary)> hook);
}  // namespace detail

}  // namespace yarnfit::numerics
