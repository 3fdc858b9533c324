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

// The contract's words for planners and controllers. A name the runtime's registry does not know
// is refused as unsupported when the contract has it (a build without that algorithm), and as an
// invalid field otherwise.
constexpr std::array<std::string_view, 2> kContractPlanners{"astar", "voronoi"};
constexpr std::array<std::string_view, 5> kContractControllers{"lyapunov", "pure_pursuit", "dwa",
                                                               "potential_field", "vfh"};

std::string join(const std::vector<std::string>& names) {
  std::string list;
  for (const auto& name : names) list += (list.empty() ? "" : ", ") + name;
  return list;
}

template <std::size_t N>
std::string choose(const nlohmann::json& body, const std::string& key, std::string_view fallback,
                   const std::array<std::string_view, N>& contract,
                   const std::vector<std::string>& known) {
  if (!body.contains(key)) return std::string(fallback);
  const std::string value = require_string(body, key.c_str(), 32);
  if (std::find(known.begin(), known.end(), value) != known.end()) return value;
  if (std::find(contract.begin(), contract.end(), value) != contract.end()) {
    throw DomainException(ErrorKind::kImpossible, "unsupported_" + key,
                          "the " + key + " '" + value + "' is not available in this build");
  }
  throw ApiError(400, "invalid_field", "'" + key + "' must be one of " + join(known));
}

GoalRequest parse_goal(const nlohmann::json& body, const ControlPort& control) {
  GoalRequest request;
  request.has_heading = body.contains("theta") && !body["theta"].is_null();
  request.target = parse_pose(body, false);
  request.planner =
      choose(body, "planner", control.default_planner(), kContractPlanners, control.planner_names());
  request.controller =
      choose(body, "controller", control.default_controller(), kContractControllers,
             control.controller_names());
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

Handled RestApi::route_goals(const Request& request, const Segments& path, const Replier& reply) {
  const auto method = request.method();
  if (path.size() == 4) return route_goal(request, path[3], reply);
  if (path.size() != 3) throw ApiError(404, "not_found", "no such endpoint");
  if (method == http::verb::get) {
    require_role(request, Role::kViewer);
    nlohmann::json goals = nlohmann::json::array();
    for (const auto& goal : ports_.control.list_goals()) goals.push_back(goal_json(goal));
    return json_response(request, http::status::ok, goals);
  }
  if (method == http::verb::post) {
    require_role(request, Role::kOperator);
    return submit_goal(request, reply);
  }
  throw ApiError(405, "method_not_allowed", "use GET or POST on /api/v1/goals");
}

Handled RestApi::submit_goal(const Request& request, const Replier& reply) {
  const GoalRequest goal_request = parse_goal(parse_json_body(request.body()), ports_.control);
  const OperatorLock::Change lock = require_driver(request, reply);
  ports_.control.submit_goal(
      goal_request,
      undo_if_refused(lock, reply.completion<navigation::Goal>([](const Request& head,
                                                                  const navigation::Goal& goal) {
        return json_response(head, http::status::created, goal_json(goal));
      })));
  return kReplyLater;
}

Handled RestApi::route_goal(const Request& request, std::string_view id_text,
                            const Replier& reply) {
  const auto method = request.method();
  const auto id = parse_id(id_text);
  if (method == http::verb::get) {
    require_role(request, Role::kViewer);
    if (!id) unknown_goal();
    const auto goal = ports_.control.find_goal(*id);
    if (!goal) unknown_goal();
    return json_response(request, http::status::ok, goal_json(*goal));
  }
  if (method == http::verb::delete_) {
    require_role(request, Role::kOperator);
    if (!id) unknown_goal();
    // Stopping is never locked, as e-stop is not: whoever sees a goal go wrong may end it.
    ports_.control.cancel_goal(
        *id,
        reply.completion<navigation::Goal>([](const Request& head, const navigation::Goal& goal) {
          return json_response(head, http::status::ok, goal_json(goal));
        }));
    return kReplyLater;
  }
  throw ApiError(405, "method_not_allowed", "use GET or DELETE on a goal");
}

Handled RestApi::set_pose(const Request& request, const Replier& reply) {
  const nlohmann::json body = parse_json_body(request.body());
  const geometry::Pose2D pose = parse_pose(body, true);
  const std::array<double, 9> cov = parse_covariance(body);
  ports_.control.set_localization_pose(
      pose, cov, reply.completion<Done>([pose, cov](const Request& head, const Done&) {
        return json_response(head, http::status::ok, {{"pose", pose_json(pose)}, {"cov", cov}});
      }));
  return kReplyLater;
}

}  // namespace mobot::api
