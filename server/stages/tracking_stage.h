#pragma once

#include <deque>
#include <memory>
#include <mutex>
#include <optional>

#include "api/ports/result.h"
#include "drivers/camera_info.h"
#include "drivers/pan_tilt_driver.h"
#include "server/stage.h"
#include "server/tracking_worker.h"

namespace mobot::server {

// Target tracking on the camera's frames (docs/algorithms.md E6): hands each frame to the
// tracking thread while a target is tracked, turns the tracker's window into the target's
// position in the robot frame (the head's angles, the pixel's ray and the head ranger's range,
// R4) and publishes it on the `target` topic; status changes are `tracking` events. Keeps the
// newest frame for the snapshot and for seeding the tracker.
class TrackingStage final : public Stage {
 public:
  // `head` is null for a camera that does not turn.
  TrackingStage(drivers::CameraInfo camera, const drivers::PanTiltDriver* head,
                vision::TargetTrackerOptions options = {});

  std::string_view name() const override { return "tracking"; }
  void step(TickContext& context) override;

  // Seeds the tracker with `box` on the newest frame; `done` is completed from a later tick
  // with the first state or the refusal (no_frame, not_trackable).
  void start(const api::PixelBox& box, api::Completion<api::TrackingSnapshot> done);
  void stop(TickContext& context);
  bool active() const { return active_; }
  std::shared_ptr<const msgs::Image> latest_frame() const;
  const drivers::CameraInfo& camera() const { return camera_; }

 private:
  struct StartOutcome {
    std::optional<vision::TrackerError> error;
    vision::TrackState state;
  };
  void finish_start(TickContext& context);
  void apply(const TrackedFrame& frame, TickContext& context);
  api::TrackingSnapshot snapshot_of(const TrackedFrame& frame, double now_s);
  // Whether a range agrees with the target's size in the image: the window's size times the
  // range is the target's size times the focal length, steady while the ranger sees the target.
  // Something passing in front answers the ranger before it hides the target.
  bool range_fits_size(double window_px, double range_m);
  void publish(api::TrackingSnapshot snapshot, TickContext& context);
  // Where the head was when a frame stamped `stamp_s` was taken: a frame reaches the loop a tick
  // or more after its exposure, and the head has moved on since.
  vision::PanTilt head_at(double stamp_s) const;

  const drivers::CameraInfo camera_;
  const drivers::PanTiltDriver* head_;
  bool active_ = false;
  std::optional<msgs::HeadRange> range_;
  std::optional<double> size_times_range_;  // px m, averaged over the ranges that fitted
  int misfits_in_row_ = 0;
  std::deque<std::pair<double, vision::PanTilt>> head_history_;  // (stamp, joints), oldest first
  std::optional<api::Completion<api::TrackingSnapshot>> pending_start_;

  mutable std::mutex mutex_;  // latest_ (read by the snapshot endpoint) and started_
  std::shared_ptr<const msgs::Image> latest_;
  std::optional<StartOutcome> started_;
  // Last: its thread, which calls back into started_ under mutex_, is joined before they go.
  TrackingWorker worker_;
};

}  // namespace mobot::server
