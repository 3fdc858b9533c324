#pragma once

#include <memory>
#include <span>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/msgs/laser_scan.h"
#include "core/msgs/sonar_ring.h"
#include "core/planning/planning_grid.h"

namespace mobot::perception {

struct UnmappedObstaclesOptions {
  // A return within this many cells of a lethal cell of the map is that wall.
  int map_match_cells = 2;
  // Arc samples across a sonar cone: the echo may come from anywhere in it, not only its axis.
  int cone_samples = 5;
  // Echoes of the short-range ring (IR) stay obstacles this long after they were seen: a table
  // top only the IR ring sees drops out of its narrow cones as soon as the robot turns away, and
  // the replan must still go round it (docs/algorithms.md C6).
  double range_echo_hold_s = 10.0;
  // An echo counts when the same sensor reported this many in a row, each within
  // range_echo_agreement_m of the one before: a Sharp ranger's odd high sample (a spike of up to
  // 0.3 V in 1 % of the readings) reads a phantom 0.5-0.8 m out about once a second on a ten-sensor
  // ring at 20 Hz, and held for range_echo_hold_s those phantoms wall in the goal the robot stands
  // next to. A real obstacle echoes on consecutive readings.
  int range_echo_confirmations = 2;
  double range_echo_agreement_m = 0.1;
};

// What the range sensors see that the map does not explain (dropped obstacles, people): the
// laser's returns away from the map's walls, which planning adds as obstacles, and the sonar
// echoes on the path being followed, which the potential field reacts to. A costmap layer in all
// but its output: it keeps points, not cells, because planning re-inflates them per plan.
class UnmappedObstacles {
 public:
  explicit UnmappedObstacles(UnmappedObstaclesOptions options = {});

  // The inflated active map the returns are compared with; null: everything is explained.
  void set_map(std::shared_ptr<const planning::PlanningGrid> map) { map_ = std::move(map); }

  // Keeps the scan's returns the map does not explain, in the map frame (replacing the last).
  void observe_scan(const msgs::LaserScan& scan, const geometry::Pose2D& sensor_in_map);
  // Keeps the confirmed echoes of a ring of short-range sensors (IR) the map does not explain,
  // each until range_echo_hold_s after it was seen. The ring's readings in the same sensor order
  // every call; a ring of another size starts the confirmation over.
  void observe_ranges(std::span<const msgs::RangeReading> ring, const geometry::Pose2D& base_in_map,
                      double now_s);
  // The laser's unexplained returns and the held range echoes, map frame.
  const std::vector<geometry::Point2D>& points() const { return points_; }
  // Whether a kept return lies within `within_m` of the polyline `path`.
  bool blocks(const std::vector<geometry::Point2D>& path, double within_m) const;

  // The ring with every echo the potential field should ignore set to its maximum range: walls
  // of the map, and what lies farther than `within_m` from `path` (the planner keeps clear of it).
  std::vector<msgs::RangeReading> echoes_on_path(const msgs::SonarRing& ring,
                                                 const geometry::Pose2D& base_in_map,
                                                 const std::vector<geometry::Point2D>& path,
                                                 double within_m) const;

  bool explained_by_map(const geometry::Point2D& point_in_map) const;

 private:
  bool echo_is_wall(const msgs::RangeReading& reading, const geometry::Pose2D& sensor) const;

  UnmappedObstaclesOptions options_;
  std::shared_ptr<const planning::PlanningGrid> map_;
  void merge_points();

  std::vector<geometry::Point2D> scan_points_;
  struct HeldEcho {
    geometry::Point2D point;
    double seen_s = 0.0;
  };
  std::vector<HeldEcho> range_echoes_;
  // Per sensor of the ring: the last reading's range and how many agreeing echoes in a row.
  struct EchoRun {
    double range_m = 0.0;
    int count = 0;
  };
  std::vector<EchoRun> echo_runs_;
  std::vector<geometry::Point2D> points_;
};

}  // namespace mobot::perception
