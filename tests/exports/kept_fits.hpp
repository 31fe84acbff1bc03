#pragma once
// The kept fits the export tests read (tests/exports/data): the bundled example's
// (stockinette_demo, shell and yarn stages) and a stiffening-law fit of the acrylic 1x1 rib
// (shell stage), as fit folders in a scratch folder.

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/test_support.hpp"

namespace yarnfit::exports::testing {

inline const std::filesystem::path k_data = std::filesystem::path(YARNFIT_SOURCE_DIR) / "tests/exports/data";

// A fit folder `dir/name` holding the kept shell_fit.json `name` (and its yarn_fit.json when
// `with_yarn`); "<name>_thesis" is the same fabric's fit with eq. 6.1 alone (the thesis-model
// fit a stiffening fit starts from, which its file keeps).
inline std::filesystem::path fit_folder(const yarnfit::testing::ScratchDir& dir, const std::string& name,
                                        bool with_yarn = false) {
  namespace fs = std::filesystem;
  const fs::path folder = dir / name;
  fs::create_directories(folder);
  const std::string suffix = "_thesis";
  if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
    nlohmann::json file = nlohmann::json::parse(
        yarnfit::testing::read_file(k_data / (name.substr(0, name.size() - suffix.size()) + "_shell_fit.json")));
    nlohmann::json params = file["thesis_model_fit"]["params"];
    for (const char* k : {"ktheta_weft", "ktheta_bias", "ktheta_warp"}) params[k] = file["params"][k];
    file["params"] = params;
    file["model"] = "thesis";
    yarnfit::testing::write_file(folder / "shell_fit.json", file.dump());
  } else {
    fs::copy_file(k_data / (name + "_shell_fit.json"), folder / "shell_fit.json");
  }
  if (with_yarn) fs::copy_file(k_data / (name + "_yarn_fit.json"), folder / "yarn_fit.json");
  return folder;
}

}  // namespace yarnfit::exports::testing
