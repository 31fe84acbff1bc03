#include "reports/summaries/fabric_text.hpp"

#include <algorithm>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <utility>
#include <vector>

#include "fabrics_db/fab/fab_physics.hpp"
#include "fabrics_db/text_util.hpp"

namespace yarnfit::reports {
namespace {

using nlohmann::json;
using yarnfit::db::format_g;

std::string g(const json& v, int digits = 4, double scale = 1.0) {
  if (v.is_null()) return "-";
  return format_g(v.get<double>() * scale, digits);
}

std::string span_text(const json& r, int digits = 4, double scale = 1.0) {
  if (r.is_null()) return "-";
  return g(r[0], digits, scale) + " to " + g(r[1], digits, scale);
}

std::string size_mm(const json& s) {
  if (s.is_null()) return "-";
  return g(s["length_m"], 4, 1e3) + " x " + g(s["width_m"], 4, 1e3) + " mm";
}

// JSON objects sort their keys; tests are shown weft, bias, warp as engineers read them.
std::vector<std::pair<std::string, json>> in_direction_order(const json& by_direction) {
  std::vector<std::pair<std::string, json>> out;
  for (const char* d : {"weft", "bias", "warp"}) {
    if (by_direction.contains(d)) out.emplace_back(d, by_direction[d]);
  }
  return out;
}

void print_tile(std::ostream& out, const json& p) {
  out << "  pattern: " << p["file"].get<std::string>() << " (weft along "
      << p["weft_axis"].get<std::string>() << ")\n";
  out << "    period " << g(p["period_x_m"], 4, 1e3) << " x " << g(p["period_y_m"], 4, 1e3)
      << " mm, area " << g(p["area_m2"], 4, 1e6) << " mm², " << p["vertices"].get<int>()
      << " vertices\n";
  out << "    " << p["yarn_count"].get<std::size_t>() << " periodic yarn"
      << (p["yarn_count"].get<std::size_t>() == 1 ? "" : "s") << ":";
  for (const auto& y : p["yarns"]) {
    out << " [" << y["segments"].get<int>() << " segments, offset (" << y["period_offset"][0].get<int>()
        << "," << y["period_offset"][1].get<int>() << "), " << g(y["length_m"], 4, 1e3) << " mm]";
  }
  out << "\n";
  out << "    yarn length " << g(p["total_length_m"], 5, 1e3) << " mm (rest lengths sum to "
      << g(p["total_rest_length_m"], 5, 1e3) << " mm), mean segment "
      << g(p["mean_segment_length_m"], 3, 1e3) << " mm\n";
  out << "    yarn radius " << g(p["yarn_radius_m"], 4, 1e3) << " mm, R_est "
      << g(p["r_est_m"], 4, 1e3) << " mm (" << g(p["r_est_over_radius"], 3)
      << " radii), closest contact distance " << g(p["min_contact_distance_m"], 3, 1e3) << " mm\n";
}

// A name from a stranger's file, with control characters shown as '?' (no terminal escapes).
std::string printable(std::string text) {
  for (char& c : text)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  return text;
}

}  // namespace

void print_fabric(std::ostream& out, const json& f) {
  out << "fabric " << f["id"].get<std::string>() << " (family " << f["family"].get<std::string>()
      << ")\n";
  if (!f["description"].get<std::string>().empty())
    out << "  " << f["description"].get<std::string>() << "\n";
  out << "  folder: " << f["folder"].get<std::string>() << "\n";
  out << "  areal density: "
      << (f["areal_density_kg_per_m2"].is_null() ? "not given"
                                                  : g(f["areal_density_kg_per_m2"], 4, 1e3) + " g/m²")
      << "\n";
  out << "  yarns:\n";
  for (const auto& y : f["yarns"]) {
    out << "    " << std::left << std::setw(12) << y["material"].get<std::string>() << std::right
        << g(y["denier"]) << " den";
    if (!y["filaments"].is_null()) out << ", " << y["filaments"].get<int>() << " filaments";
    out << ", " << g(y["mass_fraction"], 3, 100.0) << " % of mass, "
        << g(y["linear_density_kg_per_m"], 4, 1e6) << " mg/m, stiffness "
        << (y["stiffness_N"].is_null() ? "not given" : g(y["stiffness_N"]) + " N") << "\n";
  }
  out << "  swatch: " << (f["swatch"].is_null() ? "given per test" : size_mm(f["swatch"])) << "\n";
  out << "  stretch tests:\n";
  for (const auto& [dir, t] : in_direction_order(f["stretch_tests"])) {
    out << "    " << std::left << std::setw(5) << dir << std::right << " " << t["points"].get<int>()
        << " points from " << t["file"].get<std::string>() << "\n";
    out << "          stretch " << span_text(t["stretch"]) << ", force " << span_text(t["force_N"])
        << " N (up to " << g(t["line_force_N_per_m"][1]) << " N/m), compression "
        << (t["compression_measured"].get<bool>() ? span_text(t["compression"]) : "not measured") << "\n";
    out << "          swatch " << size_mm(t["swatch"]);
    if (t.contains("gauge")) {
      const auto& gg = t["gauge"];
      out << ", gauge marks " << (gg["length_m"].is_null() ? "clamps" : g(gg["length_m"], 4, 1e3) + " mm")
          << " along, " << (gg["width_m"].is_null() ? "edges" : g(gg["width_m"], 4, 1e3) + " mm")
          << " across";
    }
    out << "\n          comfort range (33.3 N/m) up to s = "
        << (t["comfort_stretch"].is_null() ? "beyond the data" : g(t["comfort_stretch"], 3))
        << ", power range (83.3 N/m) up to s = "
        << (t["power_stretch"].is_null() ? "beyond the data" : g(t["power_stretch"], 3)) << "\n";
  }
  out << "  bending tests:" << (f["bending_tests"].empty() ? " none" : "") << "\n";
  for (const auto& [dir, t] : in_direction_order(f["bending_tests"])) {
    out << "    " << std::left << std::setw(5) << dir << std::right << " " << t["points"].get<int>()
        << " points, clamp distance " << span_text(t["clamp_distance_m"], 4, 1e3)
        << " mm, aspect ratio " << span_text(t["aspect_ratio"]) << "\n";
  }
  if (f.contains("fab_tests") && !f["fab_tests"].empty()) {
    out << "  FAB tests (every cycle and branch; docs/fab.md):\n";
    for (const auto& [dir, tests] : in_direction_order(f["fab_tests"])) {
      out << "    " << std::left << std::setw(5) << dir << std::right;
      for (const char* name : {"S1", "S2", "U1", "D1", "D2"}) {
        if (!tests.contains(name)) continue;
        const auto& t = tests[name];
        out << " " << name << " " << g(t["clamp_distance_m"], 4, 1e3) << " mm ("
            << t["cycles"].get<int>() << " cycles" << (t["zero_offset_N"].is_null() ? "" : ", zero " + g(t["zero_offset_N"], 3) + " N")
            << ")";
      }
      out << "\n";
    }
  }
  if (f["pattern"].is_null()) {
    out << "  pattern: none (needed for a yarn fit)\n";
  } else if (f["pattern"].contains("knit")) {
    const auto& k = f["pattern"];
    out << "  pattern: " << k["knit"].get<std::string>() << " (" << k["chart_rows"].get<std::string>()
        << "), stitch length " << db::format_g(k["stitch_length_mm"].get<double>()) << " mm, yarn radius "
        << db::format_g(k["yarn_radius_mm"].get<double>()) << " mm: generated when a yarn fit needs it\n";
  } else {
    print_tile(out, f["pattern"]);
  }
  if (!f["ground_truth"].empty()) out << "  ground truth: " << f["ground_truth"].dump() << "\n";
}

void print_fabric_table(std::ostream& out, const json& entries) {
  std::size_t w_id = 2, w_family = 6;
  for (const auto& e : entries) {
    w_id = std::max(w_id, e["id"].get<std::string>().size());
    w_family = std::max(w_family, e["family"].get<std::string>().size());
  }
  auto dirs = [](const json& list) {
    std::string s;
    for (const auto& d : list) s += (s.empty() ? "" : ",") + d.get<std::string>();
    return s.empty() ? std::string("-") : s;
  };
  out << std::left << std::setw(static_cast<int>(w_id)) << "id" << "  "
      << std::setw(static_cast<int>(w_family)) << "family" << "  " << std::setw(16) << "stretch"
      << std::setw(16) << "bending" << std::setw(8) << "pattern" << "status\n";
  for (const auto& e : entries) {
    out << std::setw(static_cast<int>(w_id)) << (e["id"].get<std::string>().empty() ? "?" : e["id"].get<std::string>())
        << "  " << std::setw(static_cast<int>(w_family)) << e["family"].get<std::string>() << "  "
        << std::setw(16) << dirs(e["stretch_tests"]) << std::setw(16) << dirs(e["bending_tests"])
        << std::setw(8) << (e["pattern"].is_null() ? "?" : (e["pattern"].get<bool>() ? "yes" : "no"))
        << (e["valid"].get<bool>() ? std::string("valid")
                                   : "invalid (" + std::to_string(e["problems"].get<int>()) + " problems)")
        << "\n";
  }
  out << std::right << entries.size() << " fabric" << (entries.size() == 1 ? "" : "s") << "\n";
}

std::string tensile_import_text(const db::TensileImportResult& r, const std::string& output) {
  std::ostringstream out;
  out << "wrote " << output << ": " << r.rows_written << " rows";
  if (r.rows_dropped > 0) out << " (" << r.rows_dropped << " dropped outside the loading branch)";
  out << ", stretch " << db::format_g(r.curve.stretch.front(), 4) << " to "
      << db::format_g(r.curve.stretch.back(), 4) << ", force up to "
      << db::format_g(*std::max_element(r.curve.force.begin(), r.curve.force.end()), 4)
      << " N" << (r.curve.has_compression() ? ", with compression" : ", no compression")
      << "\n";
  return out.str();
}

std::string fab_import_text(const db::FabImportResult& r, const std::string& output) {
  std::ostringstream out;
  const auto& m = *r.measurement;
  std::size_t tests = 0, branches = 0;
  for (const auto& [d, ts] : m.tests) {
    tests += ts.size();
    for (const auto& t : ts) branches += t.branches.size();
  }
  out << "wrote " << output << ": " << tests << " FAB tests (" << branches
      << " branches) from " << m.label << (m.name.empty() ? "" : " (" + printable(m.name) + ")") << "\n"
      << "  mass per area " << db::format_g(m.mass_per_area * 1e3, 4) << " g/m², thickness "
      << (m.thickness ? db::format_g(*m.thickness * 1e3, 3) + " mm" : "not given") << "\n";
  for (const auto& [d, ts] : m.tests) {
    out << "  " << db::to_string(d) << " (" << db::fab_grain_letter(d) << "):";
    for (const auto& t : ts)
      out << " " << t.name << " " << db::format_g(t.clamp_distance * 1e3, 4) << " mm"
          << (t.zero_offset ? ", zero " + db::format_g(*t.zero_offset / db::k_gram_force, 3) + " gf" : "") << ";";
    out << "\n";
  }
  out << "  stretch_tests: each grain's S2, the mean of its loading branches"
      << (r.stretch_points_dropped > 0
              ? " (" + std::to_string(r.stretch_points_dropped) + " samples left out: not advancing or below zero)"
              : "")
      << "\n";
  return out.str();
}

}  // namespace yarnfit::reports
