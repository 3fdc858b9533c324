#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/geometry/pose2d.h"

namespace mobot::navigation {

// docs/api.md's goal lifecycle: planning -> active -> succeeded | failed | canceled.
enum class GoalStatus { kPlanning, kActive, kSucceeded, kFailed, kCanceled };

std::string_view to_string(GoalStatus status);

// One navigation goal as the API reports it.
struct Goal {
  std::int64_t id = 0;
  GoalStatus status = GoalStatus::kPlanning;
  std::string reason;  // why it failed or was canceled (snake_case), empty otherwise
  geometry::Pose2D target;
  bool has_heading = false;  // without one the robot ends facing along the path's last segment
  std::string planner = "astar";
  std::string controller = "lyapunov";
  std::vector<geometry::Point2D> path;  // map frame, the smoothed plan being followed
  double created_s = 0.0;               // robot clock
  std::optional<double> ended_s;
  int replans = 0;

  bool finished() const {
    return status == GoalStatus::kSucceeded || status == GoalStatus::kFailed ||
           status == GoalStatus::kCanceled;
  }
};

}  // namespace mobot::navigation
