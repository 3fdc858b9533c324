#pragma once

#include "core/msgs/twist.h"

namespace mobot::control {

struct VelocityLimits {
  double max_linear_mps = 1.3;
  double max_angular_radps = 2.0;
  double max_linear_accel_mps2 = 1.0;
  double max_angular_accel_radps2 = 3.0;
};

// Clamps each component to the speed limits (not the acceleration limits).
msgs::Twist clamp_to_limits(const msgs::Twist& command, const VelocityLimits& limits);

}  // namespace mobot::control
