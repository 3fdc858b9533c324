#pragma once

#include "core/geometry/pose2d.h"
#include "core/msgs/twist.h"

namespace mobot::msgs {

// Dead-reckoned pose of the base in the odom frame and its body velocity.
struct Odometry {
  double stamp_s = 0.0;
  geometry::Pose2D pose;
  Twist twist;
};

}  // namespace mobot::msgs
