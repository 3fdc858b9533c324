#include "api/api_error.h"
#include "api/json_request.h"
#include "api/rest_api.h"

namespace mobot::api {
namespace {

nlohmann::json mapping_status_json(const MappingStatus& status) {
  nlohmann::json body = {{"mapping", status.mapping},
                         {"scans", status.scans},
                         {"nodes", status.nodes},
                         {"loop_closures", status.loop_closures}};
  if (status.started_t) body["started_t"] = *status.started_t;
  return body;
}

}  // namespace

Handled RestApi::route_mapping(const Request& request, const Segments& path, const Replier& reply) {
  if (path.size() != 3) throw ApiError(404, "not_found", "no such endpoint");
  if (request.method() == http::verb::get) {
    require_role(request, Role::kViewer);
    return json_response(request, http::status::ok,
                         mapping_status_json(ports_.mapping.mapping_status()));
  }
  if (request.method() != http::verb::post) {
    throw ApiError(405, "method_not_allowed", "use GET or POST on /api/v1/mapping");
  }
  require_role(request, Role::kOperator);
  const nlohmann::json body = parse_json_body(request.body());
  const std::string action = require_string(body, "action", 16);
  if (action == "start") {
    ports_.mapping.start_mapping(
        reply.completion<MappingStatus>([](const Request& head, const MappingStatus&) {
          return json_response(head, http::status::ok, {{"mapping", true}});
        }));
    return kReplyLater;
  }
  if (action != "stop") {
    throw ApiError(400, "invalid_field", "'action' must be \"start\" or \"stop\"");
  }
  std::optional<std::string> save_as;
  if (body.contains("save_as") && !body["save_as"].is_null()) {
    save_as = require_string(body, "save_as", 128);
    if (save_as->empty()) throw ApiError(400, "invalid_field", "'save_as' must not be empty");
  }
  ports_.mapping.stop_mapping(
      save_as, reply.completion<MappingStopped>([](const Request& head, const MappingStopped& out) {
        nlohmann::json answer = {{"mapping", false}};
        if (out.map_id) answer["map_id"] = *out.map_id;
        return json_response(head, http::status::ok, answer);
      }));
  return kReplyLater;
}

Handled RestApi::route_localization(const Request& request, const Segments& path,
                                    const Replier& reply) {
  if (path.size() != 4) throw ApiError(404, "not_found", "no such endpoint");
  const std::string_view what = path[3];
  const auto method = request.method();
  if (what == "pose") {
    if (method != http::verb::post) {
      throw ApiError(405, "method_not_allowed", "use POST to set the pose");
    }
    require_role(request, Role::kOperator);
    return set_pose(request, reply);
  }
  if (what == "global") {
    if (method != http::verb::post) {
      throw ApiError(405, "method_not_allowed", "use POST to localize globally");
    }
    require_role(request, Role::kOperator);
    ports_.localization.localize_globally(
        reply.completion<std::string>([](const Request& head, const std::string& name) {
          return json_response(head, http::status::accepted, {{"method", name}});
        }));
    return kReplyLater;
  }
  if (what == "method") {
    if (method != http::verb::put) {
      throw ApiError(405, "method_not_allowed", "use PUT to choose the method");
    }
    require_role(request, Role::kOperator);
    const std::string name = require_string(parse_json_body(request.body()), "method", 64);
    const auto known = ports_.localization.localization_methods();
    if (std::find(known.begin(), known.end(), name) == known.end()) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      throw ApiError(400, "unknown_method", "'method' must be one of " + list);
    }
    ports_.localization.set_localization_method(
        name, reply.completion<std::string>([](const Request& head, const std::string& chosen) {
          return json_response(head, http::status::ok, {{"method", chosen}});
        }));
    return kReplyLater;
  }
  throw ApiError(404, "not_found", "no such endpoint");
}

}  // namespace mobot::api
