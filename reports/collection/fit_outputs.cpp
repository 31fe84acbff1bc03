#include "reports/collection/fit_outputs.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace yarnfit::reports {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// The file's JSON, or null with a problem when it exists and cannot be parsed.
json read_json(const fs::path& file, std::vector<std::string>& problems) {
  if (!fs::exists(file)) return nullptr;
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  json j = json::parse(text.str(), nullptr, false);
  if (j.is_discarded() || !j.is_object()) {
    problems.push_back(file.string() + ": not a JSON object (left out of the report)");
    return nullptr;
  }
  return j;
}

std::string string_or(const json& j, const char* key, const std::string& fallback) {
  return j.is_object() && j.contains(key) && j[key].is_string() && !j[key].get<std::string>().empty()
             ? j[key].get<std::string>()
             : fallback;
}

}  // namespace

FabricOutputs read_fit_outputs(const fs::path& folder, std::vector<std::string>& problems) {
  FabricOutputs f;
  f.folder = folder;
  const std::size_t problems_before = problems.size();
  if (const fs::path file = folder / "shell_fit.json"; fs::exists(file)) {
    try {
      f.shell = results::read_shell_fit_file(file);
    } catch (const std::runtime_error& e) {
      problems.push_back(std::string(e.what()) + " (left out of the report)");
    }
  }
  f.yarn = read_json(folder / "yarn_fit.json", problems);
  const auto non_empty = [](const std::string& s, const std::string& fallback) { return s.empty() ? fallback : s; };
  f.id = non_empty(f.shell ? f.shell->fabric : "", string_or(f.yarn, "fabric", folder.filename().string()));
  f.family = non_empty(f.shell ? f.shell->family : "", string_or(f.yarn, "family", ""));
  if (f.shell && !f.shell->converged) {
    f.status = "failed";
    f.error = "shell fit did not converge: " + non_empty(f.shell->message, "no message");
  } else if (f.yarn.is_object() && !f.yarn.value("ok", false)) {
    f.status = "failed";
    f.error = "yarn fit failed: " + string_or(f.yarn, "message", "no message");
  } else if (!f.shell && f.yarn.is_null()) {
    f.status = "failed";
    f.error = problems.size() > problems_before ? problems.back()
                                                : "no shell_fit.json or yarn_fit.json in " + folder.string();
  }
  return f;
}

RunOutputs read_fit_folders(const fs::path& dir) {
  RunOutputs run;
  run.source = dir;
  run.label = fs::weakly_canonical(dir).filename().string();
  if (fs::exists(dir / "shell_fit.json") || fs::exists(dir / "yarn_fit.json")) {
    run.fabrics.push_back(read_fit_outputs(dir, run.problems));
    return run;
  }
  if (!fs::is_directory(dir)) throw std::invalid_argument(dir.string() + ": no such folder");
  std::vector<fs::path> folders;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_directory() && (fs::exists(e.path() / "shell_fit.json") || fs::exists(e.path() / "yarn_fit.json")))
      folders.push_back(e.path());
  if (folders.empty())
    throw std::invalid_argument(dir.string() +
                                ": neither a batch output (batch.db), nor a `yarnfit fit` output folder, nor a folder "
                                "of them (no shell_fit.json found)");
  std::sort(folders.begin(), folders.end());
  for (const auto& folder : folders) run.fabrics.push_back(read_fit_outputs(folder, run.problems));
  std::sort(run.fabrics.begin(), run.fabrics.end(),
            [](const FabricOutputs& a, const FabricOutputs& b) { return a.id < b.id; });
  return run;
}

}  // namespace yarnfit::reports
