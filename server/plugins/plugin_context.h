#pragma once

#include "core/control/velocity_limits.h"
#include "core/kinematics/robot_geometry.h"
#include "server/config.h"

namespace mobot::server {

// What every plugin may take its defaults from: the robot it runs on and the config's shared
// sections (limits, navigation tolerances), so no tuning constant lives in the wiring.
struct PluginContext {
  kinematics::RobotGeometry geometry;
  control::VelocityLimits limits;
  NavigationSection navigation;
  double control_period_s = 0.02;  // one tick of the control loop: 1 / robot.control_rate_hz
  // The base's tightest turn (KinematicModel::min_turning_radius_m); 0 when it turns on the spot.
  double min_turning_radius_m = 0.0;
};

inline PluginContext plugin_context(const Config& config,
                                    const kinematics::RobotGeometry& geometry) {
  return {geometry, config.robot.limits, config.navigation, 1.0 / config.robot.control_rate_hz};
}

}  // namespace mobot::server
