#pragma once

#include "api/ports/camera_port.h"
#include "drivers/driver_set.h"
#include "server/recorder.h"
#include "server/runtime.h"
#include "server/stages/follow_stage.h"
#include "server/stages/navigate_stage.h"
#include "server/stages/tracking_stage.h"

namespace mobot::server {

// The CameraPort on the robot's camera: tracking and following run as stages on the control loop
// (TrackingStage, FollowStage); this posts the commands to them. `tracking` and `follow` are null
// on a robot without a camera, `head` on one whose camera does not turn.
class CameraService final : public api::CameraPort {
 public:
  CameraService(Runtime& runtime, Recorder& recorder, TrackingStage* tracking, FollowStage* follow,
                NavigateStage& navigate, drivers::PanTiltDriver* head);

  std::optional<api::CameraDescription> camera() const override;
  std::shared_ptr<const msgs::Image> snapshot() const override;
  void set_pan_tilt(double pan_rad, double tilt_rad,
                    api::Completion<api::CameraDescription::Head> done) override;
  void start_tracking(const api::PixelBox& box,
                      api::Completion<api::TrackingSnapshot> done) override;
  api::TrackingSnapshot tracking() const override;
  void stop_tracking(api::Completion<api::TrackingSnapshot> done) override;
  void start_follow(double distance_m, api::Completion<api::Done> done) override;
  void stop_follow(api::Completion<api::Done> done) override;

 private:
  api::CameraDescription::Head head_state() const;

  Runtime& runtime_;
  Recorder& recorder_;
  TrackingStage* tracking_;
  FollowStage* follow_;
  NavigateStage& navigate_;
  drivers::PanTiltDriver* head_;
};

}  // namespace mobot::server
