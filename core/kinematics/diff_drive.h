#pragma once

#include "core/geometry/pose2d.h"
#include "core/msgs/twist.h"

namespace mobot::kinematics {

struct WheelSpeeds {
  double left_mps = 0.0;
  double right_mps = 0.0;
};

msgs::Twist twist_from_wheels(const WheelSpeeds& wheels, double track_m);
WheelSpeeds wheels_from_twist(const msgs::Twist& twist, double track_m);

// docs/algorithms.md E1: advances a pose by the distances each wheel rolled, using the mid-step
// heading (exact for straight lines, second-order accurate on arcs).
geometry::Pose2D integrate_wheel_travel(const geometry::Pose2D& pose, double left_travel_m,
                                        double right_travel_m, double track_m);

}  // namespace mobot::kinematics
