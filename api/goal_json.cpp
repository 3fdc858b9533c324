#include "api/goal_json.h"

namespace mobot::api {

nlohmann::json path_json(const std::vector<geometry::Point2D>& path) {
  nlohmann::json points = nlohmann::json::array();
  for (const auto& point : path) points.push_back({point.x, point.y});
  return points;
}

nlohmann::json goal_json(const navigation::Goal& goal) {
  nlohmann::json target{{"x", goal.target.x}, {"y", goal.target.y}};
  if (goal.has_heading) target["theta"] = goal.target.theta;
  nlohmann::json out{{"id", goal.id},
                     {"status", navigation::to_string(goal.status)},
                     {"target", target},
                     {"planner", goal.planner},
                     {"controller", goal.controller},
                     {"path", path_json(goal.path)},
                     {"replans", goal.replans},
                     {"created_t", goal.created_s}};
  if (!goal.reason.empty()) out["reason"] = goal.reason;
  if (goal.ended_s) out["ended_t"] = *goal.ended_s;
  return out;
}

}  // namespace mobot::api
