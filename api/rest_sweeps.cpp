#include <cmath>

#include "api/api_error.h"
#include "api/cloud_formats.h"
#include "api/frame_codec.h"
#include "api/json_request.h"
#include "api/rest_api.h"

namespace mobot::api {
namespace {

nlohmann::json sweep_json(const SweepInfo& sweep) {
  nlohmann::json out{
      {"id", sweep.id},
      {"status", sweep.status},
      {"points", sweep.points},
      {"mode",
       {{"period_s", sweep.period_s}, {"step_deg", sweep.step_deg}, {"scans", sweep.scans}}},
      {"scans_done", sweep.scans_done},
      {"started_t", sweep.started_t}};
  if (sweep.ended_t) out["ended_t"] = *sweep.ended_t;
  if (!sweep.reason.empty()) out["reason"] = sweep.reason;
  return out;
}

SweepRequest parse_sweep(std::string_view body) {
  // Every field is optional, so an empty body asks for the default mode.
  const nlohmann::json json = body.find_first_not_of(" \t\r\n") == std::string_view::npos
                                  ? nlohmann::json::object()
                                  : parse_json_body(body);
  SweepRequest request;
  request.period_s = optional_number(json, "period_s", 0.0, 1e6).value_or(request.period_s);
  request.step_deg = optional_number(json, "step_deg", 0.0, 1e6).value_or(request.step_deg);
  return request;
}

nlohmann::json obstacle_map_json(std::int64_t id, const mapping::OccupancyGrid& grid) {
  return {{"sweep_id", id},
          {"resolution", grid.resolution_m()},
          {"origin", pose_json(grid.origin())},
          {"width", grid.width()},
          {"height", grid.height()},
          {"data", grid.cells()}};
}

[[noreturn]] void unknown_sweep() {
  throw ApiError(404, "unknown_sweep", "no 3D sweep with this id");
}

}  // namespace

Handled RestApi::route_sweeps(const Request& request, const Segments& path, const Replier& reply) {
  const auto method = request.method();
  if (path.size() == 4 || path.size() == 5) return route_sweep(request, path);
  if (path.size() != 3) throw ApiError(404, "not_found", "no such endpoint");
  if (method == http::verb::get) {
    require_role(request, Role::kViewer);
    nlohmann::json sweeps = nlohmann::json::array();
    for (const auto& sweep : ports_.sweeps.list_sweeps()) sweeps.push_back(sweep_json(sweep));
    return json_response(request, http::status::ok, sweeps);
  }
  if (method == http::verb::post) {
    require_role(request, Role::kOperator);
    return start_sweep(request, reply);
  }
  throw ApiError(405, "method_not_allowed", "use GET or POST on /api/v1/sweeps");
}

Handled RestApi::start_sweep(const Request& request, const Replier& reply) {
  const SweepRequest sweep_request = parse_sweep(request.body());
  ports_.sweeps.start_sweep(
      sweep_request, reply.completion<SweepInfo>([](const Request& head, const SweepInfo& sweep) {
        return json_response(head, http::status::created, sweep_json(sweep));
      }));
  return kReplyLater;
}

Response RestApi::route_sweep(const Request& request, const Segments& path) {
  const auto method = request.method();
  const auto id = parse_id(path[3]);
  if (path.size() == 4 && method == http::verb::delete_) {
    // Like a map, stored data only an admin removes.
    require_role(request, Role::kAdmin);
    if (!id) unknown_sweep();
    ports_.sweeps.delete_sweep(*id);
    return no_content_response(request);
  }
  if (method != http::verb::get) {
    throw ApiError(405, "method_not_allowed",
                   path.size() == 4 ? "use GET or DELETE on a sweep" : "use GET");
  }
  require_role(request, Role::kViewer);
  if (!id) unknown_sweep();
  if (path.size() == 4) {
    const auto sweep = ports_.sweeps.find_sweep(*id);
    if (!sweep) unknown_sweep();
    return json_response(request, http::status::ok, sweep_json(*sweep));
  }
  if (path[4] == "cloud") return sweep_cloud(request, *id);
  if (path[4] == "obstacle_map") {
    return json_response(request, http::status::ok,
                         obstacle_map_json(*id, ports_.sweeps.sweep_obstacle_map(*id)));
  }
  throw ApiError(404, "not_found", "no such endpoint");
}

Response RestApi::sweep_cloud(const Request& request, std::int64_t id) const {
  std::string format = query_parameter(request.target(), "format");
  if (format.empty()) format = "ply";
  if (format != "ply" && format != "bin") {
    throw ApiError(400, "invalid_format", "format must be ply or bin");
  }
  const perception::PointCloud cloud = ports_.sweeps.sweep_cloud(id);
  if (format == "ply") {
    Response response =
        bytes_response(request, http::status::ok, "application/octet-stream", encode_ply(cloud));
    response.set(http::field::content_disposition,
                 "attachment; filename=\"sweep-" + std::to_string(id) + ".ply\"");
    return response;
  }
  // The bytes of one `cloud` stream frame holding the whole sweep (README "Binary frames").
  const auto sweep = ports_.sweeps.find_sweep(id);
  const auto scans = static_cast<std::uint32_t>(sweep ? sweep->scans : 0);
  const CloudChunk chunk{static_cast<std::uint32_t>(id), 0, true, scans, scans};
  const FrameStamp stamp{sweep && sweep->ended_t ? *sweep->ended_t : 0.0, 0, 0};
  return bytes_response(request, http::status::ok, "application/octet-stream",
                        encode_binary_cloud(stamp, chunk, cloud));
}

}  // namespace mobot::api
