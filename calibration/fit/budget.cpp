#include "calibration/fit/budget.hpp"

namespace yarnfit::calibration {

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

void apply_budget(Budget budget, YarnFitSettings& s) {
  switch (budget) {
    case Budget::quick:
      s.staged.contact = {6, 3, 3, 8};
      s.staged.all = {10, 3, 3, 8};
      s.staged.rescored = 2;
      s.staged.starts = 1;
      s.local_samples = 8;
      s.alternation.max_rounds = 5;
      s.particles = 32;
      s.iterations = 5;
      break;
    case Budget::standard: {
      const YarnFitSettings defaults;
      s.staged = defaults.staged;
      s.local_samples = defaults.local_samples;
      s.alternation = defaults.alternation;
      s.particles = defaults.particles;
      s.iterations = defaults.iterations;
      break;
    }
    case Budget::thorough:
      s.staged.contact = {16, 6, 4, 40};
      s.staged.all = {32, 8, 5, 40};
      s.staged.rescored = 8;
      s.staged.starts = 4;
      s.local_samples = 20;
      s.alternation.max_rounds = 12;
      s.particles = 128;
      s.iterations = 20;
      break;
  }
}

}  // namespace yarnfit::calibration
