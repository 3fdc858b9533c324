#pragma once

#include <optional>

#include "core/control/dynamic_window.h"
#include "core/control/path_tracker.h"
#include "core/geometry/pose2d.h"
#include "core/msgs/twist.h"
#include "core/planning/path.h"

namespace mobot::control {

// What a local planner following a global path (DWA, VFH) keeps between ticks: the path, the goal
// pose, the tracker status, and base_local_planner's latched final approach: once within the
// position tolerance the robot stops and turns to the goal heading (stop_and_rotate), and stays in
// that phase even if it drifts out again.
class PathProgress {
 public:
  // False, and nothing changed, for an empty or non-finite path or a non-finite heading.
  bool start(const planning::Path& path, std::optional<double> goal_heading_rad);
  void clear();

  // Projects `pose` onto the path (within projection_window_m of the last projection) and updates
  // the distances; latches the final approach within goal_tolerance_m of the goal. False when
  // there is nothing to follow (no path, arrived) or the pose is not finite: the command is zero.
  bool update(const geometry::Pose2D& pose, double goal_tolerance_m, double projection_window_m);
  bool tracking() const { return status_.state == TrackerState::kTracking; }
  // The final approach's command; arriving ends the goal (state kArrived).
  msgs::Twist final_approach(const DynamicLimits& limits, const msgs::Twist& measured,
                             double goal_tolerance_rad);

  const planning::Path& path() const { return path_; }
  const geometry::Pose2D& goal() const { return goal_; }
  const TrackerStatus& status() const { return status_; }

 private:
  planning::Path path_;
  geometry::Pose2D goal_;
  TrackerStatus status_;
};

}  // namespace mobot::control
