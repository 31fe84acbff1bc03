#include "cli/option_names.hpp"

#include <algorithm>
#include <map>
#include <set>
#include <vector>

#include "cli/request_options.hpp"
#include "pipeline/fit_request_fields.hpp"

namespace yarnfit::cli {

namespace {

// Each request field's name, and the library's names of the settings it sets, to its option
// (pipeline/fit_request_fields.hpp).
std::map<std::string, std::string> request_options() {
  std::map<std::string, std::string> out;
  pipeline::FitRequest request;
  pipeline::for_each_request_field(request, [&out](const pipeline::RequestField& f, const auto&) {
    out[f.name] = first_option_name(f.option);
    for (const char* name : f.settings_names) out[name] = first_option_name(f.option);
  });
  return out;
}

}  // namespace

std::string option_name(const std::string& field) {
  // The options that set no field of a fit request.
  static const std::map<std::string, std::string> others{
      {"threads", "--threads"},
      {"resume", "--resume"},
      {"jobs", "--jobs"},
      {"threads_per_job", "--threads-per-job"},
      {"only", "--only"},
      {"out", "--out"},
      {"database", "DB"},
      {"targets", "--targets"},
      {"bend_mesh", "--bend-mesh"},
      {"stretches", "--weft/--bias/--warp"},
  };
  static const std::map<std::string, std::string> requested = request_options();
  std::string bare = field;
  if (bare.rfind("fit.", 0) == 0) bare = bare.substr(4);  // batch::BatchOptions::fit
  for (const char* prefix : {"shell.", "yarn."})
    if (bare.rfind(prefix, 0) == 0) bare = bare.substr(std::string(prefix).size());
  // The fields of the simulator commands' requests (pipeline/tools/) whose option is their
  // name with dashes: "stitch_length_mm" is --stitch-length-mm.
  static const std::set<std::string> plain{
      "chart", "weave", "stitch_length_mm", "yarn_spacing_mm", "yarn_radius_mm", "weft_crimp_share", "gauge", "aspect",
      "ks2", "directions", "bending", "stress_tolerance", "compression_method", "stretch", "compression",
      "free_compression", "curvature", "dump", "max_stretch", "points", "dump_dir", "distance", "direction", "length_mm",
      "width_mm", "gauge_length_mm", "gauge_width_mm", "areal_density_gsm", "ktheta_weft", "ktheta_bias", "ktheta_warp",
      "kxx", "kxy", "kyy", "kss", "kn1", "kn2", "lxx", "bxx", "lyy", "byy", "lss", "bss", "axx", "ayy"};
  if (const auto it = requested.find(bare); it != requested.end()) return it->second;
  if (const auto it = others.find(bare); it != others.end()) return it->second;
  if (!plain.contains(bare)) return field;
  std::string option = "--" + bare;
  std::replace(option.begin(), option.end(), '_', '-');
  return option;
}

db::Problems as_options(const db::Problems& problems) {
  db::Problems out;
  std::vector<std::string> seen;
  for (const auto& p : problems.items()) {
    db::Problem q = p;
    if (q.file.empty()) q.field = option_name(q.field);
    const std::string text = q.to_string();
    if (std::find(seen.begin(), seen.end(), text) != seen.end()) continue;
    seen.push_back(text);
    out.add(q.file, q.line, q.field, q.message);
  }
  return out;
}

}  // namespace yarnfit::cli
