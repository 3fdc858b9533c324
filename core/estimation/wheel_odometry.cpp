#include "core/estimation/wheel_odometry.h"

#include <cmath>
#include <numbers>

#include "core/kinematics/diff_drive.h"

namespace mobot::estimation {

WheelOdometry::WheelOdometry(const OdometryParams& params, geometry::Pose2D start)
    : params_(params) {
  odometry_.pose = start;
}

const msgs::Odometry& WheelOdometry::update(const msgs::WheelEncoders& encoders) {
  if (!last_) {
    last_ = encoders;
    odometry_.stamp_s = encoders.stamp_s;
    last_travel_ = {};
    return odometry_;
  }
  const double metres_per_tick = 2.0 * std::numbers::pi / params_.ticks_per_wheel_rev;
  const double left_m = static_cast<double>(encoders.left_ticks - last_->left_ticks) *
                        metres_per_tick * params_.left_wheel_radius_m;
  const double right_m = static_cast<double>(encoders.right_ticks - last_->right_ticks) *
                         metres_per_tick * params_.right_wheel_radius_m;
  const double dt_s = encoders.stamp_s - last_->stamp_s;

  odometry_.pose =
      kinematics::integrate_wheel_travel(odometry_.pose, left_m, right_m, params_.track_m);
  if (dt_s > 0.0) {
    odometry_.twist =
        kinematics::twist_from_wheels({left_m / dt_s, right_m / dt_s}, params_.track_m);
  }
  odometry_.stamp_s = encoders.stamp_s;
  travelled_m_ += std::abs((left_m + right_m) / 2.0);
  last_travel_ = {left_m, right_m};
  last_ = encoders;
  return odometry_;
}

void WheelOdometry::reset(geometry::Pose2D pose) {
  odometry_.pose = pose;
  odometry_.twist = {};
}

}  // namespace mobot::estimation
