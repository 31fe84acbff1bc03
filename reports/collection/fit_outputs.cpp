#include "reports/collection/fit_outputs.hpp"

#include <algorithm>
#include <stdexcept>

#include "numerics/util/error.hpp"
#include "results/read_if_present.hpp"

namespace yarnfit::reports {

namespace fs = std::filesystem;

namespace {

// The file as its type, when it exists; a problem line when it cannot be read.
template <class File, class Read>
std::optional<File> read_result(const fs::path& file, Read read, std::vector<std::string>& problems) {
  std::string why;
  auto out = results::read_if_present<File>(file, read, &why);
  if (!why.empty()) problems.push_back(why + " (left out of the report)");
  return out;
}

}  // namespace

FabricOutputs read_fit_outputs(const fs::path& folder, std::vector<std::string>& problems) {
  FabricOutputs f;
  f.folder = folder;
  const std::size_t problems_before = problems.size();
  f.shell = read_result<results::ShellFitFile>(folder / "shell_fit.json", results::read_shell_fit_file, problems);
  f.yarn = read_result<results::YarnFitFile>(folder / "yarn_fit.json", results::read_yarn_fit_file, problems);
  if (f.yarn && fs::exists(folder / "tile.pyp")) {
    db::Problems tile_problems;
    f.tile = db::read_pyp(folder / "tile.pyp", tile_problems);
    for (const auto& p : tile_problems.items()) problems.push_back(p.to_string() + " (the tile is not drawn)");
  }
  std::error_code ec;
  for (fs::recursive_directory_iterator e(folder / "exports", ec), end; !ec && e != end; e.increment(ec))
    if (e->is_regular_file()) f.exports.push_back(e->path());
  std::sort(f.exports.begin(), f.exports.end());
  const auto non_empty = [](const std::string& s, const std::string& fallback) { return s.empty() ? fallback : s; };
  f.id = non_empty(f.shell ? f.shell->fabric : "", non_empty(f.yarn ? f.yarn->fabric : "", folder.filename().string()));
  f.family = non_empty(f.shell ? f.shell->family : "", f.yarn ? f.yarn->family : "");
  if (f.shell && !f.shell->converged) {
    f.status = "failed";
    f.error = "shell fit did not converge: " + non_empty(f.shell->message, "no message");
  } else if (f.yarn && !f.yarn->ok) {
    f.status = "failed";
    f.error = "yarn fit failed: " + non_empty(f.yarn->message, "no message");
  } else if (!f.shell && !f.yarn) {
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
  if (!fs::is_directory(dir)) throw Error(ErrorCategory::input, dir.string() + ": no such folder");
  std::vector<fs::path> folders;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_directory() && (fs::exists(e.path() / "shell_fit.json") || fs::exists(e.path() / "yarn_fit.json")))
      folders.push_back(e.path());
  if (folders.empty())
    throw Error(ErrorCategory::input, dir.string() +
                                ": neither a batch output (batch.db), nor a `yarnfit fit` output folder, nor a folder "
                                "of them (no shell_fit.json found)");
  std::sort(folders.begin(), folders.end());
  for (const auto& folder : folders) run.fabrics.push_back(read_fit_outputs(folder, run.problems));
  std::sort(run.fabrics.begin(), run.fabrics.end(),
            [](const FabricOutputs& a, const FabricOutputs& b) { return a.id < b.id; });
  return run;
}

}  // namespace yarnfit::reports
