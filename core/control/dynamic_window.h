#pragma once

#include "core/msgs/twist.h"

namespace mobot::control {

// Speed and acceleration limits of a local planner that may only command what the base can reach
// by the next control tick (dwa_local_planner's limits). The defaults are the Dashgo thesis's DWA
// configuration (docs/algorithms.md C5).
struct DynamicLimits {
  double max_linear_mps = 0.3;
  double max_angular_radps = 1.0;
  // A turn on the spot runs at least this fast once the acceleration allows (min_rot_vel): a
  // differential base's wheels stall below it.
  double min_in_place_angular_radps = 0.4;
  double linear_accel_mps2 = 1.5;
  double angular_accel_radps2 = 2.0;
  // One control period: the window is what the accelerations reach in it (sim_period). The
  // server's 50 Hz tick.
  double control_period_s = 0.02;
};

// Positive and finite limits, a minimum in-place rate within [0, max_angular_radps].
bool valid(const DynamicLimits& limits);

// The velocities reachable from `measured` within one control period, forward only: linear in
// [max(0, v - a dt), min(v_max, v + a dt)], angular likewise within +-w_max. A measured velocity
// beyond a limit gives the window at that limit.
struct DynamicWindow {
  double min_linear_mps = 0.0;
  double max_linear_mps = 0.0;
  double min_angular_radps = 0.0;
  double max_angular_radps = 0.0;

  msgs::Twist clamp(const msgs::Twist& command) const;
  bool contains(const msgs::Twist& command, double slack = 1e-9) const;
};

DynamicWindow reachable_window(const DynamicLimits& limits, const msgs::Twist& measured);

}  // namespace mobot::control
