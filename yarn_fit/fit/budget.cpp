#include "yarn_fit/fit/budget.hpp"

namespace yarnfit::yarn {

const char* to_string(Budget budget) {
  switch (budget) {
    case Budget::quick: return "quick";
    case Budget::standard: return "default";
    case Budget::thorough: return "thorough";
  }
  return "unknown";
}

std::optional<Budget> budget_from_string(std::string_view name) {
  for (const Budget b : {Budget::quick, Budget::standard, Budget::thorough})
    if (name == to_string(b)) return b;
  return std::nullopt;
}

namespace {

// What a budget sets: the search's size, nothing of the physics.
struct BudgetPreset {
  SwarmStageSettings contact;
  SwarmStageSettings all;
  int rescored = 0;
  int starts = 0;
  int local_samples = 0;
  int max_rounds = 0;
  int particles = 0;  // the thesis's swarm (global_method swarm)
  int iterations = 0;
};

BudgetPreset preset(Budget budget) {
  switch (budget) {
    case Budget::quick: return {{6, 3, 3, 8}, {10, 3, 3, 8}, 2, 1, 8, 5, 32, 5};
    case Budget::thorough: return {{16, 6, 4, 40}, {32, 8, 5, 40}, 8, 4, 20, 12, 128, 20};
    case Budget::standard: break;
  }
  const YarnFitSettings d;  // the defaults
  return {d.staged.contact, d.staged.all,         d.staged.rescored, d.staged.starts,
          d.local_samples,  d.alternation.max_rounds, d.particles,   d.iterations};
}

}  // namespace

void apply_budget(Budget budget, YarnFitSettings& s) {
  const BudgetPreset p = preset(budget);
  s.staged.contact = p.contact;
  s.staged.all = p.all;
  s.staged.rescored = p.rescored;
  s.staged.starts = p.starts;
  s.local_samples = p.local_samples;
  s.alternation.max_rounds = p.max_rounds;
  s.particles = p.particles;
  s.iterations = p.iterations;
}

}  // namespace yarnfit::yarn
