#pragma once
// Small text helpers shared by the readers of fabrics_db.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace yarnfit::db {

std::string_view trim(std::string_view s);
// Reads a whole file; on failure returns false and a message such as
// "cannot read file: No such file or directory".
bool read_text_file(const std::filesystem::path& file, std::string& text, std::string& why);
// numerics::write_file_whole (numerics/util/whole_file.hpp): the file whole or not at all.
void write_text_file_atomically(const std::filesystem::path& file, const std::string& text);
// Levenshtein distance, for "did you mean" hints on misspelt keys.
std::size_t edit_distance(std::string_view a, std::string_view b);
// The closest of `candidates` to `word` if it is a plausible typo, else "".
std::string closest_match(std::string_view word, const std::vector<std::string>& candidates);
// "a, b and c"
std::string join_words(const std::vector<std::string>& words, std::string_view last = " or ");
// True when `s` is well-formed UTF-8 (no stray continuation bytes, no overlong forms, no
// surrogates, nothing past U+10FFFF); `bad_at` gets the offset of the first bad byte.
bool valid_utf8(std::string_view s, std::size_t* bad_at = nullptr);
// The file a record names `name`, inside `folder` (SPEC §2: a relative name that leaves the
// folder neither by ".." nor through a link; a record arrives from strangers over HTTP). Empty,
// with `why` saying what is wrong with the name (never anything read from another file), when
// the name is not such a file.
std::filesystem::path file_inside_folder(const std::filesystem::path& folder, const std::string& name,
                                         std::string& why);
// ISO 8601 UTC time of `seconds` since 1970: "2020-01-27T12:35:50Z".
std::string format_utc(long long seconds);
// printf-style "%.<digits>g" of a double.
std::string format_g(double value, int digits = 6);
// The shortest text that reads back as exactly `value`: 0.1, not 0.10000000000000001.
std::string format_shortest(double value);

}  // namespace yarnfit::db
