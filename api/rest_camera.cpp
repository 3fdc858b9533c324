#include <cmath>

#include "api/api_error.h"
#include "api/frame_codec.h"
#include "api/json_request.h"
#include "api/rest_api.h"

namespace mobot::api {
namespace {

[[noreturn]] void wrong_method(std::string_view allowed) {
  throw ApiError(405, "method_not_allowed", "use " + std::string(allowed));
}

nlohmann::json head_json(const CameraDescription::Head& head) {
  return {{"pan", head.pan_rad},
          {"tilt", head.tilt_rad},
          {"pan_limits", head.pan_limits_rad},
          {"tilt_limits", head.tilt_limits_rad}};
}

nlohmann::json camera_description_json(const CameraDescription& camera) {
  nlohmann::json body{{"kind", camera.kind},
                      {"width", camera.width_px},
                      {"height", camera.height_px},
                      {"rate_hz", camera.rate_hz}};
  if (camera.head) body.update(head_json(*camera.head));
  return body;
}

// A box must be whole pixels inside the image and at least 4 x 4 (a tracker needs some colour to
// learn from).
PixelBox parse_box(const nlohmann::json& body, const CameraDescription& camera) {
  if (!body.contains("box") || !body["box"].is_object()) {
    throw ApiError(400, "invalid_field", "'box' must be an object {x, y, w, h} in image pixels");
  }
  const nlohmann::json& box = body["box"];
  const double x = require_number(box, "x", -1e6, 1e6);
  const double y = require_number(box, "y", -1e6, 1e6);
  const double w = require_number(box, "w", -1e6, 1e6);
  const double h = require_number(box, "h", -1e6, 1e6);
  constexpr double kMinSide_px = 4.0;
  if (w < kMinSide_px || h < kMinSide_px) {
    throw ApiError(400, "invalid_box", "the box must be at least 4 x 4 pixels");
  }
  if (x < 0.0 || y < 0.0 || x + w > camera.width_px || y + h > camera.height_px) {
    throw ApiError(400, "invalid_box",
                   "the box must lie inside the " + std::to_string(camera.width_px) + " x " +
                       std::to_string(camera.height_px) + " image");
  }
  return {static_cast<int>(std::floor(x)), static_cast<int>(std::floor(y)),
          static_cast<int>(std::floor(w)), static_cast<int>(std::floor(h))};
}

}  // namespace

CameraDescription RestApi::require_camera() const {
  std::optional<CameraDescription> camera = ports_.camera.camera();
  if (!camera) throw ApiError(404, "no_camera", "this robot has no camera");
  return *camera;
}

Handled RestApi::route_camera(const Request& request, const Segments& path,
                              const Replier& reply) {
  const auto method = request.method();
  if (path.size() == 3) {
    if (method != http::verb::get) wrong_method("GET");
    require_role(request, Role::kViewer);
    return json_response(request, http::status::ok, camera_description_json(require_camera()));
  }
  if (path.size() == 4 && path[3] == "snapshot") {
    if (method != http::verb::get) wrong_method("GET");
    require_role(request, Role::kViewer);
    require_camera();
    const std::shared_ptr<const msgs::Image> frame = ports_.camera.snapshot();
    if (!frame) throw ApiError(503, "no_frame", "the camera has not delivered a frame yet");
    return bytes_response(request, http::status::ok, "image/jpeg",
                          std::string(frame->data.begin(), frame->data.end()));
  }
  if (path.size() == 4 && path[3] == "pan_tilt") {
    if (method != http::verb::put) wrong_method("PUT");
    require_role(request, Role::kOperator);
    require_camera();
    const nlohmann::json body = parse_json_body(request.body());
    const double pan = require_number(body, "pan", -10.0, 10.0);
    const double tilt = require_number(body, "tilt", -10.0, 10.0);
    ports_.camera.set_pan_tilt(
        pan, tilt,
        reply.completion<CameraDescription::Head>(
            [](const Request& head, const CameraDescription::Head& state) {
              return json_response(head, http::status::ok, head_json(state));
            }));
    return kReplyLater;
  }
  throw ApiError(404, "not_found", "no such endpoint");
}

Handled RestApi::route_tracking(const Request& request, const Segments& path,
                                const Replier& reply) {
  if (path.size() != 3) throw ApiError(404, "not_found", "no such endpoint");
  const auto render = [](const Request& head, const TrackingSnapshot& snapshot) {
    return json_response(head, http::status::ok, tracking_json(snapshot));
  };
  switch (request.method()) {
    case http::verb::get:
      require_role(request, Role::kViewer);
      require_camera();
      return json_response(request, http::status::ok, tracking_json(ports_.camera.tracking()));
    case http::verb::post: {
      require_role(request, Role::kOperator);
      const PixelBox box = parse_box(parse_json_body(request.body()), require_camera());
      ports_.camera.start_tracking(
          box, reply.completion<TrackingSnapshot>([](const Request& head, const TrackingSnapshot& s) {
            return json_response(head, http::status::created, tracking_json(s));
          }));
      return kReplyLater;
    }
    case http::verb::delete_:
      require_role(request, Role::kOperator);
      require_camera();
      ports_.camera.stop_tracking(reply.completion<TrackingSnapshot>(render));
      return kReplyLater;
    default:
      wrong_method("GET, POST or DELETE");
  }
}

Handled RestApi::route_follow(const Request& request, const Segments& path,
                              const Replier& reply) {
  if (path.size() != 3) throw ApiError(404, "not_found", "no such endpoint");
  const auto answer = [](bool following) {
    return [following](const Request& head, const Done&) {
      return json_response(head, http::status::ok, {{"following", following}});
    };
  };
  if (request.method() == http::verb::post) {
    require_role(request, Role::kOperator);
    require_camera();
    const double distance_m =
        require_number(parse_json_body(request.body()), "distance_m", 0.5, 5.0);
    const OperatorLock::Change lock = require_driver(request, reply);
    ports_.camera.start_follow(distance_m,
                               undo_if_refused(lock, reply.completion<Done>(answer(true))));
    return kReplyLater;
  }
  if (request.method() == http::verb::delete_) {
    require_role(request, Role::kOperator);
    require_camera();
    ports_.camera.stop_follow(reply.completion<Done>(answer(false)));
    return kReplyLater;
  }
  wrong_method("POST or DELETE");
}

}  // namespace mobot::api
