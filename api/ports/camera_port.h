#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>

#include "api/ports/result.h"
#include "core/geometry/pose2d.h"
#include "core/msgs/image.h"

namespace mobot::api {

// GET /api/v1/camera: what the camera is and, on a pan/tilt head, where it looks.
struct CameraDescription {
  std::string kind;  // pan_tilt | omni | fixed
  int width_px = 0;
  int height_px = 0;
  double rate_hz = 0.0;
  struct Head {
    double pan_rad = 0.0;
    double tilt_rad = 0.0;
    std::array<double, 2> pan_limits_rad{};
    std::array<double, 2> tilt_limits_rad{};
  };
  std::optional<Head> head;
};

// A box in the camera image's pixels, origin top left, y down.
struct PixelBox {
  int x = 0;
  int y = 0;
  int w = 0;
  int h = 0;
};

// GET /api/v1/tracking and the `target` topic.
struct TrackingSnapshot {
  double t_s = 0.0;
  std::string status = "idle";  // idle | tracking | occluded | lost
  std::optional<PixelBox> box;
  std::optional<geometry::Point2D> target;  // robot frame, m
  std::optional<double> range_m;
};

// The camera, target tracking and following (docs/api.md). Thread-safe; the commands run on the
// control loop or the tracking thread and complete from there.
class CameraPort {
 public:
  virtual ~CameraPort() = default;

  // nullopt: the robot has no camera (404 no_camera on every camera path).
  virtual std::optional<CameraDescription> camera() const = 0;
  // The newest frame (JPEG); null before the first.
  virtual std::shared_ptr<const msgs::Image> snapshot() const = 0;
  // kNotFound no_pan_tilt without a head; kInvalid out_of_range beyond its limits.
  virtual void set_pan_tilt(double pan_rad, double tilt_rad,
                            Completion<CameraDescription::Head> done) = 0;
  // kConflict no_frame before the first frame; kImpossible not_trackable when the box holds too
  // little colour to track. The box is inside the image (the caller checks).
  virtual void start_tracking(const PixelBox& box, Completion<TrackingSnapshot> done) = 0;
  virtual TrackingSnapshot tracking() const = 0;
  virtual void stop_tracking(Completion<TrackingSnapshot> done) = 0;
  // kConflict not_tracking without a tracked target, estop_engaged under e-stop; kNotFound
  // no_pan_tilt on a camera that cannot turn to the target.
  virtual void start_follow(double distance_m, Completion<Done> done) = 0;
  // kConflict not_following.
  virtual void stop_follow(Completion<Done> done) = 0;
};

}  // namespace mobot::api
