#include "server/stages/follow_stage.h"

#include <algorithm>
#include <cmath>

namespace mobot::server {
namespace {

bool seen(const api::TrackingSnapshot& target) {
  return target.status == "tracking" || target.status == "occluded";
}

}  // namespace

FollowStage::FollowStage(drivers::CameraInfo camera, drivers::PanTiltDriver* head,
                         FollowOptions options)
    : camera_(std::move(camera)), head_(head), options_(options), follower_(options.base) {}

std::optional<api::DomainError> FollowStage::start(double distance_m, TickContext& context) {
  if (context.estop) {
    return api::DomainError{api::ErrorKind::kConflict, "estop_engaged",
                            "the e-stop is engaged"};
  }
  if (!seen(context.target)) {
    return api::DomainError{api::ErrorKind::kConflict, "not_tracking",
                            "no target is tracked: draw a box around it first"};
  }
  distance_m_ = distance_m;
  follower_.reset();
  last_sighting_s_ = -1.0;
  observe(context);
  context.following = true;
  context.event("follow", {{"following", true}, {"distance_m", distance_m}});
  return std::nullopt;
}

bool FollowStage::stop(const std::string& reason, TickContext& context) {
  if (!distance_m_) return false;
  distance_m_.reset();
  context.following = false;
  context.mux_requests.push_back({"navigation", std::nullopt});
  context.event("follow", {{"following", false}, {"reason", reason}});
  return true;
}

void FollowStage::step(TickContext& context) {
  if (seen(context.target)) centre_head(context);
  if (!distance_m_) return;
  if (const std::optional<std::string> reason = end_reason(context)) {
    stop(*reason, context);
    return;
  }
  context.following = true;
  observe(context);
  context.mux_requests.push_back(
      {"navigation", follower_.command(context.pose, *distance_m_, context.now_s)});
}

std::optional<std::string> FollowStage::end_reason(const TickContext& context) const {
  if (context.estop) return "estop";
  if (context.teleop_active) return "teleop";
  if (context.navigating) return "goal";
  if (context.target.status == "lost") return "target_lost";
  if (context.target.status == "idle") return "tracking_stopped";
  return std::nullopt;
}

void FollowStage::centre_head(const TickContext& context) {
  if (!head_ || !context.head || !context.target_head) return;
  vision::PanTiltHeadOptions slow = head_->head();
  slow.max_pan_rate_rad_s = std::min(slow.max_pan_rate_rad_s, options_.head_rate_rad_s);
  slow.max_tilt_rate_rad_s = std::min(slow.max_tilt_rate_rad_s, options_.head_rate_rad_s);
  head_->set_target(vision::PanTiltHead(slow).step_towards(*context.head, *context.target_head,
                                                           context.period_s));
}

void FollowStage::observe(const TickContext& context) {
  // A new ranged sighting: where the target stands in the map now.
  const api::TrackingSnapshot& target = context.target;
  if (!target.target || target.status != "tracking" || target.t_s <= last_sighting_s_) return;
  last_sighting_s_ = target.t_s;
  follower_.observe(geometry::transform_point(context.pose, *target.target), target.t_s);
}

}  // namespace mobot::server
