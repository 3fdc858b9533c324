#include "core/estimation/wheel_odometry.h"

#include <cmath>
#include <numbers>

#include "core/kinematics/diff_drive.h"

namespace mobot::estimation {

WheelOdometry::WheelOdometry(const OdometryParams& params, geometry::Pose2D start)
    : params_(params) {
  odometry_.pose = start;
}

WheelTravel WheelOdometry::travel(const msgs::WheelEncoders& from,
                                  const msgs::WheelEncoders& to) const {
  const double metres_per_tick = 2.0 * std::numbers::pi / params_.ticks_per_wheel_rev;
  return {static_cast<double>(to.left_ticks - from.left_ticks) * metres_per_tick *
              params_.left_wheel_radius_m,
          static_cast<double>(to.right_ticks - from.right_ticks) * metres_per_tick *
              params_.right_wheel_radius_m};
}

const msgs::Odometry& WheelOdometry::update(const msgs::WheelEncoders& encoders) {
  if (recent_.empty()) {
    recent_.assign(1, encoders);
    odometry_.stamp_s = encoders.stamp_s;
    last_travel_ = {};
    return odometry_;
  }
  const WheelTravel step = travel(recent_.back(), encoders);
  const double dt_s = encoders.stamp_s - recent_.back().stamp_s;
  odometry_.pose = kinematics::integrate_wheel_travel(odometry_.pose, step.left_m, step.right_m,
                                                     params_.track_m);
  if (dt_s > 0.0) {
    recent_.push_back(encoders);
    // (Written so that a NaN window keeps only the last step rather than every reading.)
    while (recent_.size() > 2 &&
           !(encoders.stamp_s - recent_[1].stamp_s < params_.velocity_window_s)) {
      recent_.pop_front();
    }
    const WheelTravel window = travel(recent_.front(), encoders);
    const double span_s = encoders.stamp_s - recent_.front().stamp_s;
    odometry_.twist = kinematics::twist_from_wheels(
        {window.left_m / span_s, window.right_m / span_s}, params_.track_m);
  } else {
    recent_.assign(1, encoders);  // a clock that stepped back restarts the window
  }
  odometry_.stamp_s = encoders.stamp_s;
  travelled_m_ += std::abs((step.left_m + step.right_m) / 2.0);
  last_travel_ = step;
  return odometry_;
}

void WheelOdometry::reset(geometry::Pose2D pose) {
  odometry_.pose = pose;
  odometry_.twist = {};
}

}  // namespace mobot::estimation
