#include "server/services/camera_service.h"

#include "server/services/after_commit.h"

namespace mobot::server {
namespace {

api::DomainError no_camera() {
  return {api::ErrorKind::kNotFound, "no_camera", "this robot has no camera"};
}

api::DomainError no_pan_tilt() {
  return {api::ErrorKind::kNotFound, "no_pan_tilt", "this robot's camera has no pan/tilt head"};
}

}  // namespace

CameraService::CameraService(Runtime& runtime, Recorder& recorder, TrackingStage* tracking,
                             FollowStage* follow, NavigateStage& navigate,
                             drivers::PanTiltDriver* head)
    : runtime_(runtime),
      recorder_(recorder),
      tracking_(tracking),
      follow_(follow),
      navigate_(navigate),
      head_(head) {}

api::CameraDescription::Head CameraService::head_state() const {
  const vision::PanTiltHeadOptions& options = head_->head();
  const vision::PanTilt current = head_->current();
  return {current.pan_rad,
          current.tilt_rad,
          {options.min_pan_rad, options.max_pan_rad},
          {options.min_tilt_rad, options.max_tilt_rad}};
}

std::optional<api::CameraDescription> CameraService::camera() const {
  if (!tracking_) return std::nullopt;
  const drivers::CameraInfo& info = tracking_->camera();
  api::CameraDescription description;
  description.kind = info.kind;
  description.rate_hz = info.rate_hz;
  if (info.omni) {
    description.width_px = info.omni->width_px;
    description.height_px = info.omni->height_px;
  } else {
    description.width_px = info.pinhole.width_px;
    description.height_px = info.pinhole.height_px;
  }
  if (head_) description.head = head_state();
  return description;
}

std::shared_ptr<const msgs::Image> CameraService::snapshot() const {
  if (!tracking_) throw api::DomainException(no_camera());
  return tracking_->latest_frame();
}

void CameraService::set_pan_tilt(double pan_rad, double tilt_rad,
                                 api::Completion<api::CameraDescription::Head> done) {
  if (!tracking_) return done(no_camera());
  if (!head_) return done(no_pan_tilt());
  const vision::PanTiltHeadOptions& head = head_->head();
  if (pan_rad < head.min_pan_rad || pan_rad > head.max_pan_rad || tilt_rad < head.min_tilt_rad ||
      tilt_rad > head.max_tilt_rad) {
    return done(api::DomainError{api::ErrorKind::kInvalid, "out_of_range",
                                 "pan and tilt must lie within the head's limits (GET /camera)"});
  }
  runtime_.post([this, pan_rad, tilt_rad, done = std::move(done)](TickContext& context) mutable {
    head_->set_target({pan_rad, tilt_rad});
    api::CameraDescription::Head state = head_state();
    state.pan_rad = pan_rad;
    state.tilt_rad = tilt_rad;
    context.then([done = std::move(done), state] { done(state); });
  });
}

void CameraService::start_tracking(const api::PixelBox& box,
                                   api::Completion<api::TrackingSnapshot> done) {
  if (!tracking_) return done(no_camera());
  runtime_.post([this, box, done = std::move(done)](TickContext&) mutable {
    tracking_->start(box, std::move(done));
  });
}

api::TrackingSnapshot CameraService::tracking() const {
  if (!tracking_) throw api::DomainException(no_camera());
  return runtime_.state()->target;
}

void CameraService::stop_tracking(api::Completion<api::TrackingSnapshot> done) {
  if (!tracking_) return done(no_camera());
  runtime_.post([this, done = std::move(done)](TickContext& context) mutable {
    tracking_->stop(context);
    if (follow_) follow_->stop("tracking_stopped", context);
    after_commit(recorder_, context, std::move(done), context.target);
  });
}

void CameraService::start_follow(double distance_m, api::Completion<api::Done> done) {
  if (!tracking_) return done(no_camera());
  if (!follow_) return done(no_pan_tilt());
  runtime_.post([this, distance_m, done = std::move(done)](TickContext& context) mutable {
    if (const auto refusal = follow_->start(distance_m, context)) return done(*refusal);
    if (context.navigating) {
      navigate_.end_active(navigation::GoalStatus::kCanceled, "follow", context);
    }
    after_commit(recorder_, context, std::move(done), api::Done{});
  });
}

void CameraService::stop_follow(api::Completion<api::Done> done) {
  if (!tracking_) return done(no_camera());
  if (!follow_) return done(no_pan_tilt());
  runtime_.post([this, done = std::move(done)](TickContext& context) mutable {
    follow_->stop("canceled", context);
    after_commit(recorder_, context, std::move(done), api::Done{});
  });
}

}  // namespace mobot::server
