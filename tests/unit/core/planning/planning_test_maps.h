#pragma once

// Small occupancy maps drawn cell by cell for the planning tests, and their planning grids.

#include <cstdint>

#include "core/mapping/occupancy_grid.h"
#include "core/planning/planning_grid_builder.h"

namespace mobot::planning::test_maps {

inline constexpr double kRes = 0.05;

inline mapping::OccupancyGrid free_map(int width, int height) {
  return mapping::OccupancyGrid(width, height, kRes, {}, mapping::OccupancyGrid::kFree);
}

inline void fill(mapping::OccupancyGrid& map, int x0, int y0, int x1, int y1, std::uint8_t value) {
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) map.set({x, y}, value);
  }
}

// The map's outline as walls, one cell thick.
inline void outline(mapping::OccupancyGrid& map) {
  constexpr std::uint8_t kWall = mapping::OccupancyGrid::kOccupied;
  fill(map, 0, 0, map.width() - 1, 0, kWall);
  fill(map, 0, map.height() - 1, map.width() - 1, map.height() - 1, kWall);
  fill(map, 0, 0, 0, map.height() - 1, kWall);
  fill(map, map.width() - 1, 0, map.width() - 1, map.height() - 1, kWall);
}

// R1's defaults: inscribed radius 0.3 m (6 cells), inflated 0.25 m beyond.
inline PlanningGrid build(const mapping::OccupancyGrid& map) {
  return PlanningGridBuilder().build(map);
}

}  // namespace mobot::planning::test_maps
