#pragma once

#include <cstddef>
#include <optional>
#include <string_view>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/mapping/occupancy_grid.h"
#include "core/planning/planning_grid.h"

namespace mobot::planning {

// Why a plan failed. error_code() gives the docs/api.md snake_case code the API answers with
// (422 for the impossible goals, 400 for kInvalidPose, 409 for kNoMap).
enum class PlanError {
  kInvalidPose,      // "invalid_pose": NaN or infinite coordinates
  kNoMap,            // "no_map": the planning grid is empty
  kStartOutsideMap,  // "start_outside_map"
  kGoalOutsideMap,   // "goal_outside_map"
  kStartInObstacle,  // "start_in_obstacle": inside an obstacle with no free cell within reach
  kGoalInObstacle,   // "goal_in_obstacle": the goal cell is lethal, inscribed or unknown
  kNoPath,           // "no_path"
  kGoalInKeepout,    // "goal_in_keepout": the goal lies inside a keep-out zone
};

std::string_view error_code(PlanError error);

struct PlanResult {
  std::optional<PlanError> error;
  // Start cell to goal cell, 8-connected. When the start had to escape an inflated obstacle the
  // first cells are the escape route.
  std::vector<mapping::CellIndex> cells;
  // Cell centres in the map frame, except that the first is the exact start and the last the
  // exact goal position.
  std::vector<geometry::Point2D> points_in_map;
  double cost = 0.0;      // the search cost: metres weighted by (1 + cost penalty)
  double length_m = 0.0;  // along points_in_map
  bool start_escaped = false;
  std::size_t expanded_cells = 0;

  bool ok() const { return !error.has_value(); }
};

// A global planner in the Nav2 sense: one implementation per algorithm, chosen by name. plan()
// reads only its arguments (the grid is passed in rather than held, so a worker thread can plan on
// a snapshot); implementations may keep scratch buffers, so one instance is not for concurrent use.
class GlobalPlanner {
 public:
  virtual ~GlobalPlanner() = default;
  virtual std::string_view name() const = 0;
  // Whether a smoother may shorten the route. A planner whose route is its point (the passage
  // middles of the Voronoi roadmap) says no.
  virtual bool route_may_be_smoothed() const { return true; }
  // Headings of start and goal are ignored by grid planners; the tracker turns to the goal's.
  virtual PlanResult plan(const PlanningGrid& grid, const geometry::Pose2D& start,
                          const geometry::Pose2D& goal) = 0;
};

}  // namespace mobot::planning
