#pragma once

#include "core/control/dynamic_window.h"
#include "core/msgs/twist.h"

namespace mobot::control {

// The final approach of the local planners (base_local_planner's LatchedStopRotateController):
// once the robot is within the position tolerance it brakes to a stop, then turns on the spot to
// the goal heading at sqrt(2 a |error|) (so it can stop in time), at least the minimum in-place
// rate and at most the maximum, always inside the dynamic window. It has arrived when the heading
// is within tolerance and the stop is one period of deceleration away, so the zero command that
// follows respects the acceleration limits.
struct StopAndRotate {
  msgs::Twist command;
  bool arrived = false;
};

// heading_error_rad is the robot's heading minus the goal heading, wrapped.
StopAndRotate stop_and_rotate(const DynamicLimits& limits, const msgs::Twist& measured,
                              double heading_error_rad, double tolerance_rad);

}  // namespace mobot::control
