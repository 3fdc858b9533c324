#pragma once

#include <algorithm>
#include <array>
#include <cstdlib>
#include <numbers>

#include "core/mapping/occupancy_grid.h"

namespace mobot::planning {

// One move of an 8-connected grid search.
struct GridStep {
  int dx;
  int dy;
  double length_cells;
};

// The order is fixed, because searches record a cell's step as its index here: the four straight
// steps, then the four diagonals.
inline constexpr std::array<GridStep, 8> kGridSteps{{{1, 0, 1.0},
                                                     {-1, 0, 1.0},
                                                     {0, 1, 1.0},
                                                     {0, -1, 1.0},
                                                     {1, 1, std::numbers::sqrt2},
                                                     {1, -1, std::numbers::sqrt2},
                                                     {-1, 1, std::numbers::sqrt2},
                                                     {-1, -1, std::numbers::sqrt2}}};

// The octile distance: the length of the shortest 8-connected path on an empty grid.
inline double octile_cells(mapping::CellIndex a, mapping::CellIndex b) {
  const int dx = std::abs(a.x - b.x);
  const int dy = std::abs(a.y - b.y);
  return std::max(dx, dy) + (std::numbers::sqrt2 - 1.0) * std::min(dx, dy);
}

}  // namespace mobot::planning
