#pragma once

#include "core/control/path_tracker.h"
#include "server/plugins/registry.h"

namespace mobot::server {

// controllers.lyapunov: the WaypointFollower's options; tolerances and speed caps default to the
// navigation section and the robot's limits.
Registry<control::PathTracker>::Maker lyapunov_plugin(const YAML::Node& section,
                                                      const PluginContext& context);

}  // namespace mobot::server
