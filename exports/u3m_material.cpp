#include "exports/u3m_material.hpp"

#include <archive.h>
#include <archive_entry.h>
#include <openssl/rand.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <map>
#include <memory>

#include "fabrics_db/text_util.hpp"
#include "numerics/util/error.hpp"

namespace yarnfit::exports {

namespace {

constexpr const char* k_physics_file = "physics/physics.json";

std::string uuid4() {
  std::array<unsigned char, 16> b{};
  if (RAND_bytes(b.data(), static_cast<int>(b.size())) != 1)
    throw Error(ErrorCategory::system, "OpenSSL RAND_bytes failed");
  b[6] = static_cast<unsigned char>((b[6] & 0x0f) | 0x40);  // version 4
  b[8] = static_cast<unsigned char>((b[8] & 0x3f) | 0x80);  // variant 10xx
  char s[37];
  std::snprintf(s, sizeof s, "%02x%02x%02x%02x-%02x%02x-%02x%02x-%02x%02x-%02x%02x%02x%02x%02x%02x", b[0], b[1], b[2], b[3],
                b[4], b[5], b[6], b[7], b[8], b[9], b[10], b[11], b[12], b[13], b[14], b[15]);
  return s;
}

std::string utc_now() {
  return db::format_utc(std::chrono::system_clock::to_time_t(std::chrono::system_clock::now()));
}

// Lower case without separators: "Single-Jersey" and "single_jersey" compare alike.
std::string folded(const std::string& name) {
  std::string out;
  for (const char c : name)
    if (std::isalnum(static_cast<unsigned char>(c))) out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// U3M's fibre names (its composition enum, those a knit's yarn is likely to be).
const std::array<const char*, 22> k_fibres{"Acetate", "Acrylic", "Alpaca",    "Angora",   "Cashmere", "Cotton",
                                           "Cupro",   "Elastane", "Hemp",     "Linen",    "Lycra",    "Lyocell",
                                           "Modal",   "Mohair",  "Nylon",     "Polyamid", "Polyester", "Ramie",
                                           "Rayon",   "Silk",    "Spandex",   "Wool"};

nlohmann::json composition(const db::Fabric& fabric) {
  if (fabric.yarns.empty()) return nullptr;
  nlohmann::json parts = nlohmann::json::array();
  for (const auto& y : fabric.yarns) {
    const auto it = std::find_if(k_fibres.begin(), k_fibres.end(), [&](const char* f) { return folded(f) == folded(y.material); });
    if (it != k_fibres.end()) parts.push_back({{"ratio", y.mass_fraction}, {"type", *it}, {"name", nullptr}});
    else parts.push_back({{"ratio", y.mass_fraction}, {"type", "other"}, {"name", y.material}});
  }
  return {{"parts", parts}};
}

// The knit's chart name, or the family's.
std::string knit_name(const db::Fabric& fabric) {
  if (fabric.pattern && fabric.pattern->knit) return fabric.pattern->knit->chart.name;
  return fabric.family;
}

nlohmann::json physics_fields(const FittedFabric& fabric) {
  nlohmann::json p = {{"thickness", nullptr},
                      {"weight", fabric.areal_density ? nlohmann::json(*fabric.areal_density * 1e3) : nlohmann::json(nullptr)},
                      {"composition", nullptr},
                      {"devices", {{"fab", k_physics_file}}},
                      {"material_type", {{"type", "Knit"}, {"name", nullptr}}},
                      {"construction", nullptr}};
  if (fabric.record_fabric) {
    p["composition"] = composition(*fabric.record_fabric);
    const std::string name = knit_name(*fabric.record_fabric);
    const std::string construction = u3m_construction(name);
    if (!construction.empty()) p["construction"] = {{"type", construction}, {"name", nullptr}};
    else if (!name.empty()) p["construction"] = {{"type", "other"}, {"name", name}};
  }
  return p;
}

// The units of the shell law's and the yarn model's parameters.
std::string unit_of(const std::string& name) {
  static const std::map<std::string, std::string> units{
      {"kxx", "N/m"}, {"kxy", "N/m"}, {"kyy", "N/m"}, {"kss", "N/m"}, {"kn1", "N/m"}, {"kn2", "N/m"},
      {"lxx", "N/m"}, {"lyy", "N/m"}, {"lss", "N/m"}, {"bxx", "-"},   {"byy", "-"},   {"bss", "-"},
      {"axx", "-"},   {"ayy", "-"},   {"ktheta_weft", "N m"}, {"ktheta_bias", "N m"}, {"ktheta_warp", "N m"},
      {"ks1", "N"},   {"eps_s", "-"}, {"kb", "N m^2"}, {"R1", "m"},  {"kc1", "N/m"}, {"ks2", "N"},
      {"kc2", "N/m"}, {"R2", "m"}};
  const auto it = units.find(name);
  return it == units.end() ? "" : it->second;
}

nlohmann::json with_units(const std::map<std::string, double>& values) {
  nlohmann::json out = nlohmann::json::object();
  for (const auto& [name, value] : values) out[name] = {{"value", value}, {"unit", unit_of(name)}};
  return out;
}

nlohmann::json yarnfit_block(const FittedFabric& fabric) {
  std::map<std::string, double> shell_values;
  for (const auto& [name, value] : fabric.shell.params)
    if (value) shell_values[name] = *value;
  nlohmann::json shell_errors = nlohmann::json::object();
  for (const auto& d : fabric.shell.directions) {
    const results::ShellDirectionErrors e = fabric.shell.direction_errors(d.direction);
    shell_errors[d.direction] = {{"force_pct", e.stretch_force_pct}, {"width_pct", e.compression_pct}, {"aspect_ratio_pct", e.bending_pct}};
  }
  nlohmann::json yarn = nullptr;
  if (fabric.yarn) {
    nlohmann::json errors = nlohmann::json::object();
    for (const auto& [direction, e] : fabric.yarn->errors_by_direction)
      errors[direction] = {{"stress_comfort_range_pct", e.stress_comfort_pct}, {"stress_full_range_pct", e.stress_full_pct},
                           {"width_pct", e.compression_pct}};
    yarn = {{"fitted", with_units(fabric.yarn->params)},
            {"errors_pct", errors},
            {"options", results::to_json(*fabric.yarn).at("settings")},
            {"about", "the yarn-level model (biphasic stretch, rod bending, two-barrier contact) fitted by periodic "
                      "simulation of the tile; SI units"}};
  }
  return {{"version", YARNFIT_VERSION},
          {"fabric", fabric.shell.fabric},
          {"family", fabric.shell.family},
          {"provenance",
           {{"record", fabric.record.empty() ? nlohmann::json(nullptr) : nlohmann::json(fabric.record)},
            {"record_sha256", fabric.record_sha256.empty() ? nlohmann::json(nullptr) : nlohmann::json(fabric.record_sha256)},
            {"fit_folder", fabric.folder.string()}}},
          {"shell_law",
           {{"model", fabric.shell.model},
            {"fitted", with_units(shell_values)},
            {"energy",
             "psi = 1/2 e^T K e + kn1 (J - 1)^2 + kn2 log^2 J (+ the lock-up terms of the stiffening model) per area, "
             "e the material-frame Green strain (weft, warp, 2 x shear), K = [[kxx, kxy, 0], [kxy, kyy, 0], [0, 0, kss]]; "
             "bending k_theta kappa^2 per area, k_theta interpolated between weft, bias and warp"},
            {"errors_pct", shell_errors}}},
          {"yarn", yarn}};
}

using ArchivePtr = std::unique_ptr<archive, decltype(&archive_write_free)>;
using EntryPtr = std::unique_ptr<archive_entry, decltype(&archive_entry_free)>;

la_ssize_t append_to(archive*, void* buffer, const void* data, size_t size) {
  static_cast<std::string*>(buffer)->append(static_cast<const char*>(data), size);
  return static_cast<la_ssize_t>(size);
}

void require_ok(archive* a, int status, const std::string& what) {
  if (status != ARCHIVE_OK) throw Error(ErrorCategory::io, "zip: " + what + ": " + archive_error_string(a));
}

// A fit made from a FAB record (issue 51) gives its measurement back: the record's physics
// file's raw_data unchanged, and the vendor's own custom entries beside yarnfit's, so that a
// U3M that went in comes out with its physics.
void keep_fab_measurement(const FittedFabric& fabric, nlohmann::json& physics) {
  if (!fabric.record_fabric || !fabric.record_fabric->fab_source || fabric.record_fabric->fab_source->file.empty())
    return;
  const auto& file = fabric.record_fabric->fab_source->file;
  std::string text, why;
  if (!db::read_text_file(file, text, why)) throw Error(ErrorCategory::input, file.string() + ": " + why);
  const auto source = nlohmann::json::parse(text, nullptr, false);
  if (source.is_discarded() || !source.is_object() || !source.contains("raw_data"))
    throw Error(ErrorCategory::input, file.string() + ": not the U3M physics file the record was imported from");
  physics["raw_data"] = source["raw_data"];
  if (const auto c = source.find("custom"); c != source.end() && c->is_object())
    for (const auto& [key, value] : c->items())
      if (key != "yarnfit") physics["custom"][key] = value;
}

}  // namespace

std::string u3m_construction(const std::string& knit_or_family) {
  static const std::map<std::string, std::string> names{
      {"stockinette", "Single jersey"}, {"singlejersey", "Single jersey"}, {"jersey", "Single jersey"},
      {"rib1x1", "1 x 1 rib"},          {"1x1rib", "1 x 1 rib"},          {"rib2x2", "2 x 2 rib"},
      {"2x2rib", "2 x 2 rib"},          {"rib4x2", "4 x 2 rib"},          {"interlock", "Interlock"},
      {"doubleknit", "Doubleknit"},     {"pique", "Pique"},               {"fleece", "Fleece"}};
  const auto it = names.find(folded(knit_or_family));
  return it == names.end() ? "" : it->second;
}

U3mMaterial u3m_material(const FittedFabric& fabric) {
  U3mMaterial u;
  u.name = fabric.shell.fabric;
  const std::string now = utc_now();
  u.material = {{"schema", "1.1"},
                {"material",
                 {{"id", uuid4()},
                  {"name", u.name},
                  {"description", "Fitted by yarnfit " YARNFIT_VERSION " from " + fabric.folder.string() +
                                      ": the physics are in physics/physics.json (custom.yarnfit)"},
                  {"created", now},
                  {"modified", now},
                  {"front", nullptr},
                  {"back", nullptr},
                  {"side", nullptr},
                  {"physics", physics_fields(fabric)},
                  {"metadata", nullptr}}},
                {"custom", nullptr}};
  u.physics = {{"schema", "1.1"}, {"raw_data", nullptr}, {"custom", {{"yarnfit", yarnfit_block(fabric)}}}};
  keep_fab_measurement(fabric, u.physics);
  return u;
}

std::vector<std::filesystem::path> write_u3m_folder(const U3mMaterial& u3m, const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir / "physics");
  const std::filesystem::path material = dir / (u3m.name + ".u3m"), physics = dir / k_physics_file;
  db::write_text_file_atomically(physics, u3m.physics.dump(2) + "\n");
  db::write_text_file_atomically(material, u3m.material.dump(2) + "\n");
  return {material, physics};
}

void write_u3ma(const U3mMaterial& u3m, const std::filesystem::path& file) {
  std::string zip;
  {
    ArchivePtr a(archive_write_new(), archive_write_free);
    require_ok(a.get(), archive_write_set_format_zip(a.get()), "format");
    require_ok(a.get(), archive_write_set_options(a.get(), "zip:compression=store,zip:hdrcharset=UTF-8"), "options");
    require_ok(a.get(), archive_write_set_bytes_in_last_block(a.get(), 1), "block size");  // nothing after the archive
    require_ok(a.get(), archive_write_open2(a.get(), &zip, nullptr, append_to, nullptr, nullptr), "open");
    const std::time_t now = std::time(nullptr);
    for (const auto& [name, text] : {std::pair{u3m.name + ".u3m", u3m.material.dump(2) + "\n"},
                                     std::pair{std::string(k_physics_file), u3m.physics.dump(2) + "\n"}}) {
      EntryPtr e(archive_entry_new(), archive_entry_free);
      archive_entry_set_pathname_utf8(e.get(), name.c_str());
      archive_entry_set_filetype(e.get(), AE_IFREG);
      archive_entry_set_perm(e.get(), 0644);
      archive_entry_set_size(e.get(), static_cast<la_int64_t>(text.size()));
      archive_entry_set_mtime(e.get(), now, 0);
      require_ok(a.get(), archive_write_header(a.get(), e.get()), name);
      if (archive_write_data(a.get(), text.data(), text.size()) != static_cast<la_ssize_t>(text.size()))
        throw Error(ErrorCategory::io, "zip: " + name + ": " + archive_error_string(a.get()));
    }
    require_ok(a.get(), archive_write_close(a.get()), "close");
  }
  db::write_text_file_atomically(file, zip);
}

}  // namespace yarnfit::exports
