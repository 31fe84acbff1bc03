// A FAB measurement → a yarnfit record folder, staged beside the destination and renamed into place.
#include "fabrics_db/fab/fab_import.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <chrono>
#include <ctime>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <random>

#include <yaml-cpp/yaml.h>

#include "fabrics_db/fab/fab_curves.hpp"
#include "fabrics_db/records/fabric_reader.hpp"
#include "fabrics_db/text_util.hpp"
#include "fabrics_db/records/units.hpp"
#include "numerics/util/error.hpp"

namespace yarnfit::db {
namespace {

namespace fs = std::filesystem;
using units::k_mm;

std::string lower_id(const std::string& text) {
  std::string id;
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (std::isalnum(u)) id += static_cast<char>(std::tolower(u));
    else if (!id.empty() && id.back() != '-') id += '-';
  }
  while (!id.empty() && id.back() == '-') id.pop_back();
  return id;
}

// The grain's 8 cm stretch (S2), the test its stretch_tests curve comes from; null if absent.
const FabTest* eight_cm_stretch(const std::vector<FabTest>& tests) {
  const auto it = std::find_if(tests.begin(), tests.end(), [](const FabTest& t) { return t.name == "S2"; });
  return it == tests.end() ? nullptr : &*it;
}

std::string test_csv(const FabTest& t) {
  std::string s = "cycle,branch,clamp_distance_mm,raw_force_N\n";
  for (const auto& b : t.branches)
    for (std::size_t i = 0; i < b.clamp_distance.size(); ++i)
      s += std::to_string(b.cycle) + "," + std::string(to_string(b.branch)) + "," +
           format_shortest(b.clamp_distance[i] / k_mm) + "," + format_shortest(b.raw_force[i]) + "\n";
  return s;
}

std::string stretch_csv(const StretchCurve& c, const FabTest& t) {
  std::string s = "# the " + t.name + " test's loading branches, their mean at each stretch, from its taut length " +
                  format_g(t.clamp_distance / k_mm) + " mm, zero offset " + format_g(t.zero_offset.value_or(0.0)) +
                  " N taken off (fab_tests keeps every sample)\nstretch,force_N\n";
  for (std::size_t i = 0; i < c.size(); ++i) s += format_shortest(c.stretch[i]) + "," + format_shortest(c.force[i]) + "\n";
  return s;
}

std::string description(const FabMeasurement& m, const fs::path& input) {
  std::string d = (m.name.empty() ? input.filename().string() : m.name);
  if (!m.category.empty()) d += " (" + m.category + ")";
  d += ", measured on a Browzwear FAB";
  if (m.serial) d += " (serial " + std::to_string(*m.serial) + ")";
  long long first = 0;
  for (const auto& [dir, tests] : m.tests)
    for (const auto& t : tests)
      if (t.time && (first == 0 || *t.time < first)) first = *t.time;
  if (first > 0) d += " on " + format_utc(first).substr(0, 10);
  return d + "; imported by yarnfit db import-fab from " + input.filename().string();
}

void emit_size(YAML::Emitter& y, double length, double width) {
  y << YAML::Flow << YAML::BeginMap << YAML::Key << "length_mm" << YAML::Value << format_shortest(length / k_mm)
    << YAML::Key << "width_mm" << YAML::Value << format_shortest(width / k_mm) << YAML::EndMap;
}

std::string record_yaml(const FabImportOptions& o, const FabMeasurement& m, const std::string& id,
                        const std::string& family, const std::map<Direction, std::string>& stretch_files,
                        const std::string& tile_name) {
  YAML::Emitter y;
  y << YAML::BeginMap;
  y << YAML::Key << "id" << YAML::Value << id;
  y << YAML::Key << "family" << YAML::Value << family;
  y << YAML::Key << "description" << YAML::Value << YAML::DoubleQuoted << description(m, o.input);
  y << YAML::Key << "areal_density_gsm" << YAML::Value << format_shortest(m.mass_per_area / 1e-3);
  if (m.thickness) y << YAML::Key << "thickness_mm" << YAML::Value << format_shortest(*m.thickness / k_mm);
  y << YAML::Key << "yarns" << YAML::Value << YAML::BeginSeq << YAML::BeginMap;
  const std::string material = !o.material.empty() ? o.material : !m.composition.empty() ? m.composition : "unknown";
  y << YAML::Key << "material" << YAML::Value << YAML::DoubleQuoted << material;
  y << YAML::Key << "denier" << YAML::Value << format_shortest(*o.denier);
  y << YAML::Key << "mass_fraction" << YAML::Value << 1;
  y << YAML::EndMap << YAML::EndSeq;
  if (!tile_name.empty()) {
    y << YAML::Key << "pattern" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "file" << YAML::Value
      << tile_name << YAML::EndMap;
  } else if (!o.knit.empty()) {
    y << YAML::Key << "pattern" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "knit" << YAML::Value
      << o.knit << YAML::Key << "stitch_length_mm" << YAML::Value << format_shortest(*o.stitch_length_mm)
      << YAML::Key << "yarn_radius_mm" << YAML::Value << format_shortest(*o.yarn_radius_mm) << YAML::EndMap;
  }
  y << YAML::Key << "stretch_tests" << YAML::Value << YAML::BeginMap;
  for (const auto& [dir, file] : stretch_files) {
    const auto& tests = m.tests.at(dir);
    const FabTest* s2 = eight_cm_stretch(tests);
    y << YAML::Key << std::string(to_string(dir)) << YAML::Value << YAML::BeginMap;
    y << YAML::Key << "file" << YAML::Value << file;
    y << YAML::Key << "swatch" << YAML::Value;
    emit_size(y, s2->clamp_distance, s2->strip_width);
    y << YAML::EndMap;
  }
  y << YAML::EndMap;
  y << YAML::Key << "fab_tests" << YAML::Value << YAML::BeginMap;
  y << YAML::Key << "source" << YAML::Value << YAML::BeginMap;
  y << YAML::Key << "file" << YAML::Value << "fab/physics.json";
  if (m.serial) y << YAML::Key << "serial" << YAML::Value << *m.serial;
  if (m.hardware_version) y << YAML::Key << "hardware_version" << YAML::Value << *m.hardware_version;
  if (m.build) y << YAML::Key << "build" << YAML::Value << *m.build;
  y << YAML::EndMap;
  for (const auto& [dir, tests] : m.tests) {
    y << YAML::Key << std::string(to_string(dir)) << YAML::Value << YAML::BeginMap;
    for (const auto& t : tests) {
      y << YAML::Key << t.name << YAML::Value << YAML::Flow << YAML::BeginMap;
      y << YAML::Key << "file" << YAML::Value << "fab/" + std::string(to_string(dir)) + "_" + t.name + ".csv";
      y << YAML::Key << "clamp_distance_mm" << YAML::Value << format_shortest(t.clamp_distance / k_mm);
      y << YAML::Key << "strip_width_mm" << YAML::Value << format_shortest(t.strip_width / k_mm);
      if (t.zero_offset) y << YAML::Key << "zero_offset_N" << YAML::Value << format_shortest(*t.zero_offset);
      if (t.sampling_hz) y << YAML::Key << "sampling_hz" << YAML::Value << *t.sampling_hz;
      if (t.test_version) y << YAML::Key << "test_version" << YAML::Value << *t.test_version;
      if (t.time) y << YAML::Key << "time_utc" << YAML::Value << format_utc(*t.time);
      y << YAML::EndMap;
    }
    y << YAML::EndMap;
  }
  y << YAML::EndMap;
  y << YAML::EndMap;
  return "# A Browzwear FAB measurement imported by yarnfit db import-fab (docs/fab.md).\n" + std::string(y.c_str()) + "\n";
}

fs::path staging_folder(const fs::path& output) {
  std::random_device rd;
  const fs::path parent = output.parent_path().empty() ? fs::path(".") : output.parent_path();
  return parent / ("." + output.filename().string() + ".importing-" + std::to_string(rd()));
}

}  // namespace

