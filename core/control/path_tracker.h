#pragma once

#include <memory>
#include <optional>
#include <string_view>

#include "core/geometry/pose2d.h"
#include "core/msgs/twist.h"
#include "core/planning/path.h"
#include "core/planning/planning_grid.h"

namespace mobot::control {

enum class TrackerState {
  kIdle,           // no path
  kTracking,       // following the path toward the goal
  kFinalApproach,  // stabilising to the goal pose
  kArrived,        // within tolerance and (nearly) stopped; commands are zero until a new path
};

struct TrackerStatus {
  TrackerState state = TrackerState::kIdle;
  double progress_m = 0.0;   // arc length of the robot's projection onto the path
  double remaining_m = 0.0;  // path length still ahead of that projection
  double distance_to_goal_m = 0.0;
  double heading_error_rad = 0.0;  // robot heading minus goal heading, wrapped
};

// A path-following controller in the Nav2 sense: one implementation per algorithm, chosen by name
// (docs/api.md's "controller" field). compute() runs once per control tick (50 Hz in the server)
// with the localised pose in the map frame and the measured body velocity; it must be cheap and
// never block.
class PathTracker {
 public:
  virtual ~PathTracker() = default;
  virtual std::string_view name() const = 0;

  // Starts following `path` (map frame) to its last point. goal_heading_rad is the requested final
  // heading; without one the robot ends facing along the path's last segment. Returns false, and
  // keeps the previous path, when the path is empty or not finite.
  virtual bool set_path(const planning::Path& path, std::optional<double> goal_heading_rad) = 0;
  virtual void clear() = 0;
  // now_s is the robot clock; static feedback laws ignore it, laws with memory need it.
  virtual msgs::Twist compute(const geometry::Pose2D& pose, const msgs::Twist& velocity,
                              double now_s) = 0;
  virtual TrackerStatus status() const = 0;
  // The rolling local costmap (map frame) as of this tick, given before compute(); trackers that
  // steer around obstacles (DWA, VFH) read it, the others ignore it.
  virtual void set_local_costmap(std::shared_ptr<const planning::PlanningGrid> /*costmap*/) {}

  bool arrived() const { return status().state == TrackerState::kArrived; }
};

}  // namespace mobot::control
