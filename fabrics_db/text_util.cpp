#include "fabrics_db/text_util.hpp"

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

#include "numerics/util/format.hpp"
#include "numerics/util/whole_file.hpp"

namespace yarnfit::db {

std::string_view trim(std::string_view s) {
  const auto is_space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

bool read_text_file(const std::filesystem::path& file, std::string& text, std::string& why) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) {
    why = "cannot read file: no such file";
    return false;
  }
  if (std::filesystem::is_directory(file, ec)) {
    why = "cannot read file: it is a folder";
    return false;
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    why = std::string("cannot read file: ") + std::strerror(errno);
    return false;
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) {
    why = "cannot read file: read error";
    return false;
  }
  text = ss.str();
  return true;
}

bool valid_utf8(std::string_view s, std::size_t* bad_at) {
  const auto bad = [&](std::size_t i) {
    if (bad_at != nullptr) *bad_at = i;
    return false;
  };
  for (std::size_t i = 0; i < s.size();) {
    const auto b = static_cast<unsigned char>(s[i]);
    std::size_t n = 0;
    std::uint32_t code = 0;
    if (b < 0x80) {
      ++i;
      continue;
    }
    if (b >= 0xc2 && b <= 0xdf) n = 1, code = b & 0x1fu;
    else if (b >= 0xe0 && b <= 0xef) n = 2, code = b & 0x0fu;
    else if (b >= 0xf0 && b <= 0xf4) n = 3, code = b & 0x07u;
    else return bad(i);
    for (std::size_t k = 1; k <= n; ++k) {
      if (i + k >= s.size()) return bad(i);
      const auto c = static_cast<unsigned char>(s[i + k]);
      if ((c & 0xc0u) != 0x80u) return bad(i);
      code = (code << 6) | (c & 0x3fu);
    }
    const std::uint32_t least[] = {0, 0x80, 0x800, 0x10000};
    if (code < least[n] || code > 0x10ffff || (code >= 0xd800 && code <= 0xdfff)) return bad(i);
    i += n + 1;
  }
  return true;
}

std::filesystem::path file_inside_folder(const std::filesystem::path& folder, const std::string& name,
                                         std::string& why) {
  namespace fs = std::filesystem;
  if (name.find('\0') != std::string::npos || !valid_utf8(name)) {
    why = "the name is not valid UTF-8 text";
    return {};
  }
  const fs::path given(name);
  if (given.is_absolute() || given.has_root_name() || given.has_root_directory()) {
    why = "an absolute path: a record names its files relative to its own folder";
    return {};
  }
  const fs::path normal = given.lexically_normal();
  if (normal.empty() || *normal.begin() == ".." || normal == ".") {
    why = "'" + name + "' leaves the record's folder: a record names files inside its own folder";
    return {};
  }
  const fs::path file = folder / normal;
  std::error_code ec;
  const fs::file_status status = fs::status(file, ec);
  if (!fs::exists(status)) {
    why = "cannot read '" + name + "': no such file in the record's folder";
    return {};
  }
  // A link (or a linked folder on the way) may point anywhere: the file must be inside the
  // folder once every link is resolved.
  std::error_code real_ec, home_ec;
  const fs::path real = fs::canonical(file, real_ec);
  const fs::path home = fs::canonical(folder, home_ec);
  const bool inside = std::mismatch(home.begin(), home.end(), real.begin(), real.end()).first == home.end();
  if (real_ec || home_ec || !inside) {
    why = "'" + name + "' is a link that leaves the record's folder: a record names files inside its own folder";
    return {};
  }
  if (!fs::is_regular_file(status)) {
    why = "cannot read '" + name + "': not a regular file";
    return {};
  }
  return file;
}

void write_text_file_atomically(const std::filesystem::path& file, const std::string& text) {
  numerics::write_file_whole(file, text);
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0u : 1u)});
      diag = up;
    }
  }
  return row[b.size()];
}

std::string closest_match(std::string_view word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_d = std::max<std::size_t>(2, word.size() / 3) + 1;
  for (const auto& c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  return best;
}

std::string join_words(const std::vector<std::string>& words, std::string_view last) {
  std::string out;
  for (std::size_t i = 0; i < words.size(); ++i) {
    if (i > 0) out += (i + 1 == words.size()) ? std::string(last) : std::string(", ");
    out += words[i];
  }
  return out;
}

std::string format_g(double value, int digits) { return numerics::format_number(value, digits); }

std::string format_shortest(double value) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, value);
  return std::string(buf, r.ptr);
}

std::string format_utc(long long seconds) {
  const auto t = static_cast<std::time_t>(seconds);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

}  // namespace yarnfit::db