Problems FabImportOptions::problems() const {
  Problems p;
  if (input.empty()) p.add_field("input", "no FAB file given");
  if (output.empty()) p.add_field("out", "no record folder given");
  if (!denier) p.add_field("denier", "required: the yarn's linear density (grams per 9,000 m); the FAB does not measure it");
  else if (!(*denier > 0.0 && std::isfinite(*denier))) p.add_field("denier", "must be a positive number");
  if (tile && !knit.empty()) p.add_field("tile", "give a tile or a knit, not both");
  if (!knit.empty() && (!stitch_length_mm || !yarn_radius_mm))
    p.add_field("knit", "needs --stitch-length-mm and --yarn-radius-mm");
  if (knit.empty() && (stitch_length_mm || yarn_radius_mm))
    p.add_field("stitch-length-mm", "only with --knit");
  if (stitch_length_mm && !(*stitch_length_mm > 0.0)) p.add_field("stitch-length-mm", "must be positive");
  if (yarn_radius_mm && !(*yarn_radius_mm > 0.0)) p.add_field("yarn-radius-mm", "must be positive");
  return p;
}

bool valid_record_id(const std::string& id) {
  return !id.empty() && std::all_of(id.begin(), id.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.';
  });
}

// Moves the staged folder into place unless something took the name meanwhile.
void rename_no_replace(const fs::path& from, const fs::path& to) {
  if (::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_NOREPLACE) != 0)
    throw Error(ErrorCategory::io, std::string("cannot move the record into place: ") + std::strerror(errno));
}

