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
  plugins.trackers.add("lyapunov", lyapunov_plugin);
  plugins.trackers.add("dwa", dwa_plugin);
  plugins.trackers.add("vfh", vfh_plugin);
  plugins.estimators.add("ekf", ekf_plugin);
  plugins.estimators.add("odometry", odometry_plugin);
  plugins.estimators.add("particle_filter", particle_filter_plugin);
  plugins.kinematics.add("differential", differential_plugin);
  return plugins;
}

ConfiguredPlugins configure_plugins(const Plugins& plugins, const Config& config,
                                    const kinematics::RobotGeometry& geometry) {
  require_known(plugins.estimators, config.localization.method, "localization.method");
  require_known(plugins.kinematics, config.robot.kinematics, "robot.kinematics");
  const PluginContext context = plugin_context(config, geometry);
  const YAML::Node& root = config.document;
  return {{plugins.planners, root, context},
          {plugins.trackers, root, context},
          {plugins.estimators, root, context},
          {plugins.kinematics, root, context}};
}

}  // namespace mobot::server
