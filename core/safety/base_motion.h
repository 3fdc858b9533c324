#pragma once

#include <algorithm>
#include <cmath>

#include "core/msgs/twist.h"

namespace mobot::safety {

// What the base was last told to do and what its odometry says it does. A safety rule looks at
// both: the command leads the measurement by the drive's latency and ramp, the measurement still
// shows motion after a command has dropped to zero.
struct BaseMotion {
  msgs::Twist commanded;
  msgs::Twist measured;

  // The larger forward speed of the two (m/s, 0 when neither goes forward). A non-finite
  // component counts as not moving.
  double forward_mps() const {
    return std::max(
        {0.0, finite_or_zero(commanded.linear_mps), finite_or_zero(measured.linear_mps)});
  }
  // The larger reversing speed of the two, as a positive number (0 when neither reverses).
  double reverse_mps() const {
    return std::max(
        {0.0, -finite_or_zero(commanded.linear_mps), -finite_or_zero(measured.linear_mps)});
  }

 private:
  static double finite_or_zero(double value) { return std::isfinite(value) ? value : 0.0; }
};

}  // namespace mobot::safety
