#include "fabrics_db/records/fabric_summary.hpp"

#include <algorithm>

namespace yarnfit::db {

namespace {

using nlohmann::json;

json range_of(const std::vector<double>& v) {
  if (v.empty()) return nullptr;
  const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  return json::array({*lo, *hi});
}

json describe_swatch(const Swatch& s) { return {{"length_m", s.length}, {"width_m", s.width}}; }

json optional_number(const std::optional<double>& v) { return v ? json(*v) : json(nullptr); }

json describe_stretch_test(const StretchTest& t) {
  std::vector<double> line_force(t.curve.force);
  for (double& f : line_force) f /= t.swatch.width;
  json j{{"file", t.file.string()},
         {"points", t.curve.size()},
         {"swatch", describe_swatch(t.swatch)},
         {"stretch", range_of(t.curve.stretch)},
         {"force_N", range_of(t.curve.force)},
         {"line_force_N_per_m", range_of(line_force)},
         {"compression", range_of(t.curve.compression)},
         {"compression_measured", t.curve.has_compression()},
         {"comfort_stretch", optional_number(stretch_at_line_force(t, k_comfort_line_force))},
         {"power_stretch", optional_number(stretch_at_line_force(t, k_power_line_force))}};
  if (!t.gauge.empty()) {
    j["gauge"] = {{"length_m", optional_number(t.gauge.length)},
                  {"width_m", optional_number(t.gauge.width)}};
  }
  return j;
}

json describe_bending_test(const BendingTest& t) {
  return {{"file", t.file.string()},
          {"points", t.curve.size()},
          {"swatch", describe_swatch(t.swatch)},
          {"clamp_distance_m", range_of(t.curve.clamp_distance)},
          {"aspect_ratio", range_of(t.curve.aspect_ratio)}};
}

json describe_fab_test(const FabTest& t) {
  int cycles = 0;
  std::size_t samples = 0;
  double nearest = t.clamp_distance, farthest = t.clamp_distance;
  for (const auto& b : t.branches) {
    cycles = std::max(cycles, b.cycle);
    samples += b.clamp_distance.size();
    for (const double d : b.clamp_distance) {
      nearest = std::min(nearest, d);
      farthest = std::max(farthest, d);
    }
  }
  return {{"file", t.file.string()},
          {"kind", std::string(to_string(t.kind))},
          {"clamp_distance_m", t.clamp_distance},
          {"strip_width_m", t.strip_width},
          {"cycles", cycles},
          {"branches", t.branches.size()},
          {"samples", samples},
          {"travel_m", json::array({nearest, farthest})},
          {"zero_offset_N", optional_number(t.zero_offset)}};
}

}  // namespace

std::optional<double> stretch_at_line_force(const StretchTest& test, double line_force) {
  const auto& c = test.curve;
  for (std::size_t i = 0; i < c.size(); ++i) {
    const double f = test.line_force(i);
    if (f < line_force) continue;
    if (i == 0) return c.stretch[0];
    const double f0 = test.line_force(i - 1);
    const double t = (line_force - f0) / (f - f0);
    return c.stretch[i - 1] + t * (c.stretch[i] - c.stretch[i - 1]);
  }
  return std::nullopt;
}

json describe_tile(const PeriodicTile& tile, const TileFacts& facts) {
  json yarns = json::array();
  for (const auto& y : facts.yarns) {
    yarns.push_back({{"segments", y.edges.size()},
                     {"period_offset", json::array({y.offset_x, y.offset_y})},
                     {"length_m", y.length},
                     {"rest_length_m", y.rest_length}});
  }
  return {{"vertices", tile.vertex_count()},
          {"period_x_m", tile.period_x},
          {"period_y_m", tile.period_y},
          {"area_m2", facts.area},
          {"yarn_count", facts.yarns.size()},
          {"yarns", yarns},
          {"total_length_m", facts.total_length},
          {"total_rest_length_m", facts.total_rest_length},
          {"yarn_radius_m", facts.yarn_radius},
          {"mean_segment_length_m", facts.mean_segment_length},
          {"r_est_m", facts.r_est},
          {"r_est_over_radius", facts.yarn_radius > 0 ? facts.r_est / facts.yarn_radius : 0.0},
          {"min_contact_distance_m", facts.min_contact_distance}};
}

json describe_fabric(const Fabric& fabric) {
  json yarns = json::array();
  for (const auto& y : fabric.yarns) {
    yarns.push_back({{"material", y.material},
                     {"denier", y.denier},
                     {"filaments", y.filaments ? json(*y.filaments) : json(nullptr)},
                     {"mass_fraction", y.mass_fraction},
                     {"stiffness_N", optional_number(y.stiffness)},
                     {"linear_density_kg_per_m", y.linear_density()}});
  }
  json stretch = json::object();
  for (const auto& [dir, t] : fabric.stretch_tests) stretch[std::string(to_string(dir))] = describe_stretch_test(t);
  json bending = json::object();
  for (const auto& [dir, t] : fabric.bending_tests) bending[std::string(to_string(dir))] = describe_bending_test(t);

  json fab = json::object();
  for (const auto& [dir, tests] : fabric.fab_tests)
    for (const auto& t : tests) fab[std::string(to_string(dir))][t.name] = describe_fab_test(t);

  json j{{"id", fabric.id},
         {"family", fabric.family},
         {"description", fabric.description},
         {"folder", fabric.folder.string()},
         {"areal_density_kg_per_m2", optional_number(fabric.areal_density)},
         {"yarns", yarns},
         {"swatch", fabric.swatch ? describe_swatch(*fabric.swatch) : json(nullptr)},
         {"stretch_tests", stretch},
         {"bending_tests", bending},
         {"fab_tests", fab},
         {"ground_truth", fabric.ground_truth}};
  if (fabric.pattern && !fabric.pattern->has_tile() && fabric.pattern->knit) {
    const KnitSpec& k = *fabric.pattern->knit;
    j["pattern"] = json{{"knit", k.chart.name},
                        {"chart_rows", k.chart.text()},
                        {"stitch_length_mm", 1e3 * k.stitch_length},
                        {"yarn_radius_mm", 1e3 * k.yarn_radius},
                        {"generated", false},
                        {"weft_axis", fabric.pattern->weft_axis == Axis::x ? "x" : "y"}};
  } else if (fabric.pattern) {
    json p = describe_tile(fabric.pattern->tile, fabric.pattern->facts);
    p["file"] = fabric.pattern->file.string();
    p["weft_axis"] = fabric.pattern->weft_axis == Axis::x ? "x" : "y";
    j["pattern"] = p;
  } else {
    j["pattern"] = nullptr;
  }
  return j;
}

json list_entry(const FabricLoad& load) {
  json j{{"id", load.id},
         {"family", load.family},
         {"folder", load.folder.string()},
         {"valid", load.ok()},
         {"problems", load.problems.size()}};
  json stretch = json::array();
  json bending = json::array();
  if (load.fabric) {
    for (const auto& [dir, t] : load.fabric->stretch_tests) stretch.push_back(std::string(to_string(dir)));
    for (const auto& [dir, t] : load.fabric->bending_tests) bending.push_back(std::string(to_string(dir)));
  }
  j["stretch_tests"] = stretch;
  j["bending_tests"] = bending;
  j["pattern"] = load.fabric ? json(load.fabric->pattern.has_value()) : json(nullptr);
  return j;
}

}  // namespace yarnfit::db
