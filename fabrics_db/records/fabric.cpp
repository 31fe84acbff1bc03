#include "fabrics_db/records/fabric.hpp"

#include <algorithm>
#include <numbers>

namespace yarnfit::db {

std::string_view to_string(Direction d) {
  switch (d) {
    case Direction::weft: return "weft";
    case Direction::bias: return "bias";
    case Direction::warp: return "warp";
  }
  return "?";
}

std::optional<Direction> parse_direction(std::string_view name) {
  for (Direction d : k_all_directions) {
    if (to_string(d) == name) return d;
  }
  return std::nullopt;
}

double pull_angle(Direction d) {
  switch (d) {
    case Direction::weft: return 0.0;
    case Direction::bias: return std::numbers::pi / 4.0;
    case Direction::warp: return std::numbers::pi / 2.0;
  }
  return 0.0;
}

std::string_view to_string(FabTestKind kind) {
  switch (kind) {
    case FabTestKind::stretch: return "stretch";
    case FabTestKind::up_bend: return "up bend";
    case FabTestKind::down_bend: return "down bend";
  }
  return "?";
}

std::string_view to_string(FabBranch branch) { return branch == FabBranch::loading ? "loading" : "relaxation"; }

std::optional<FabBranch> parse_fab_branch(std::string_view name) {
  if (name == "loading") return FabBranch::loading;
  if (name == "relaxation") return FabBranch::relaxation;
  return std::nullopt;
}

const FabTestName* find_fab_test(std::string_view name) {
  for (const auto& t : k_fab_tests)
    if (name == t.name) return &t;
  return nullptr;
}

std::optional<double> Fabric::stiffest_yarn_stiffness() const {
  std::optional<double> best;
  for (const auto& y : yarns) {
    if (y.stiffness && (!best || *y.stiffness > *best)) best = y.stiffness;
  }
  return best;
}

}  // namespace yarnfit::db
