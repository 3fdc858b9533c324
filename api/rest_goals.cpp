#include <algorithm>
#include <array>
#include <cmath>

#include "api/api_error.h"
#include "api/frame_codec.h"
#include "api/goal_json.h"
#include "api/json_request.h"
#include "api/rest_api.h"

namespace mobot::api {
namespace {

constexpr std::array<std::string_view, 2> kPlanners{"astar", "voronoi"};
constexpr std::array<std::string_view, 4> kControllers{"lyapunov", "pure_pursuit", "dwa",
                                                       "potential_field"};
// What this build runs; the others are in the contract but not implemented yet.
constexpr std::array<std::string_view, 2> kAvailablePlanners{"astar", "voronoi"};
constexpr std::array<std::string_view, 1> kAvailableControllers{"lyapunov"};

template <std::size_t N, std::size_t M>
std::string choose(const nlohmann::json& body, const char* key, std::string_view fallback,
                   const std::array<std::string_view, N>& allowed,
                   const std::array<std::string_view, M>& available) {
  if (!body.contains(key)) return std::string(fallback);
  const std::string value = require_string(body, key, 32);
  if (std::find(allowed.begin(), allowed.end(), value) == allowed.end()) {
    std::string list;
    for (const auto name : allowed) list += (list.empty() ? "" : ", ") + std::string(name);
    throw ApiError(400, "invalid_field", "'" + std::string(key) + "' must be one of " + list);
  }
  if (std::find(available.begin(), available.end(), value) == available.end()) {
    throw ApiError(422, "unsupported_" + std::string(key),
                   "the " + std::string(key) + " '" + value + "' is not available in this build");
  }
  return value;
}

GoalRequest parse_goal(const nlohmann::json& body) {
  GoalRequest request;
  request.has_heading = body.contains("theta") && !body["theta"].is_null();
  request.target = parse_pose(body, false);
  request.planner = choose(body, "planner", "astar", kPlanners, kAvailablePlanners);
  request.controller = choose(body, "controller", "lyapunov", kControllers, kAvailableControllers);
  return request;
}

std::array<double, 9> parse_covariance(const nlohmann::json& body) {
  // A rough initial pose by default: 0.25 m and 0.1 rad standard deviation.
  std::array<double, 9> cov{0.0625, 0, 0, 0, 0.0625, 0, 0, 0, 0.01};
  if (!body.contains("cov")) return cov;
  const auto& values = body["cov"];
  if (!values.is_array() || values.size() != 9) {
    throw ApiError(400, "invalid_field", "'cov' must be 9 numbers (row-major 3x3)");
  }
  for (std::size_t i = 0; i < 9; ++i) {
    if (!values[i].is_number() || !std::isfinite(values[i].get<double>())) {
      throw ApiError(400, "invalid_field", "'cov' must hold finite numbers");
    }
    cov[i] = values[i].get<double>();
  }
  for (std::size_t i = 0; i < 3; ++i) {
    if (cov[i * 4] < 0.0) throw ApiError(400, "invalid_field", "'cov' has a negative variance");
    for (std::size_t j = 0; j < 3; ++j) {
      if (std::abs(cov[i * 3 + j] - cov[j * 3 + i]) > 1e-9) {
        throw ApiError(400, "invalid_field", "'cov' must be symmetric");
      }
    }
  }
  return cov;
}

[[noreturn]] void unknown_goal() { throw ApiError(404, "unknown_goal", "no goal with this id"); }

}  // namespace

Response RestApi::route_goals(const Request& request, const Segments& path) {
  const auto method = request.method();
  if (path.size() == 3) {
    if (method == http::verb::get) {
      require_role(request, Role::kViewer);
      nlohmann::json goals = nlohmann::json::array();
      for (const auto& goal : port_.list_goals()) goals.push_back(goal_json(goal));
      return json_response(request, http::status::ok, goals);
    }
    if (method == http::verb::post) {
      require_role(request, Role::kOperator);
      const GoalRequest goal_request = parse_goal(parse_json_body(request.body()));
      return json_response(request, http::status::created,
                           goal_json(port_.submit_goal(goal_request)));
    }
    throw ApiError(405, "method_not_allowed", "use GET or POST on /api/v1/goals");
  }
  if (path.size() != 4) throw ApiError(404, "not_found", "no such endpoint");
  const auto id = parse_id(path[3]);
  if (method == http::verb::get) {
    require_role(request, Role::kViewer);
    if (!id) unknown_goal();
    const auto goal = port_.find_goal(*id);
    if (!goal) unknown_goal();
    return json_response(request, http::status::ok, goal_json(*goal));
  }
  if (method == http::verb::delete_) {
    require_role(request, Role::kOperator);
    if (!id) unknown_goal();
    const auto before = port_.find_goal(*id);
    if (!before) unknown_goal();
    if (before->finished()) {
      throw ApiError(409, "goal_finished",
                     "the goal has already ended (" +
                         std::string(navigation::to_string(before->status)) + ")");
    }
    return json_response(request, http::status::ok, goal_json(port_.cancel_goal(*id)));
  }
  throw ApiError(405, "method_not_allowed", "use GET or DELETE on a goal");
}

Response RestApi::route_localization(const Request& request, const Segments& path) {
  if (path.size() != 4 || path[3] != "pose") throw ApiError(404, "not_found", "no such endpoint");
  if (request.method() != http::verb::post) {
    throw ApiError(405, "method_not_allowed", "use POST to set the pose");
  }
  require_role(request, Role::kOperator);
  const nlohmann::json body = parse_json_body(request.body());
  const geometry::Pose2D pose = parse_pose(body, true);
  const std::array<double, 9> cov = parse_covariance(body);
  port_.set_localization_pose(pose, cov);
  return json_response(request, http::status::ok, {{"pose", pose_json(pose)}, {"cov", cov}});
}

}  // namespace mobot::api
