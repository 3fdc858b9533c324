#include <openssl/evp.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <span>

#include "api/api_error.h"
#include "api/json_request.h"
#include "api/rest_api.h"
#include "core/mapping/map_image_codec.h"

namespace mobot::api {
namespace {

constexpr std::size_t kMaxMapCells = 25'000'000;

std::vector<std::uint8_t> decode_base64(std::string_view text) {
  std::string compact;
  compact.reserve(text.size());
  for (const char c : text) {
    if (std::isspace(static_cast<unsigned char>(c)) == 0) compact.push_back(c);
  }
  if (compact.empty() || compact.size() % 4 != 0) {
    throw ApiError(400, "invalid_image", "'image_base64' is not valid base64");
  }
  std::vector<std::uint8_t> bytes(compact.size() / 4 * 3);
  const int length =
      EVP_DecodeBlock(bytes.data(), reinterpret_cast<const unsigned char*>(compact.data()),
                      static_cast<int>(compact.size()));
  if (length < 0) throw ApiError(400, "invalid_image", "'image_base64' is not valid base64");
  const auto padding = static_cast<std::size_t>(std::count(compact.end() - 2, compact.end(), '='));
  bytes.resize(static_cast<std::size_t>(length) - padding);
  return bytes;
}

nlohmann::json map_info_json(const MapInfo& info) {
  return {{"id", info.id},
          {"name", info.name},
          {"width", info.width},
          {"height", info.height},
          {"resolution", info.resolution_m},
          {"origin", {{"x", info.origin.x}, {"y", info.origin.y}, {"theta", info.origin.theta}}},
          {"created", info.created_unix_s},
          {"active", info.active}};
}

[[noreturn]] void unknown_map() { throw ApiError(404, "unknown_map", "no map with this id"); }

}  // namespace

Handled RestApi::route_maps(const Request& request, const Segments& path, const Replier& reply) {
  const auto method = request.method();
  if (path.size() == 3) {
    if (method == http::verb::get) {
      require_role(request, Role::kViewer);
      return list_maps(request);
    }
    if (method == http::verb::post) {
      require_role(request, Role::kAdmin);
      return import_map(request);
    }
    throw ApiError(405, "method_not_allowed", "use GET or POST on /api/v1/maps");
  }
  const auto id = parse_id(path[3]);
  if (path.size() == 4) {
    if (method == http::verb::get) {
      require_role(request, Role::kViewer);
      if (!id) unknown_map();
      return map_info(request, *id);
    }
    if (method == http::verb::delete_) {
      require_role(request, Role::kAdmin);
      if (!id) unknown_map();
      return delete_map(request, *id);
    }
    throw ApiError(405, "method_not_allowed", "use GET or DELETE on a map");
  }
  if (path.size() >= 5 && path[4] == "zones") {
    if (!id) unknown_map();
    return route_zones(request, path, *id, reply);
  }
  if (path.size() == 5) {
    const std::string_view what = path[4];
    if (what == "activate") {
      if (method != http::verb::post) {
        throw ApiError(405, "method_not_allowed", "use POST to activate a map");
      }
      require_role(request, Role::kOperator);
      if (!id) unknown_map();
      return activate_map(*id, reply);
    }
    if (what == "image" || what == "map.pgm" || what == "map.yaml") {
      if (method != http::verb::get) {
        throw ApiError(405, "method_not_allowed", "use GET for map files");
      }
      require_role(request, Role::kViewer);
      if (!id) unknown_map();
      return map_export(request, *id, what);
    }
  }
  throw ApiError(404, "not_found", "no such endpoint");
}

Response RestApi::list_maps(const Request& request) const {
  nlohmann::json maps = nlohmann::json::array();
  for (const auto& info : ports_.maps.list_maps()) maps.push_back(map_info_json(info));
  return json_response(request, http::status::ok, maps);
}

Response RestApi::import_map(const Request& request) {
  const nlohmann::json body = parse_json_body(request.body());
  const std::string name = require_string(body, "name", 128);
  const double resolution_m = require_number(body, "resolution", 0.001, 10.0);
  const geometry::Pose2D origin = require_pose(body, "origin", false);
  mapping::MapImageOptions options;
  options.negate = optional_bool(body, "negate").value_or(false);
  options.occupied_thresh =
      optional_number(body, "occupied_thresh", 0.0, 1.0).value_or(options.occupied_thresh);
  options.free_thresh =
      optional_number(body, "free_thresh", 0.0, 1.0).value_or(options.free_thresh);
  if (options.free_thresh >= options.occupied_thresh) {
    throw ApiError(400, "invalid_field", "'free_thresh' must be below 'occupied_thresh'");
  }
  const std::string encoded = require_string(body, "image_base64", 8 * 1024 * 1024);
  const std::vector<std::uint8_t> image = decode_base64(encoded);
  mapping::OccupancyGrid grid;
  try {
    grid = mapping::decode_map_image(image, resolution_m, origin, options, kMaxMapCells);
  } catch (const mapping::MapImageError& error) {
    throw ApiError(400, "invalid_image", error.what());
  }
  const std::int64_t id = ports_.maps.import_map(name, grid);
  return json_response(request, http::status::created, {{"id", id}});
}

Response RestApi::map_info(const Request& request, std::int64_t id) const {
  const auto info = ports_.maps.map_info(id);
  if (!info) unknown_map();
  return json_response(request, http::status::ok, map_info_json(*info));
}

Response RestApi::map_export(const Request& request, std::int64_t id, std::string_view what) const {
  const auto grid = ports_.maps.map_grid(id);
  if (!grid) unknown_map();
  if (what == "image") {
    const auto png = mapping::encode_map_png(*grid);
    return bytes_response(request, http::status::ok, "image/png", {png.begin(), png.end()});
  }
  if (what == "map.pgm") {
    const auto pgm = mapping::encode_map_pgm(*grid);
    Response response = bytes_response(request, http::status::ok, "image/x-portable-graymap",
                                       {pgm.begin(), pgm.end()});
    response.set(http::field::content_disposition, "attachment; filename=\"map.pgm\"");
    return response;
  }
  Response response = bytes_response(request, http::status::ok, "application/yaml",
                                     mapping::encode_map_yaml(*grid, "map.pgm"));
  response.set(http::field::content_disposition, "attachment; filename=\"map.yaml\"");
  return response;
}

Handled RestApi::activate_map(std::int64_t id, const Replier& reply) {
  ports_.maps.activate_map(id,
                           reply.completion<MapInfo>([](const Request& head, const MapInfo& info) {
                             return json_response(head, http::status::ok, map_info_json(info));
                           }));
  return kReplyLater;
}

Response RestApi::delete_map(const Request& request, std::int64_t id) {
  ports_.maps.delete_map(id);
  return no_content_response(request);
}

}  // namespace mobot::api
