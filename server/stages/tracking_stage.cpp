#include "server/stages/tracking_stage.h"

#include <cmath>

namespace mobot::server {
namespace {

api::PixelBox pixel_box(const cv::Rect& box) { return {box.x, box.y, box.width, box.height}; }

// The back-projection mass in the window, as a fraction of the target's whole, above which the
// target counts as wholly in view.
constexpr double kWholeMassFraction = 0.8;
// CamShift's window breathes by about 10 % from frame to frame; a range off by more than this
// from what the window's size says belongs to something else.
constexpr double kSizeRangeTolerance = 0.2;
constexpr double kSizeRangeSmoothing = 0.1;
constexpr int kMisfitsToReseed = 30;

}  // namespace

TrackingStage::TrackingStage(drivers::CameraInfo camera, const drivers::PanTiltDriver* head,
                             vision::TargetTrackerOptions options)
    : camera_(std::move(camera)), head_(head), worker_(options) {}

std::shared_ptr<const msgs::Image> TrackingStage::latest_frame() const {
  std::lock_guard lock(mutex_);
  return latest_;
}

void TrackingStage::start(const api::PixelBox& box, api::Completion<api::TrackingSnapshot> done) {
  std::shared_ptr<const msgs::Image> frame = latest_frame();
  if (!frame) {
    return done(api::DomainError{api::ErrorKind::kConflict, "no_frame",
                                 "the camera has not delivered a frame yet"});
  }
  // A start still in work is answered as replaced.
  if (pending_start_) {
    (*pending_start_)(api::DomainError{api::ErrorKind::kConflict, "tracking_replaced",
                                       "a newer tracking request replaced this one"});
  }
  pending_start_ = std::move(done);
  worker_.start(std::move(frame), {box.x, box.y, box.w, box.h},
                [this](std::optional<vision::TrackerError> error, const vision::TrackState& state) {
                  std::lock_guard lock(mutex_);
                  started_ = StartOutcome{error, state};
                });
}

void TrackingStage::stop(TickContext& context) {
  worker_.stop();
  if (!active_ && context.target.status == "idle") return;
  active_ = false;
  context.target_head.reset();
  publish({context.now_s, "idle", std::nullopt, std::nullopt, std::nullopt}, context);
}

vision::PanTilt TrackingStage::head_at(double stamp_s) const {
  // The last angles at or before the stamp; a frame older than the history gets its oldest.
  if (head_history_.empty()) return {};
  vision::PanTilt joints = head_history_.front().second;
  for (const auto& [t_s, at] : head_history_) {
    if (t_s > stamp_s) break;
    joints = at;
  }
  return joints;
}

void TrackingStage::step(TickContext& context) {
  if (context.head_range) range_ = context.head_range;
  if (context.head) {
    head_history_.emplace_back(context.now_s, *context.head);
    // A second of history covers any frame's delay.
    while (head_history_.front().first < context.now_s - 1.0) head_history_.pop_front();
  }
  if (context.image) {
    auto frame = std::make_shared<const msgs::Image>(*context.image);
    {
      std::lock_guard lock(mutex_);
      latest_ = frame;
    }
    if (active_) {
      const double stamp_s = frame->stamp_s;
      worker_.submit(std::move(frame), head_at(stamp_s), range_ ? range_->range_m : std::nullopt);
    }
  }
  finish_start(context);
  if (!active_) return;
  if (std::optional<TrackedFrame> result = worker_.take_result()) apply(*result, context);
}

void TrackingStage::finish_start(TickContext& context) {
  std::optional<StartOutcome> outcome;
  {
    std::lock_guard lock(mutex_);
    outcome.swap(started_);
  }
  if (!outcome || !pending_start_) return;
  api::Completion<api::TrackingSnapshot> done = std::move(*pending_start_);
  pending_start_.reset();
  if (outcome->error) {
    const std::string reason(vision::error_code(*outcome->error));
    return done(api::DomainError{api::ErrorKind::kImpossible, "not_trackable",
                                 "the box cannot be tracked: " + reason});
  }
  active_ = true;
  size_times_range_.reset();
  TrackedFrame first{outcome->state, outcome->state.stamp_s, context.head.value_or(vision::PanTilt{}),
                     range_ ? range_->range_m : std::nullopt};
  api::TrackingSnapshot snapshot = snapshot_of(first, context.now_s);
  // The first window is the user's box, not CamShift's fit to the target: no reference.
  size_times_range_.reset();
  misfits_in_row_ = 0;
  publish(snapshot, context);
  context.then([done = std::move(done), snapshot] { done(snapshot); });
}

void TrackingStage::apply(const TrackedFrame& frame, TickContext& context) {
  publish(snapshot_of(frame, context.now_s), context);
  // Only a sighting moves the head: turning it after a coasting prediction would shift the image
  // under the prediction, which the tracker would take for the target's motion.
  if (!head_ || frame.state.status != vision::TrackStatus::kTracking) {
    context.target_head.reset();
    return;
  }
  context.target_head = vision::PanTiltHead(head_->head())
                            .centring_target(frame.head, frame.state.centre_px.x,
                                             frame.state.centre_px.y, camera_.pinhole);
}

bool TrackingStage::range_fits_size(double window_px, double range_m) {
  const double product = window_px * range_m;
  if (!(product > 0.0)) return false;
  if (!size_times_range_) {
    size_times_range_ = product;
    return true;
  }
  if (std::abs(product / *size_times_range_ - 1.0) > kSizeRangeTolerance) {
    // Longer than anything passes in front: the reference itself was wrong (a window still
    // settling); start it again.
    if (++misfits_in_row_ >= kMisfitsToReseed) {
      size_times_range_ = product;
      misfits_in_row_ = 0;
    }
    return false;
  }
  misfits_in_row_ = 0;
  *size_times_range_ += kSizeRangeSmoothing * (product - *size_times_range_);
  return true;
}

api::TrackingSnapshot TrackingStage::snapshot_of(const TrackedFrame& frame, double now_s) {
  api::TrackingSnapshot snapshot;
  snapshot.t_s = now_s;
  snapshot.status = std::string(vision::to_string(frame.state.status));
  if (frame.state.status == vision::TrackStatus::kIdle ||
      frame.state.status == vision::TrackStatus::kLost) {
    return snapshot;
  }
  if (!frame.state.box.empty()) snapshot.box = pixel_box(frame.state.box);
  if (!head_ || camera_.kind != "pan_tilt") return snapshot;
  const vision::PanTiltHead head(head_->head());
  const double u = frame.state.centre_px.x;
  const double v = frame.state.centre_px.y;
  // The ranger looks along the optical axis: its echo is the target's only while the target is
  // inside its cone, and only while the target is wholly seen (something passing in front of it
  // answers first).
  const double off_axis_rad =
      std::abs(std::atan((u - camera_.pinhole.width_px / 2.0) / camera_.pinhole.focal_px()));
  const bool ranged = frame.range_m && frame.state.status == vision::TrackStatus::kTracking &&
                      frame.state.mass_fraction >= kWholeMassFraction &&
                      off_axis_rad <= camera_.range_cone_rad / 2.0 &&
                      range_fits_size(std::sqrt(frame.state.window.size.area()), *frame.range_m);
  if (ranged) {
    snapshot.range_m = frame.range_m;
    snapshot.target = head.target_in_base(frame.head, u, v, *frame.range_m, camera_.pinhole);
  }
  return snapshot;
}

void TrackingStage::publish(api::TrackingSnapshot snapshot, TickContext& context) {
  if (snapshot.status != context.target.status) {
    context.event("tracking", {{"status", snapshot.status}});
  }
  // While occluded or unranged the last position is kept for whoever steers toward it; the
  // topic says what this frame gave.
  context.bus->target.publish(snapshot);
  const bool keep_position = !snapshot.target && snapshot.status == "occluded";
  const auto last_target = context.target.target;
  const auto last_range = context.target.range_m;
  context.target = std::move(snapshot);
  if (keep_position) {
    context.target.target = last_target;
    context.target.range_m = last_range;
  }
}

}  // namespace mobot::server