FabImportResult import_fab(const FabImportOptions& options) {
  FabImportResult r;
  FabImportOptions o = options;
  // "dir/new/" names the folder "new".
  o.output = o.output.lexically_normal();
  if (!o.output.empty() && !o.output.has_filename()) o.output = o.output.parent_path();
  r.problems = o.problems();
  std::error_code ec;
  if (!o.output.empty() && fs::exists(fs::symlink_status(o.output, ec)))
    r.problems.add(o.output.string(), 0, "out", "already exists: nothing is overwritten (choose a new folder)");
  if (!o.output.empty()) {
    const fs::path parent = o.output.parent_path().empty() ? fs::path(".") : o.output.parent_path();
    if (!fs::is_directory(parent, ec)) r.problems.add(parent.string(), 0, "out", "the folder to hold the record does not exist");
  }
  std::string tile_text;
  if (o.tile) {
    std::string why;
    if (!read_text_file(*o.tile, tile_text, why)) r.problems.add(o.tile->string(), 0, "tile", why);
  }
  if (!r.problems.empty() || o.input.empty()) return r;

  auto read = read_fab_file(o.input);
  r.problems.append(read.problems);
  if (!read.measurement) return r;
  const FabMeasurement& m = *read.measurement;

  // Each grain's 8 cm stretch as the curve the fit uses today.
  std::map<Direction, std::string> stretch_files;
  std::map<Direction, StretchCurve> curves;
  for (const auto& [dir, tests] : m.tests) {
    const FabTest* s2 = eight_cm_stretch(tests);
    if (!s2) continue;
    int dropped = 0;
    auto c = fab_stretch_curve(*s2, dropped);
    r.stretch_points_dropped += dropped;
    if (c.size() < k_min_curve_points) {
      r.problems.add(m.label, 0, std::string("/raw_data/") + fab_grain_letter(dir) + "/S2/samplesTree",
                     "no loading branch stretches the strip past its taut length (" +
                         format_g(s2->clamp_distance / k_mm) + " mm)");
      continue;
    }
    stretch_files[dir] = "stretch_" + std::string(to_string(dir)) + ".csv";
    curves[dir] = std::move(c);
  }
  if (!r.problems.empty()) return r;

  const std::string id = !o.id.empty() ? o.id : o.output.filename().string();
  if (!valid_record_id(id)) {
    r.problems.add_field("id", "'" + id + "' is not a record id (letters, digits, '-', '_' and '.'): " +
                                   (o.id.empty() ? "the folder's name is the default; give --id" : "choose another"));
    return r;
  }
  std::string family = !o.family.empty() ? o.family : lower_id(m.category);
  if (family.empty()) family = "fab";
  const std::string tile_name = o.tile ? "tile.pyp" : "";
  const fs::path stage = staging_folder(o.output);
  try {
    fs::create_directories(stage / "fab");
    write_text_file_atomically(stage / "fab" / "physics.json", m.physics_text);
    for (const auto& [dir, tests] : m.tests)
      for (const auto& t : tests)
        write_text_file_atomically(stage / "fab" / (std::string(to_string(dir)) + "_" + t.name + ".csv"), test_csv(t));
    for (const auto& [dir, file] : stretch_files) {
      const auto& tests = m.tests.at(dir);
      const FabTest* s2 = eight_cm_stretch(tests);
      write_text_file_atomically(stage / file, stretch_csv(curves.at(dir), *s2));
    }
    if (o.tile) write_text_file_atomically(stage / tile_name, tile_text);
    write_text_file_atomically(stage / k_fabric_file_name, record_yaml(o, m, id, family, stretch_files, tile_name));
    // The record must read back as it was meant; a problem here is the importer's, and the
    // user's options (an id the format refuses) are named as such.
    const auto back = load_fabric(stage);
    if (!back.ok()) {
      for (auto p : back.problems.items()) {
        p.file = (o.output / fs::path(p.file).lexically_relative(stage)).string();
        r.problems.add(p.file, p.line, p.field, p.message);
      }
      fs::remove_all(stage, ec);
      return r;
    }
    rename_no_replace(stage, o.output);
  } catch (const std::exception& e) {
    fs::remove_all(stage, ec);
    r.problems.add(o.output.string(), 0, "file", e.what());
    return r;
  }
  r.written = true;
  r.measurement = std::move(read.measurement);
  return r;
}

}  // namespace yarnfit::db
