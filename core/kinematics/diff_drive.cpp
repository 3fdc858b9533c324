#include "core/kinematics/diff_drive.h"

#include <cmath>

namespace mobot::kinematics {

msgs::Twist twist_from_wheels(const WheelSpeeds& wheels, double track_m) {
  return {(wheels.right_mps + wheels.left_mps) / 2.0,
          (wheels.right_mps - wheels.left_mps) / track_m};
}

WheelSpeeds wheels_from_twist(const msgs::Twist& twist, double track_m) {
  const double half_track_m = track_m / 2.0;
  return {twist.linear_mps - twist.angular_radps * half_track_m,
          twist.linear_mps + twist.angular_radps * half_track_m};
}

geometry::Pose2D integrate_wheel_travel(const geometry::Pose2D& pose, double left_travel_m,
                                        double right_travel_m, double track_m) {
  const double ds = (right_travel_m + left_travel_m) / 2.0;
  const double dtheta = (right_travel_m - left_travel_m) / track_m;
  const double mid_heading = pose.theta + dtheta / 2.0;
  return {pose.x + ds * std::cos(mid_heading), pose.y + ds * std::sin(mid_heading),
          geometry::wrap_angle(pose.theta + dtheta)};
}

}  // namespace mobot::kinematics
