#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/costmap/inflation_layer.h"
#include "core/geometry/pose2d.h"
#include "core/mapping/occupancy_grid.h"
#include "core/planning/planning_grid.h"

namespace mobot::planning {

struct PlanningGridOptions {
  // R1: a 0.6 x 0.6 m footprint has an inscribed radius of 0.3 m. Cells closer than this to an
  // obstacle are kInscribed: the robot's centre there means a collision.
  double inscribed_radius_m = 0.3;
  // P3: the cost decays over this band beyond the inscribed radius (costmap_2d's inflation radius
  // is inscribed_radius_m + inflation_margin_m), so planned paths keep clearance where they can.
  double inflation_margin_m = 0.25;
  // P3: costmap_2d's cost_scaling_factor, per metre.
  double cost_scaling_per_m = 10.0;
  // Unknown space blocks and is inflated like an obstacle (the robot does not drive where it has
  // never seen). When false, unknown cells plan like free space.
  bool unknown_is_obstacle = true;
  // An occupancy value (0..100) at or above this is an obstacle (ROS map_server's 0.65).
  std::uint8_t occupied_threshold = mapping::OccupancyGrid::kOccupiedThreshold;
};

// Extra obstacle sources merged into the lethal layer before inflation, e.g. the 2D projection of
// 3D obstacles (IPaBD, P2) or sonar hits. The grids may have any resolution and origin: an
// occupied cell marks every planning cell whose centre it covers, and the cell under its own
// centre (so a finer grid is never lost).
struct ExtraObstacles {
  std::span<const mapping::OccupancyGrid> grids;
  std::span<const geometry::Point2D> points_in_map;
  // Keep-out zones (simple polygons, map frame): lethal, and inflated like walls, so the robot's
  // body stays out of them, not only its centre.
  std::span<const std::vector<geometry::Point2D>> keepout_zones;
};

// Builds the costmap-like grid A* searches from an occupancy grid: a global costmap of the map's
// geometry with three of the costmap layers (docs/algorithms.md P3), run once: the static layer
// (obstacles kLethal, unknown kUnknown or free), the extra obstacles as in the obstacle-grid layer,
// and the inflation layer (exact Euclidean distance, costmap_2d's kInscribed or decaying cost).
class PlanningGridBuilder {
 public:
  // Throws std::invalid_argument on negative or non-finite options.
  explicit PlanningGridBuilder(const PlanningGridOptions& options = {});

  const PlanningGridOptions& options() const { return options_; }

  // An empty occupancy grid gives an empty planning grid (planners then answer kNoMap).
  PlanningGrid build(const mapping::OccupancyGrid& occupancy,
                     const ExtraObstacles& extra = {}) const;

  // costmap_2d's inflation cost for a cell at `distance_m` from the nearest obstacle.
  std::uint8_t cost_at_distance(double distance_m) const {
    return inflation_.cost_at_distance(distance_m);
  }

 private:
  PlanningGridOptions options_;
  costmap::InflationLayer inflation_;
};

}  // namespace mobot::planning
