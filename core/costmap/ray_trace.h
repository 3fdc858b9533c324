#pragma once

#include <cstdlib>
#include <optional>

#include "core/geometry/pose2d.h"
#include "core/mapping/occupancy_grid.h"
#include "core/planning/planning_grid.h"

namespace mobot::costmap {

struct CellSegment {
  mapping::CellIndex from;
  mapping::CellIndex to;
};

// The part of the map-frame segment from -> to that lies on the grid, as the cells holding its
// clipped ends (Liang-Barsky against the grid's rectangle); nullopt when none of it does or a point
// is not finite. A sensor outside the window still clears the part of its ray inside it.
std::optional<CellSegment> clip_to_grid(const planning::PlanningGrid& grid,
                                        geometry::Point2D from_map, geometry::Point2D to_map);

// costmap_2d's raytraceLine: calls visit(cell) for each cell of the Bresenham line from `from` to
// `to`, both included, stepping along the major axis (so |dx| + 1 or |dy| + 1 cells).
template <class Visit>
void trace_cells(mapping::CellIndex from, mapping::CellIndex to, Visit&& visit) {
  const int dx = to.x - from.x;
  const int dy = to.y - from.y;
  const int step_x = dx >= 0 ? 1 : -1;
  const int step_y = dy >= 0 ? 1 : -1;
  const int abs_dx = std::abs(dx);
  const int abs_dy = std::abs(dy);
  mapping::CellIndex cell = from;
  if (abs_dx >= abs_dy) {
    int error = abs_dx / 2;
    for (int i = 0; i < abs_dx; ++i) {
      visit(cell);
      cell.x += step_x;
      error += abs_dy;
      if (error >= abs_dx) {
        cell.y += step_y;
        error -= abs_dx;
      }
    }
  } else {
    int error = abs_dy / 2;
    for (int i = 0; i < abs_dy; ++i) {
      visit(cell);
      cell.y += step_y;
      error += abs_dx;
      if (error >= abs_dy) {
        cell.x += step_x;
        error -= abs_dy;
      }
    }
  }
  visit(cell);
}

}  // namespace mobot::costmap
