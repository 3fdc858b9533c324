#pragma once

#include <optional>
#include <variant>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/mapping/occupancy_grid.h"
#include "core/planning/global_planner.h"
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

// Where a grid search runs between, after the checks every planner makes.
struct SearchEnds {
  mapping::CellIndex start;  // the robot's cell, or where its escape ends
  mapping::CellIndex goal;
  // The escape's cells from the robot's cell up to (not including) `start`; empty when the robot's
  // cell is traversable. escape_cost_m is their length.
  std::vector<mapping::CellIndex> escape;
  double escape_cost_m = 0.0;
};

// The error codes of global_planner.h in the order a planner checks them: non-finite poses, an
// empty grid, start or goal outside, a goal the robot does not fit at, a start that cannot
// escape within max_escape_distance_m.
std::variant<PlanError, SearchEnds> search_ends(const PlanningGrid& grid,
                                                const geometry::Pose2D& start,
                                                const geometry::Pose2D& goal,
                                                double max_escape_distance_m);

// The cell path's points in the map frame with the first replaced by the exact start and the
// last by the exact goal (a one-cell path gets the goal appended).
std::vector<geometry::Point2D> path_points(const PlanningGrid& grid,
                                           const std::vector<mapping::CellIndex>& cells,
                                           const geometry::Pose2D& start,
                                           const geometry::Pose2D& goal);

double polyline_length_m(const std::vector<geometry::Point2D>& points);

// What every grid planner does around its own search: search_ends' checks and start escape, then
// search(from, to, result), which appends its cells to result.cells (the escape's cells are there
// already) and sets result.cost, returning false when the goal is unreachable (kNoPath). On
// success the result holds every cell, the total cost with the escape, path_points and length_m.
template <class Search>
PlanResult plan_on_grid(const PlanningGrid& grid, const geometry::Pose2D& start,
                        const geometry::Pose2D& goal, double max_escape_distance_m,
                        Search&& search) {
  PlanResult result;
  const auto ends = search_ends(grid, start, goal, max_escape_distance_m);
  if (const auto* error = std::get_if<PlanError>(&ends)) {
    result.error = *error;
    return result;
  }
  const SearchEnds& cells = std::get<SearchEnds>(ends);
  result.start_escaped = !cells.escape.empty();
  result.cells = cells.escape;
  if (!search(cells.start, cells.goal, result)) {
    result.error = PlanError::kNoPath;
    result.cells.clear();
    return result;
  }
  result.cost += cells.escape_cost_m;
  result.points_in_map = path_points(grid, result.cells, start, goal);
  result.length_m = polyline_length_m(result.points_in_map);
  return result;
}

}  // namespace mobot::planning
