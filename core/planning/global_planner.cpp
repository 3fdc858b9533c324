#include "core/planning/global_planner.h"

namespace mobot::planning {

std::string_view error_code(PlanError error) {
  switch (error) {
    case PlanError::kInvalidPose:
      return "invalid_pose";
    case PlanError::kNoMap:
      return "no_map";
    case PlanError::kStartOutsideMap:
      return "start_outside_map";
    case PlanError::kGoalOutsideMap:
      return "goal_outside_map";
    case PlanError::kStartInObstacle:
      return "start_in_obstacle";
    case PlanError::kGoalInObstacle:
      return "goal_in_obstacle";
    case PlanError::kNoPath:
      return "no_path";
    case PlanError::kGoalInKeepout:
      return "goal_in_keepout";
  }
  return "no_path";
}

}  // namespace mobot::planning
