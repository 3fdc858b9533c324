#pragma once

#include <optional>
#include <vector>

#include "core/mapping/occupancy_grid.h"
#include "core/planning/planning_grid.h"

namespace mobot::planning {

// The way out for a robot whose centre lies in an inflated (inscribed) or unknown cell, or in a
// lethal one it was pushed into: a Dijkstra in a window around `start` through inscribed and
// unknown cells, and lethal ones only when the start itself is lethal, to the nearest traversable
// cell within max_distance_m. Returns the cells from the start to that cell, or nullopt. Every
// planner uses it, so all accept the same starts (astar_planner.h explains why they escape).
std::optional<std::vector<mapping::CellIndex>> escape_route(const PlanningGrid& grid,
                                                            mapping::CellIndex start,
                                                            double max_distance_m);

}  // namespace mobot::planning
