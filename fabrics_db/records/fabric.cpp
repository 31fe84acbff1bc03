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

std::optional<double> Fabric::stiffest_yarn_stiffness() const {
  std::optional<double> best;
  for (const auto& y : yarns) {
    if (y.stiffness && (!best || *y.stiffness > *best)) best = y.stiffness;
  }
  return best;
}

}  // namespace yarnfit::db
