#pragma once

#include "core/control/path_tracker.h"
#include "core/estimation/pose_estimator.h"
#include "core/kinematics/kinematic_model.h"
#include "core/planning/global_planner.h"
#include "server/config.h"
#include "server/plugins/registry.h"

namespace mobot::server {

// Every kind of plugin the runtime chooses by name, with the config section its options live in.
struct Plugins {
  Registry<planning::GlobalPlanner> planners{"planner", "planners"};
  Registry<control::PathTracker> trackers{"controller", "controllers"};
  Registry<estimation::PoseEstimator> estimators{"estimator", "estimators"};
  Registry<kinematics::KinematicModel> kinematics{"kinematic model", "kinematics"};
};

// The built-in plugins: the one place each registers, one line each.
Plugins builtin_plugins();

// The plugins with the options the config gives them, ready to make instances.
struct ConfiguredPlugins {
  PluginSet<planning::GlobalPlanner> planners;
  PluginSet<control::PathTracker> trackers;
  PluginSet<estimation::PoseEstimator> estimators;
  PluginSet<kinematics::KinematicModel> kinematics;
};

// Parses every plugin's section and checks the names the config selects (robot.kinematics,
// localization.method). Throws ConfigError naming the key.
ConfiguredPlugins configure_plugins(const Plugins& plugins, const Config& config,
                                    const kinematics::RobotGeometry& geometry);

}  // namespace mobot::server
