#include "cli/option_names.hpp"

#include <algorithm>
#include <map>
#include <vector>

namespace yarnfit::cli {

std::string option_name(const std::string& field) {
  static const std::map<std::string, std::string> options{
      {"mesh", "--mesh"},
      {"refinements", "--refine"},
      {"threads", "--threads"},
      {"max_iterations", "--max-iterations"},
      {"particles", "--particles"},
      {"iterations", "--iterations"},
      {"swarm_samples", "--samples"},
      {"local_samples", "--local-samples"},
      {"local_evaluations", "--local-evaluations"},
      {"objective.compression_weight", "--compression-weight"},
      {"compression_weight", "--compression-weight"},
      {"swarm_compression_nodes", "--compression-nodes"},
      {"local_compression_nodes", "--compression-nodes"},
      {"resume", "--resume"},
      {"jobs", "--jobs"},
      {"threads_per_job", "--threads-per-job"},
      {"only", "--only"},
      {"out", "--out"},
      {"database", "DB"},
      {"stages", "--stages"},
      {"shell_model", "--shell-model"},
      {"fab_held_out", "--fab-held-out"},
      {"budget", "--budget"},
      {"global_method", "--global"},
      {"local_method", "--local"},
      {"targets", "--targets"},
  };
  std::string bare = field;
  if (bare.rfind("fit.", 0) == 0) bare = bare.substr(4);  // batch::BatchOptions::fit
  for (const char* prefix : {"shell.", "yarn."})
    if (bare.rfind(prefix, 0) == 0) bare = bare.substr(std::string(prefix).size());
  const auto it = options.find(bare);
  return it == options.end() ? field : it->second;
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
