#include "core/control/target_follower.h"

#include <algorithm>
#include <cmath>

namespace mobot::control {
namespace {

// How fast the prediction may be off: a walking target's change of speed over a second.
constexpr double kDriftAllowance_mps = 0.5;
// Sightings closer together than this correct the velocity as if this far apart.
constexpr double kMinStep_s = 0.02;

}  // namespace

bool TargetFollower::observe(const geometry::Point2D& position, double stamp_s) {
  if (!std::isfinite(position.x) || !std::isfinite(position.y) || !std::isfinite(stamp_s)) {
    return false;
  }
  if (!last_) {
    last_ = Sighting{position, stamp_s};
    return true;
  }
  const double dt_s = stamp_s - last_->stamp_s;
  if (!(dt_s > 0.0)) return false;
  const geometry::Point2D expected = *predicted(stamp_s);
  const double miss_x = position.x - expected.x;
  const double miss_y = position.y - expected.y;
  const double gate_m =
      options_.gate_m + kDriftAllowance_mps * std::min(dt_s, options_.max_extrapolation_s);
  if (std::hypot(miss_x, miss_y) > gate_m) {
    if (++outliers_in_row_ < options_.outliers_to_accept) return false;
    // The target really is there: start its track afresh from this sighting.
    outliers_in_row_ = 0;
    velocity_ = {};
    last_ = Sighting{position, stamp_s};
    return true;
  }
  outliers_in_row_ = 0;
  last_ = Sighting{{expected.x + options_.alpha * miss_x, expected.y + options_.alpha * miss_y},
                   stamp_s};
  const double gain = options_.beta / std::max(dt_s, kMinStep_s);
  velocity_.x += gain * miss_x;
  velocity_.y += gain * miss_y;
  return true;
}

void TargetFollower::reset() {
  last_.reset();
  velocity_ = {};
  outliers_in_row_ = 0;
}

std::optional<geometry::Point2D> TargetFollower::predicted(double now_s) const {
  if (!last_) return std::nullopt;
  const double dt_s = std::clamp(now_s - last_->stamp_s, 0.0, options_.max_extrapolation_s);
  return geometry::Point2D{last_->position.x + velocity_.x * dt_s,
                           last_->position.y + velocity_.y * dt_s};
}

msgs::Twist TargetFollower::command(const geometry::Pose2D& pose, double distance_m,
                                    double now_s) const {
  const std::optional<geometry::Point2D> target = predicted(now_s);
  if (!target || !geometry::is_finite(pose)) return {};
  const double dx = target->x - pose.x;
  const double dy = target->y - pose.y;
  const double range_m = std::hypot(dx, dy);
  if (range_m < 1e-6) return {};
  const double bearing_rad = geometry::wrap_angle(std::atan2(dy, dx) - pose.theta);
  // The target's velocity along and across the line of sight.
  const double ux = dx / range_m;
  const double uy = dy / range_m;
  const bool extrapolating = now_s - last_->stamp_s <= options_.max_extrapolation_s;
  const double radial_mps = extrapolating ? velocity_.x * ux + velocity_.y * uy : 0.0;
  const double tangential_mps = extrapolating ? -velocity_.x * uy + velocity_.y * ux : 0.0;
  msgs::Twist out;
  out.angular_radps =
      std::clamp(options_.bearing_gain * bearing_rad + tangential_mps / range_m,
                 -options_.max_angular_radps, options_.max_angular_radps);
  if (std::abs(bearing_rad) < options_.turn_first_rad) {
    // Driving along the heading closes the distance by v cos(bearing).
    const double closing_mps =
        options_.distance_gain * (range_m - distance_m) + radial_mps;
    out.linear_mps = std::clamp(closing_mps / std::cos(bearing_rad), -options_.max_linear_mps,
                                options_.max_linear_mps);
  }
  return out;
}

}  // namespace mobot::control
