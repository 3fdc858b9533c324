#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "core/costmap/costmap_layer.h"
#include "core/geometry/pose2d.h"
#include "core/msgs/laser_scan.h"
#include "core/planning/planning_grid.h"

namespace mobot::costmap {

struct ObstacleLayerOptions {
  std::string name = "obstacle";
  // costmap_2d's obstacle_range: returns farther than this mark nothing (they still clear). The
  // Dashgo's local costmap uses 2.5 m; a global costmap fed by the laser, about 8 m (the range
  // gmapping trusts, docs/algorithms.md E5).
  double obstacle_range_m = 2.5;
  // costmap_2d's raytrace_range: each beam clears the cells it crossed up to this far.
  double raytrace_range_m = 3.0;
  // A beam without a return (range at or beyond range_max, or infinite) clears up to
  // min(range_max, raytrace_range_m): costmap_2d's inf_is_valid. False: such beams are ignored.
  bool clear_on_no_return = true;
  // The heights the laser sees (costmap_2d's min/max_obstacle_height); metadata.
  HeightBand height_band{0.0, 2.0};
};

// costmap_2d's obstacle layer for a planar laser: its own grid in master cells (kUnknown = never
// observed, kFree = a beam crossed it, kLethal = a return), kept across updates and shifted with a
// rolling window, so an obstacle stays marked after the laser stops seeing it until a beam crosses
// its cell. Each update ray-traces the queued scans first (Bresenham from the sensor's cell) and
// then marks their returns, so one beam's clearing never erases another's return of the same
// update. Written into the master by max.
class ObstacleLayer : public CostmapLayer {
 public:
  // Throws std::invalid_argument on negative or non-finite ranges.
  explicit ObstacleLayer(const ObstacleLayerOptions& options = {});

  std::string_view name() const override { return options_.name; }
  HeightBand height_band() const override { return options_.height_band; }
  const ObstacleLayerOptions& options() const { return options_; }

  // Queues a scan (ranges in the sensor frame) taken with the sensor at `sensor_in_map`; used at
  // the next update. NaN ranges and ranges below range_min are skipped. Returns false, and queues
  // nothing, for a non-finite pose or a scan whose angles are not finite.
  bool add_scan(const msgs::LaserScan& scan, const geometry::Pose2D& sensor_in_map);
  // Forgets every observation (queued or folded in).
  void clear();
  // The layer's own grid (master geometry; empty before the costmap gave it one).
  const planning::PlanningGrid& observed() const { return grid_; }

  void match_geometry(const planning::PlanningGrid& master) override;
  void shift(const planning::PlanningGrid& master, int dx_cells, int dy_cells) override;
  void update_bounds(const planning::PlanningGrid& master, CellBounds& bounds) override;
  void update(planning::PlanningGrid& master, const CellBounds& bounds) override;

 private:
  struct Observation {
    geometry::Point2D origin_in_map;
    std::vector<geometry::Point2D> clear_to_in_map;  // one per beam that clears
    std::vector<geometry::Point2D> hits_in_map;      // returns within obstacle_range_m
  };

  ObstacleLayerOptions options_;
  planning::PlanningGrid grid_;
  std::vector<Observation> pending_;
  bool cleared_ = false;  // clear() was called: the whole grid changed
};

}  // namespace mobot::costmap
