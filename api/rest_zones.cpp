#include <cmath>

#include "api/api_error.h"
#include "api/json_request.h"
#include "api/rest_api.h"

namespace mobot::api {
namespace {

constexpr std::size_t kMinVertices = 3;
constexpr std::size_t kMaxVertices = 256;

[[noreturn]] void invalid_polygon(const std::string& why) {
  throw ApiError(400, "invalid_polygon", why);
}

// The shape of the polygon: [[x, y], ...] with finite coordinates. Whether it is simple is the
// map catalog's question (it is geometry, not JSON).
std::vector<geometry::Point2D> parse_polygon(const nlohmann::json& body) {
  if (!body.contains("polygon")) throw ApiError(400, "missing_field", "'polygon' is required");
  const nlohmann::json& vertices = body["polygon"];
  if (!vertices.is_array()) invalid_polygon("'polygon' must be an array of [x, y] pairs");
  if (vertices.size() < kMinVertices || vertices.size() > kMaxVertices) {
    invalid_polygon("'polygon' must have 3 to 256 vertices, it has " +
                    std::to_string(vertices.size()));
  }
  std::vector<geometry::Point2D> polygon;
  polygon.reserve(vertices.size());
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const nlohmann::json& vertex = vertices[i];
    if (!vertex.is_array() || vertex.size() != 2 || !vertex[0].is_number() ||
        !vertex[1].is_number()) {
      invalid_polygon("vertex " + std::to_string(i) + " is not an [x, y] pair of numbers");
    }
    const double x = vertex[0].get<double>();
    const double y = vertex[1].get<double>();
    if (!std::isfinite(x) || !std::isfinite(y) || std::abs(x) > kMaxCoordinate_m ||
        std::abs(y) > kMaxCoordinate_m) {
      invalid_polygon("vertex " + std::to_string(i) + " is not a finite point within 1e6 m");
    }
    polygon.push_back({x, y});
  }
  return polygon;
}

nlohmann::json zone_json(const mapping::KeepoutZone& zone) {
  nlohmann::json polygon = nlohmann::json::array();
  for (const auto& p : zone.polygon) polygon.push_back({p.x, p.y});
  return {{"id", zone.id}, {"name", zone.name}, {"polygon", std::move(polygon)}};
}

}  // namespace

Handled RestApi::route_zones(const Request& request, const Segments& path, std::int64_t map_id,
                             const Replier& reply) {
  const auto method = request.method();
  if (path.size() == 5) {
    if (method == http::verb::get) {
      require_role(request, Role::kViewer);
      const auto zones = ports_.maps.list_zones(map_id);
      if (!zones) throw ApiError(404, "unknown_map", "no map with this id");
      nlohmann::json out = nlohmann::json::array();
      for (const auto& zone : *zones) out.push_back(zone_json(zone));
      return json_response(request, http::status::ok, out);
    }
    if (method != http::verb::post) {
      throw ApiError(405, "method_not_allowed", "use GET or POST on a map's zones");
    }
    require_role(request, Role::kOperator);
    const nlohmann::json body = parse_json_body(request.body());
    std::string name = "keep-out";
    if (body.contains("name") && !body["name"].is_null()) name = require_string(body, "name", 128);
    const std::vector<geometry::Point2D> polygon = parse_polygon(body);
    ports_.maps.add_zone(map_id, name, polygon,
                         reply.completion<std::int64_t>([](const Request& head, std::int64_t id) {
                           return json_response(head, http::status::created, {{"id", id}});
                         }));
    return kReplyLater;
  }
  if (path.size() == 6) {
    if (method != http::verb::delete_) {
      throw ApiError(405, "method_not_allowed", "use DELETE on a zone");
    }
    require_role(request, Role::kOperator);
    const auto zone_id = parse_id(path[5]);
    if (!zone_id) throw ApiError(404, "unknown_zone", "no zone with this id");
    ports_.maps.delete_zone(map_id, *zone_id,
                            reply.completion<Done>([](const Request& head, const Done&) {
                              return no_content_response(head);
                            }));
    return kReplyLater;
  }
  throw ApiError(404, "not_found", "no such endpoint");
}

}  // namespace mobot::api
