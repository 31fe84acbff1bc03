#include "fabrics_db/targets/uniform_targets.hpp"

#include <map>
#include <sstream>
#include <stdexcept>
#include <string>

#include "fabrics_db/csv/csv_table.hpp"
#include "fabrics_db/text_util.hpp"
#include "numerics/util/error.hpp"

namespace yarnfit::db {

namespace {

constexpr const char* k_columns[] = {"direction", "kind", "stretch", "compression", "stress_s_N_per_m"};
constexpr int k_digits = 10;  // significant digits of every number in the file

// A value as the file stores it: written with k_digits and read back by the reader.
double stored(double value) {
  std::string why;
  const auto v = parse_finite_number(format_g(value, k_digits), why);
  return v ? *v : value;  // the reader would refuse a non-finite value; keep it as it is
}

}  // namespace

std::string uniform_targets_csv(const std::vector<DirectionTargets>& targets) {
  std::ostringstream out;
  out << "direction,kind,stretch,compression,stress_s_N_per_m,curvature_per_m,stress_kappa_N\n";
  for (const auto& t : targets) {
    const std::string dir(to_string(t.direction));
    for (const auto& p : t.stretch) {
      out << dir << ",stretch," << format_g(p.stretch, k_digits) << "," << format_g(p.compression, k_digits) << ","
          << format_g(p.stress, k_digits) << ",,\n";
    }
    for (const auto& b : t.bending) {
      out << dir << ",bending,,,," << format_g(b.curvature, k_digits) << "," << format_g(b.stress, k_digits) << "\n";
    }
  }
  return out.str();
}

void write_uniform_targets_csv(const std::vector<DirectionTargets>& targets, const std::filesystem::path& file) {
  write_text_file_atomically(file, uniform_targets_csv(targets));
}

std::vector<DirectionTargets> as_stored(const std::vector<DirectionTargets>& targets) {
  std::vector<DirectionTargets> out = targets;
  for (auto& t : out) {
    for (auto& p : t.stretch) {
      p.stretch = stored(p.stretch);
      p.compression = stored(p.compression);
      p.stress = stored(p.stress);
    }
    for (auto& b : t.bending) {
      b.curvature = stored(b.curvature);
      b.stress = stored(b.stress);
    }
  }
  return out;
}

std::optional<std::vector<DirectionTargets>> read_uniform_targets(const std::filesystem::path& file,
                                                                 Problems& problems) {
  const std::size_t before = problems.size();
  const auto table = read_csv(file, CsvOptions{}, problems);
  if (!table) return std::nullopt;
  const std::string label = table->file_label;

  std::map<std::string, int> col;
  for (const char* name : k_columns) {
    if (const auto c = table->column(name)) {
      col[name] = *c;
    } else {
      problems.add(label, table->header_line, name, "missing column (expected header direction,kind,stretch,"
                                                    "compression,stress_s_N_per_m,curvature_per_m,stress_kappa_N)");
    }
  }
  const auto curvature_col = table->column("curvature_per_m");
  const auto kappa_col = table->column("stress_kappa_N");
  if (problems.size() != before) return std::nullopt;

  std::map<Direction, DirectionTargets> by_dir;
  std::map<Direction, int> last_line;
  bool curvature_missing_reported = false;
  for (const auto& row : table->rows) {
    auto cell = [&](int c) -> std::string { return c < static_cast<int>(row.cells.size()) ? row.cells[c] : ""; };
    auto number = [&](std::optional<int> c, const char* field, double& out) {
      if (!c) return false;
      std::string why;
      const std::string text = cell(*c);
      if (text.empty()) {
        problems.add(label, row.line, field, "empty cell (a number is expected)");
        return false;
      }
      const auto v = parse_finite_number(text, why);
      if (!v) {
        problems.add(label, row.line, field, "'" + text + "': " + why);
        return false;
      }
      out = *v;
      return true;
    };
    const std::string dname = cell(col["direction"]);
    const auto dir = parse_direction(dname);
    if (!dir) {
      problems.add(label, row.line, "direction", "unknown direction '" + dname + "' (expected weft, bias or warp)");
      continue;
    }
    DirectionTargets& t = by_dir[*dir];
    t.direction = *dir;
    const std::string kind = cell(col["kind"]);
    if (kind == "stretch") {
      UniaxialPoint p;
      bool ok = number(col["stretch"], "stretch", p.stretch);
      ok = number(col["compression"], "compression", p.compression) && ok;
      ok = number(col["stress_s_N_per_m"], "stress_s_N_per_m", p.stress) && ok;
      if (!ok) continue;
      if (p.stretch <= -1.0) {
        problems.add(label, row.line, "stretch", "stretch " + format_g(p.stretch) + " must be > -1");
        continue;
      }
      if (!t.stretch.empty() && p.stretch <= t.stretch.back().stretch) {
        problems.add(label, row.line, "stretch",
                     "stretch " + format_g(p.stretch) + " does not increase (previous " + std::string(dname) +
                         " row, line " + std::to_string(last_line[*dir]) + ", has " +
                         format_g(t.stretch.back().stretch) + ")");
        continue;
      }
      p.converged = true;
      t.stretch.push_back(p);
      last_line[*dir] = row.line;
    } else if (kind == "bending") {
      if (!curvature_col || !kappa_col) {
        if (!curvature_missing_reported) {
          problems.add(label, row.line, !curvature_col ? "curvature_per_m" : "stress_kappa_N",
                       "missing column, needed by bending rows");
          curvature_missing_reported = true;
        }
        continue;
      }
      BendingPoint b;
      bool ok = number(curvature_col, "curvature_per_m", b.curvature);
      ok = number(kappa_col, "stress_kappa_N", b.stress) && ok;
      if (ok) t.bending.push_back(b);
    } else {
      problems.add(label, row.line, "kind", "unknown kind '" + kind + "' (expected stretch or bending)");
    }
  }
  std::vector<DirectionTargets> out;
  for (auto& [dir, t] : by_dir) {
    if (t.stretch.size() == 1) {
      problems.add(label, last_line[dir], "stretch",
                   std::string(to_string(dir)) + " has one stretch row; at least 2 are needed");
    }
    out.push_back(std::move(t));
  }
  if (out.empty() && problems.size() == before) problems.add(label, table->header_line, "file", "no target rows");
  if (problems.size() != before) return std::nullopt;
  return out;
}

std::vector<DirectionTargets> read_uniform_targets(const std::filesystem::path& file) {
  Problems problems;
  auto targets = read_uniform_targets(file, problems);
  if (!targets) throw Error(ErrorCategory::input, problems.to_string());
  return std::move(*targets);
}

const DirectionTargets* find_direction(const std::vector<DirectionTargets>& targets, Direction direction) {
  for (const auto& t : targets) {
    if (t.direction == direction) return &t;
  }
  return nullptr;
}

}  // namespace yarnfit::db
