#pragma once

#include "core/control/velocity_limits.h"
#include "core/msgs/twist.h"

namespace mobot::control {

// Ramps the output toward the mux's command within the acceleration limits, so a step command does
// not slip the wheels or tip the robot. A stop (zero target) decelerates at the same limits.
class VelocitySmoother {
 public:
  explicit VelocitySmoother(const VelocityLimits& limits) : limits_(limits) {}

  const msgs::Twist& step(const msgs::Twist& target, double dt_s);
  // Stops at once (e-stop, collision): the caller has decided to ignore the acceleration limits.
  void halt() { current_ = {}; }
  const msgs::Twist& current() const { return current_; }

 private:
  VelocityLimits limits_;
  msgs::Twist current_;
};

}  // namespace mobot::control
