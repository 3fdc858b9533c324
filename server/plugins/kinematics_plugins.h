#pragma once

#include "core/kinematics/kinematic_model.h"
#include "server/plugins/registry.h"

namespace mobot::server {

// kinematics.differential: no options; the wheel geometry is the robot's, the limits the config's.
Registry<kinematics::KinematicModel>::Maker differential_plugin(const YAML::Node& section,
                                                                const PluginContext& context);

}  // namespace mobot::server
