#pragma once

#include <cstdint>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/planning/planning_grid.h"

namespace mobot::planning {

struct PathSmootherOptions {
  // A shortcut may only cross cells at or below this cost (and never inscribed or lethal ones).
  // With the default inflation (inscribed 0.3 m, scaling 10/m) cost 70 lies about 0.43 m from an
  // obstacle: the circumscribed radius of the 0.6 x 0.6 m footprint, so a shortcut does not swing
  // the footprint's corners into a wall where the A* path kept them clear.
  std::uint8_t max_shortcut_cost = 70;
  // After shortcutting, long segments are split so waypoints are at most this far apart (the
  // tracker's progress and the API's path stay fine-grained). 0 disables densification.
  double waypoint_spacing_m = 0.3;
};

// Turns a grid planner's staircase of cell centres into a short polyline that keeps clearance:
// line-of-sight shortcutting (string pulling) checked against the planning grid, then optional
// densification. The first and last points are kept exactly; an original step between neighbouring
// points is always kept, so a path the planner found through a tight doorway survives.
class PathSmoother {
 public:
  // Throws std::invalid_argument on a negative or non-finite spacing.
  explicit PathSmoother(const PathSmootherOptions& options = {});

  std::vector<geometry::Point2D> smooth(const PlanningGrid& grid,
                                        const std::vector<geometry::Point2D>& points) const;
  std::vector<geometry::Point2D> shortcut(const PlanningGrid& grid,
                                          const std::vector<geometry::Point2D>& points) const;
  static std::vector<geometry::Point2D> densify(const std::vector<geometry::Point2D>& points,
                                                double spacing_m);

 private:
  PathSmootherOptions options_;
};

}  // namespace mobot::planning
