#pragma once

#include "core/kinematics/kinematic_model.h"
#include "server/plugins/registry.h"

namespace mobot::server {

// kinematics.differential: no options; the wheel geometry is the robot's, the limits the config's.
Registry<kinematics::KinematicModel>::Maker differential_plugin(const YAML::Node& section,
                                                                const PluginContext& context);

// kinematics.tricycle_t1 / tricycle_t2 (docs/algorithms.md R3): saturate (default true),
// max_steer_rad (default pi/4), wheelbase_m (default the robot's, else R3's sqrt(3.4) m); the
// speed limits are the config's.
Registry<kinematics::KinematicModel>::Maker tricycle_t1_plugin(const YAML::Node& section,
                                                               const PluginContext& context);
Registry<kinematics::KinematicModel>::Maker tricycle_t2_plugin(const YAML::Node& section,
                                                               const PluginContext& context);

}  // namespace mobot::server
