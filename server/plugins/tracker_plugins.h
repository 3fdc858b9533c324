#pragma once

#include "core/control/path_tracker.h"
#include "server/plugins/registry.h"

namespace mobot::server {

// controllers.lyapunov: the WaypointFollower's options; tolerances and speed caps default to the
// navigation section and the robot's limits.
Registry<control::PathTracker>::Maker lyapunov_plugin(const YAML::Node& section,
                                                      const PluginContext& context);

// controllers.dwa: the DwaTracker's options (docs/algorithms.md C5). Speeds and accelerations
// default to the Dashgo thesis's DWA values capped by the robot's limits (and the navigation
// cruise cap), and may not exceed them; tolerances come from the navigation section.
Registry<control::PathTracker>::Maker dwa_plugin(const YAML::Node& section,
                                                 const PluginContext& context);

// controllers.vfh: the VfhTracker's options, with the same speed defaults and caps as dwa.
Registry<control::PathTracker>::Maker vfh_plugin(const YAML::Node& section,
                                                 const PluginContext& context);

// controllers.pure_pursuit (docs/algorithms.md C3): look-ahead, speeds, align_heading (default on
// a base that turns on the spot).
Registry<control::PathTracker>::Maker pure_pursuit_plugin(const YAML::Node& section,
                                                          const PluginContext& context);

}  // namespace mobot::server
