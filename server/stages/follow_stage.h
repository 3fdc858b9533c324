#pragma once

#include <optional>
#include <string>

#include "api/ports/result.h"
#include "core/control/target_follower.h"
#include "drivers/camera_info.h"
#include "drivers/pan_tilt_driver.h"
#include "server/stage.h"

namespace mobot::server {

struct FollowOptions {
  // The base's law (TargetFollower); its turn rate is capped because it moves the image too.
  control::TargetFollowerOptions base;
  // The head turns toward the target no faster than this (below its servos' 2 rad/s): every
  // turn moves the whole image, and a target that jumps by more than the tracker's gate between
  // two frames (about 25 px at 15 fps) is taken for occluded.
  double head_rate_rad_s = 0.5;
};

// Follow mode (docs/algorithms.md R4, E6): the head keeps the tracked target centred whenever a
// target is tracked; while following, the base keeps it straight ahead at the set distance. The
// base's command goes through the mux as the navigation source (a goal and following exclude each
// other). Teleop, e-stop, a lost target or the end of tracking end it with a `follow` event.
class FollowStage final : public Stage {
 public:
  // `head` is null for a camera that does not turn (the base alone then turns to the target).
  FollowStage(drivers::CameraInfo camera, drivers::PanTiltDriver* head, FollowOptions options);

  std::string_view name() const override { return "follow"; }
  void step(TickContext& context) override;

  // kConflict not_tracking / estop_engaged; the distance is within 0.5..5 m (the caller checks).
  std::optional<api::DomainError> start(double distance_m, TickContext& context);
  // Ends following with `reason` in the follow event; false when not following.
  bool stop(const std::string& reason, TickContext& context);
  bool following() const { return distance_m_.has_value(); }

 private:
  void centre_head(const TickContext& context);
  void observe(const TickContext& context);
  std::optional<std::string> end_reason(const TickContext& context) const;

  const drivers::CameraInfo camera_;
  drivers::PanTiltDriver* head_;
  FollowOptions options_;
  std::optional<double> distance_m_;
  control::TargetFollower follower_;
  double last_sighting_s_ = -1.0;
};

}  // namespace mobot::server
