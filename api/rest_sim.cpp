#include <cmath>

#include "api/api_error.h"
#include "api/frame_codec.h"
#include "api/json_request.h"
#include "api/rest_api.h"

namespace mobot::api {

Handled RestApi::route_sim(const Request& request, const Segments& path, const Replier& reply) {
  const auto method = request.method();
  if (ports_.sim == nullptr) {
    throw ApiError(404, "not_simulated", "this endpoint exists only on the simulated backend");
  }
  if (path[2] == "worlds" && path.size() == 3) {
    if (method != http::verb::get) throw ApiError(405, "method_not_allowed", "use GET");
    require_role(request, Role::kViewer);
    return list_worlds(request);
  }
  if (path[2] != "sim" || path.size() < 4) throw ApiError(404, "not_found", "no such endpoint");
  const std::string_view what = path[3];
  if (what == "obstacles") return route_sim_obstacles(request, path, reply);
  if (what == "targets") return route_sim_targets(request, path, reply);
  if (path.size() != 4) throw ApiError(404, "not_found", "no such endpoint");
  if (what == "truth") {
    if (method != http::verb::get) throw ApiError(405, "method_not_allowed", "use GET");
    require_role(request, Role::kViewer);
    return sim_truth(request);
  }
  if (what == "reset") {
    if (method != http::verb::post) throw ApiError(405, "method_not_allowed", "use POST");
    require_role(request, Role::kOperator);
    return sim_reset(request, reply);
  }
  if (what == "kidnap") {
    if (method != http::verb::post) throw ApiError(405, "method_not_allowed", "use POST");
    require_role(request, Role::kOperator);
    return kidnap(request, reply);
  }
  if (what == "clock") {
    if (method != http::verb::put) throw ApiError(405, "method_not_allowed", "use PUT");
    require_role(request, Role::kOperator);
    return sim_clock(request);
  }
  throw ApiError(404, "not_found", "no such endpoint");
}

Handled RestApi::route_sim_obstacles(const Request& request, const Segments& path,
                                     const Replier& reply) {
  const auto method = request.method();
  if (path.size() == 4) {
    if (method != http::verb::post) throw ApiError(405, "method_not_allowed", "use POST");
    require_role(request, Role::kOperator);
    return add_obstacle(request, reply);
  }
  if (path.size() == 5) {
    if (method != http::verb::delete_) throw ApiError(405, "method_not_allowed", "use DELETE");
    require_role(request, Role::kOperator);
    return remove_obstacle(path[4], reply);
  }
  throw ApiError(404, "not_found", "no such endpoint");
}

Response RestApi::list_worlds(const Request& request) const {
  nlohmann::json worlds = nlohmann::json::array();
  for (const auto& world : ports_.sim->list_worlds()) {
    worlds.push_back({{"name", world.name}, {"description", world.description}});
  }
  return json_response(request, http::status::ok, worlds);
}

Response RestApi::sim_truth(const Request& request) const {
  const SimTruth truth = ports_.sim->sim_truth();
  nlohmann::json body{
      {"t", truth.t_s}, {"pose", pose_json(truth.pose)}, {"collisions", truth.collisions}};
  if (truth.steering_rad) body["steering_rad"] = *truth.steering_rad;
  return json_response(request, http::status::ok, body);
}

Handled RestApi::sim_reset(const Request& request, const Replier& reply) {
  const nlohmann::json body =
      request.body().empty() ? nlohmann::json::object() : parse_json_body(request.body());
  SimResetRequest reset;
  if (body.contains("world") && !body["world"].is_null()) {
    reset.world = require_string(body, "world", 256);
  }
  if (body.contains("pose") && !body["pose"].is_null()) {
    reset.pose = require_pose(body, "pose", false);
  }
  if (const auto seed = optional_number(body, "seed", 0.0, 9007199254740991.0)) {
    reset.seed = static_cast<std::uint64_t>(*seed);
  }
  ports_.sim->sim_reset(reset, reply.completion<Done>([](const Request& head, const Done&) {
    return json_response(head, http::status::ok, {{"ok", true}});
  }));
  return kReplyLater;
}

Handled RestApi::kidnap(const Request& request, const Replier& reply) {
  const geometry::Pose2D pose = parse_pose(parse_json_body(request.body()), true);
  ports_.sim->kidnap(pose, reply.completion<Done>([pose](const Request& head, const Done&) {
    return json_response(head, http::status::ok, {{"pose", pose_json(pose)}});
  }));
  return kReplyLater;
}

Response RestApi::sim_clock(const Request& request) {
  const double time_scale =
      require_number(parse_json_body(request.body()), "time_scale", 0.1, 100.0);
  ports_.sim->set_time_scale(time_scale);
  return json_response(request, http::status::ok, {{"time_scale", time_scale}});
}

Handled RestApi::add_obstacle(const Request& request, const Replier& reply) {
  const nlohmann::json body = parse_json_body(request.body());
  SimObstacleRequest obstacle;
  obstacle.x_m = require_number(body, "x", -1e4, 1e4);
  obstacle.y_m = require_number(body, "y", -1e4, 1e4);
  obstacle.radius_m = require_number(body, "radius", 0.01, 10.0);
  obstacle.height_m = optional_number(body, "height", 0.01, 100.0).value_or(2.0);
  ports_.sim->add_sim_obstacle(obstacle, reply.completion<int>([](const Request& head, int id) {
    return json_response(head, http::status::created, {{"id", id}});
  }));
  return kReplyLater;
}

Handled RestApi::remove_obstacle(std::string_view id_text, const Replier& reply) {
  // Obstacle ids are ints: a larger id names no obstacle.
  const auto id = parse_id(id_text);
  if (!id || *id > 1'000'000'000) {
    throw ApiError(404, "unknown_obstacle", "no obstacle with this id");
  }
  ports_.sim->remove_sim_obstacle(static_cast<int>(*id),
                                  reply.completion<Done>([](const Request& head, const Done&) {
                                    return no_content_response(head);
                                  }));
  return kReplyLater;
}

Handled RestApi::route_sim_targets(const Request& request, const Segments& path,
                                   const Replier& reply) {
  const auto method = request.method();
  if (path.size() == 4) {
    if (method != http::verb::post) throw ApiError(405, "method_not_allowed", "use POST");
    require_role(request, Role::kOperator);
    return add_target(request, reply);
  }
  if (path.size() == 5) {
    if (method != http::verb::delete_) throw ApiError(405, "method_not_allowed", "use DELETE");
    require_role(request, Role::kOperator);
    return remove_target(path[4], reply);
  }
  throw ApiError(404, "not_found", "no such endpoint");
}

Handled RestApi::add_target(const Request& request, const Replier& reply) {
  const nlohmann::json body = parse_json_body(request.body());
  SimTargetRequest target;
  if (!body.contains("color") || !body["color"].is_array() || body["color"].size() != 3) {
    throw ApiError(400, "invalid_field", "'color' must be [r, g, b], each 0..255");
  }
  for (std::size_t i = 0; i < 3; ++i) {
    const nlohmann::json& c = body["color"][i];
    if (!c.is_number_integer() || c.get<long long>() < 0 || c.get<long long>() > 255) {
      throw ApiError(400, "invalid_field", "'color' must be [r, g, b], each 0..255");
    }
    target.color[i] = static_cast<int>(c.get<long long>());
  }
  target.radius_m = require_number(body, "radius", 0.01, 5.0);
  target.height_m = require_number(body, "height", 0.0, 10.0);
  target.speed_mps = require_number(body, "speed", 0.0, 10.0);
  target.loop = optional_bool(body, "loop").value_or(true);
  if (!body.contains("path") || !body["path"].is_array() || body["path"].empty() ||
      body["path"].size() > 1000) {
    throw ApiError(400, "invalid_field", "'path' must be 1..1000 points [x, y]");
  }
  for (const nlohmann::json& point : body["path"]) {
    if (!point.is_array() || point.size() != 2 || !point[0].is_number() || !point[1].is_number() ||
        !std::isfinite(point[0].get<double>()) || !std::isfinite(point[1].get<double>()) ||
        std::abs(point[0].get<double>()) > 1e4 || std::abs(point[1].get<double>()) > 1e4) {
      throw ApiError(400, "invalid_field", "'path' must be 1..1000 points [x, y] within 1e4 m");
    }
    target.path.push_back({point[0].get<double>(), point[1].get<double>()});
  }
  ports_.sim->add_sim_target(target, reply.completion<int>([](const Request& head, int id) {
    return json_response(head, http::status::created, {{"id", id}});
  }));
  return kReplyLater;
}

Handled RestApi::remove_target(std::string_view id_text, const Replier& reply) {
  const auto id = parse_id(id_text);
  if (!id || *id > 1'000'000'000) throw ApiError(404, "unknown_target", "no target with this id");
  ports_.sim->remove_sim_target(static_cast<int>(*id),
                                reply.completion<Done>([](const Request& head, const Done&) {
                                  return no_content_response(head);
                                }));
  return kReplyLater;
}

}  // namespace mobot::api
