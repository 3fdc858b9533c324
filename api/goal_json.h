#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "core/geometry/pose2d.h"
#include "core/navigation/goal.h"

namespace mobot::api {

// docs/api.md's goal body: {"id","status","reason"?,"target","path":[[x,y],...],"created_t",
// "ended_t"?} plus the planner and controller it runs with.
nlohmann::json goal_json(const navigation::Goal& goal);
nlohmann::json path_json(const std::vector<geometry::Point2D>& path);

}  // namespace mobot::api
