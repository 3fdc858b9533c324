#include "api/api_error.h"
#include "api/frame_codec.h"
#include "api/json_request.h"
#include "api/rest_api.h"

namespace mobot::api {
namespace {

Response ok(const Request& request) {
  return json_response(request, http::status::ok, {{"ok", true}});
}

}  // namespace

Response RestApi::route_sim(const Request& request, const Segments& path) {
  const auto method = request.method();
  if (!port_.is_simulated()) {
    throw ApiError(404, "not_simulated", "this endpoint exists only on the simulated backend");
  }
  if (path[2] == "worlds" && path.size() == 3) {
    if (method != http::verb::get) throw ApiError(405, "method_not_allowed", "use GET");
    require_role(request, Role::kViewer);
    nlohmann::json worlds = nlohmann::json::array();
    for (const auto& world : port_.list_worlds()) {
      worlds.push_back({{"name", world.name}, {"description", world.description}});
    }
    return json_response(request, http::status::ok, worlds);
  }
  if (path[2] != "sim" || path.size() < 4) throw ApiError(404, "not_found", "no such endpoint");
  const std::string_view what = path[3];
  if (what == "truth" && path.size() == 4) {
    if (method != http::verb::get) throw ApiError(405, "method_not_allowed", "use GET");
    require_role(request, Role::kViewer);
    const SimTruth truth = port_.sim_truth();
    return json_response(request, http::status::ok,
                         {{"t", truth.t_s}, {"pose", pose_json(truth.pose)},
                          {"collisions", truth.collisions}});
  }
  if (what == "reset" && path.size() == 4) {
    if (method != http::verb::post) throw ApiError(405, "method_not_allowed", "use POST");
    require_role(request, Role::kOperator);
    return sim_reset(request);
  }
  if (what == "clock" && path.size() == 4) {
    if (method != http::verb::put) throw ApiError(405, "method_not_allowed", "use PUT");
    require_role(request, Role::kOperator);
    return sim_clock(request);
  }
  if (what == "obstacles" && path.size() == 4) {
    if (method != http::verb::post) throw ApiError(405, "method_not_allowed", "use POST");
    require_role(request, Role::kOperator);
    return add_obstacle(request);
  }
  if (what == "obstacles" && path.size() == 5) {
    if (method != http::verb::delete_) throw ApiError(405, "method_not_allowed", "use DELETE");
    require_role(request, Role::kOperator);
    const auto id = parse_id(path[4]);
    if (!id || *id > 1'000'000'000 || !port_.remove_sim_obstacle(static_cast<int>(*id))) {
      throw ApiError(404, "unknown_obstacle", "no obstacle with this id");
    }
    Response response{http::status::no_content, request.version()};
    response.keep_alive(request.keep_alive());
    response.prepare_payload();
    return response;
  }
  throw ApiError(404, "not_found", "no such endpoint");
}

Response RestApi::sim_reset(const Request& request) {
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
  port_.sim_reset(reset);
  return ok(request);
}

Response RestApi::sim_clock(const Request& request) {
  const double time_scale = require_number(parse_json_body(request.body()), "time_scale", 0.1, 100.0);
  port_.set_time_scale(time_scale);
  return json_response(request, http::status::ok, {{"time_scale", time_scale}});
}

Response RestApi::add_obstacle(const Request& request) {
  const nlohmann::json body = parse_json_body(request.body());
  const double x_m = require_number(body, "x", -1e4, 1e4);
  const double y_m = require_number(body, "y", -1e4, 1e4);
  const double radius_m = require_number(body, "radius", 0.01, 10.0);
  const double height_m = optional_number(body, "height", 0.01, 100.0).value_or(2.0);
  const int id = port_.add_sim_obstacle(x_m, y_m, radius_m, height_m);
  return json_response(request, http::status::created, {{"id", id}});
}

}  // namespace mobot::api
