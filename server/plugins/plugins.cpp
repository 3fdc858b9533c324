#include "server/plugins/plugins.h"

#include "server/plugins/estimator_plugins.h"
#include "server/plugins/kinematics_plugins.h"
#include "server/plugins/planner_plugins.h"
#include "server/plugins/tracker_plugins.h"

namespace mobot::server {
namespace {

template <class Interface>
void require_known(const Registry<Interface>& registry, const std::string& name,
                   const std::string& key) {
  if (!registry.contains(name)) throw registry.unknown(name, key);
}

}  // namespace

Plugins builtin_plugins() {
  Plugins plugins;
  plugins.planners.add("astar", astar_plugin);
  plugins.planners.add("voronoi", voronoi_plugin);
  plugins.planners.add("hybrid_astar", hybrid_astar_plugin);
  plugins.trackers.add("lyapunov", lyapunov_plugin);
  plugins.trackers.add("dwa", dwa_plugin);
  plugins.trackers.add("vfh", vfh_plugin);
  plugins.trackers.add("pure_pursuit", pure_pursuit_plugin);
  plugins.estimators.add("ekf", ekf_plugin);
  plugins.estimators.add("odometry", odometry_plugin);
  plugins.estimators.add("particle_filter", particle_filter_plugin);
  plugins.estimators.add("landmark_ekf", landmark_ekf_plugin);
  plugins.kinematics.add("differential", differential_plugin);
  plugins.kinematics.add("tricycle_t1", tricycle_t1_plugin);
  plugins.kinematics.add("tricycle_t2", tricycle_t2_plugin);
  return plugins;
}

ConfiguredPlugins configure_plugins(const Plugins& plugins, const Config& config,
                                    const kinematics::RobotGeometry& geometry) {
  require_known(plugins.estimators, config.localization.method, "localization.method");
  require_known(plugins.kinematics, config.robot.kinematics, "robot.kinematics");
  require_known(plugins.trackers, config.navigation.controller, "navigation.controller");
  require_known(plugins.planners, config.navigation.planner, "navigation.planner");
  PluginContext context = plugin_context(config, geometry);
  const YAML::Node& root = config.document;
  PluginSet<kinematics::KinematicModel> kinematics{plugins.kinematics, root, context};
  // The others may take the base's turning limit into account (trackers, the path's corners).
  // Checking a config alone (no robot yet: no wheel geometry) makes no model.
  if (geometry.wheel_radius_m > 0.0) {
    context.min_turning_radius_m = kinematics.make(config.robot.kinematics)->min_turning_radius_m();
  }
  return {{plugins.planners, root, context},
          {plugins.trackers, root, context},
          {plugins.estimators, root, context},
          std::move(kinematics)};
}

}  // namespace mobot::server
