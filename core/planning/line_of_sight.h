#pragma once

#include <cstdint>
#include <optional>

#include "core/geometry/pose2d.h"
#include "core/planning/planning_grid.h"

namespace mobot::planning {

// The highest cost among all cells the segment a-b touches (a supercover walk: where the segment
// passes exactly through a cell corner both side cells count), or nullopt when the segment leaves
// the grid or an end is not finite.
std::optional<std::uint8_t> max_cost_along_segment(const PlanningGrid& grid, geometry::Point2D a,
                                                   geometry::Point2D b);

// True when every cell the segment touches is traversable and at most `max_cost`.
bool segment_is_clear(const PlanningGrid& grid, geometry::Point2D a, geometry::Point2D b,
                      std::uint8_t max_cost);

}  // namespace mobot::planning
