#include "core/control/path_progress.h"

#include <cmath>

#include "core/control/stop_and_rotate.h"

namespace mobot::control {

bool PathProgress::start(const planning::Path& path, std::optional<double> goal_heading_rad) {
  if (path.empty() || !path.all_finite()) return false;
  if (goal_heading_rad && !std::isfinite(*goal_heading_rad)) return false;
  path_ = path;
  const double heading = goal_heading_rad.value_or(path.heading_at(path.length_m()));
  goal_ = {path.back().x, path.back().y, geometry::wrap_angle(heading)};
  status_ = {};
  status_.state = TrackerState::kTracking;
  status_.remaining_m = path.length_m();
  return true;
}

void PathProgress::clear() {
  path_ = {};
  status_ = {};
}

bool PathProgress::update(const geometry::Pose2D& pose, double goal_tolerance_m,
                          double projection_window_m) {
  if (status_.state == TrackerState::kIdle || status_.state == TrackerState::kArrived) return false;
  if (!geometry::is_finite(pose)) return false;
  status_.progress_m = path_.project({pose.x, pose.y}, status_.progress_m, projection_window_m);
  status_.remaining_m = path_.length_m() - status_.progress_m;
  status_.distance_to_goal_m = std::hypot(goal_.x - pose.x, goal_.y - pose.y);
  status_.heading_error_rad = geometry::wrap_angle(pose.theta - goal_.theta);
  if (status_.state == TrackerState::kTracking && status_.distance_to_goal_m <= goal_tolerance_m) {
    status_.state = TrackerState::kFinalApproach;
  }
  return true;
}

msgs::Twist PathProgress::final_approach(const DynamicLimits& limits, const msgs::Twist& measured,
                                         double goal_tolerance_rad) {
  const StopAndRotate out =
      stop_and_rotate(limits, measured, status_.heading_error_rad, goal_tolerance_rad);
  if (out.arrived) {
    status_.state = TrackerState::kArrived;
    return {};
  }
  return out.command;
}

}  // namespace mobot::control
