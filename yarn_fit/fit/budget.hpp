#pragma once
// Named settings of the yarn fit's search (SPEC §5: `--budget quick|default|thorough`): how much
// of the global step and the local step a fit buys. The detailed options still override them
// (the command line applies a budget first, then every option given). What each costs and
// reaches is measured by bench_calibration and shown in the report's "What accuracy costs".

#include <optional>
#include <string_view>

#include "yarn_fit/fit/yarn_fit.hpp"

namespace yarnfit::yarn {

enum class Budget { quick, standard, thorough };
[[nodiscard]] const char* to_string(Budget budget);  // "quick", "default", "thorough"
[[nodiscard]] std::optional<Budget> budget_from_string(std::string_view name);

// Sets the search fields of `settings` (staged stages, starts, local samples and rounds; the
// thesis swarm's size when the global method is the swarm) to the budget's; leaves the rest.
void apply_budget(Budget budget, YarnFitSettings& settings);

}  // namespace yarnfit::yarn
